#include "rasm/pipeline/stages/FusionStages.h"

namespace rasm::pipeline {

namespace {
fusion::FusionInput fusionInput(const FrameContext& ctx) {
  fusion::FusionInput in =
      fusion::makeFusionInput(*ctx.frame, ctx.pyramid[0].vertex, ctx.pyramid[0].normal,
                              ctx.result.T_world_cam, &ctx.labels);
  in.timestamp_s = ctx.t_rel_s;
  return in;
}
}  // namespace

void FusionStage::configure(const TMapperParams& /*mapper*/) {
  m_fusion->setParams(m_params);
}

void FusionStage::process(FrameContext& ctx, maps::CSurfelMap& map) {
  if (!ctx.result.fusable()) {
    ctx.result.fusion.map_size = map.size();  // frames.csv `surfels`: the map, not 0
    return;
  }
  const fusion::FusionInput in = fusionInput(ctx);
  fusion::FusionStats& st = ctx.result.fusion;
  m_fusion->updateSurfels(map.store(), in, st);
  m_fusion->addSurfels(map.store(), in, st);
  m_fusion->cleanup(map.store(), in, st);
  ctx.index_map = {};  // the cleanup moved surfels
  ctx.result.fused = true;
}

void FusionStage::csvColumns(std::vector<std::string>& c) const {
  c.insert(c.end(), {"valid_pixels", "associated", "added", "removed_unstable", "removed_carved",
                     "merged", "surfels"});
}

void FusionStage::csvValues(const FrameContext& ctx, CsvRow& row) const {
  const fusion::FusionStats& f = ctx.result.fusion;
  row.add(f.valid_pixels)
      .add(f.associated)
      .add(f.added)
      .add(f.removed_unstable)
      .add(f.removed_carved)
      .add(f.merged);
  row.add(f.map_size);
}

void IndexMapStage::process(FrameContext& ctx, maps::CSurfelMap& map) {
  if (!ctx.result.fusable()) return;
  ctx.index_map = m_fusion->renderIndexMap(map.store(), fusionInput(ctx), ctx.result.fusion);
}

}  // namespace rasm::pipeline
