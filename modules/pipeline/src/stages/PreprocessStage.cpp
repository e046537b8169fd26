#include "rasm/pipeline/stages/PreprocessStage.h"

namespace rasm::pipeline {

void PreprocessStage::process(FrameContext& ctx, maps::CSurfelMap& /*map*/) {
  const RgbdFrame& frame = *ctx.frame;
  const TMapperParams& p = m_params;
  const Image<float>* depth = &frame.depth_m;
  if (p.bilateral_filter) {
    bilateralFilterDepth(frame.depth_m, m_depth_filtered, 2, float(p.bilateral_sigma_space_px),
                         float(p.bilateral_sigma_depth_m));
    depth = &m_depth_filtered;
  }
  VertexMapOptions vo;
  vo.min_depth_m = float(p.min_depth_m);
  vo.max_depth_m = float(p.max_depth_m);
  ctx.pyramid.resize(p.pyramid_levels);
  for (int l = 0; l < p.pyramid_levels; ++l) {
    FrameLevel& L = ctx.pyramid[l];
    L.K = frame.intrinsics.level(l);
    if (l == 0)
      L.depth_m = *depth;
    else
      downsampleDepth(ctx.pyramid[l - 1].depth_m, L.depth_m);
    computeVertexMap(L.depth_m, L.K, L.vertex, vo);
    computeNormalMap(L.vertex, L.normal, float(p.normal_max_jump_rel));
  }
}

}  // namespace rasm::pipeline
