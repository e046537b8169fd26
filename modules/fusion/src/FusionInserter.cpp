// The SurfelFrameInserter behind CSurfelMap::insertObservation(): fuses a frame at a known pose
// (II-A preprocessing of core, then SurfelFusion), registered when this library is loaded.

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/initializer.h>

#include "rasm/core/FrameProcessing.h"
#include "rasm/core/Params.h"
#include "rasm/fusion/SurfelFusion.h"
#include "rasm/surfel_map/SurfelFrameInserter.h"

namespace rasm::fusion {

namespace {

class FusionFrameInserter : public maps::SurfelFrameInserter {
 public:
  explicit FusionFrameInserter(const TFusionParams& p) : m_fusion(p) {}

  void insertFrame(maps::SurfelStore& map, const RgbdFrame& frame,
                   const Eigen::Isometry3d& T_world_cam) override {
    VertexMapOptions vo;
    vo.min_depth_m = m_fusion.params().min_depth_m;
    vo.max_depth_m = m_fusion.params().max_depth_m;
    computeVertexMap(frame.depth_m, frame.intrinsics, m_vertex, vo);
    computeNormalMap(m_vertex, m_normal);
    m_fusion.fuse(map, makeFusionInput(frame, m_vertex, m_normal, T_world_cam));
  }

 private:
  SurfelFusion m_fusion;
  Image<Vec3f> m_vertex, m_normal;
};

}  // namespace

}  // namespace rasm::fusion

MRPT_INITIALIZER(rasm_fusion_register_inserter) {
  rasm::maps::setSurfelFrameInserterFactory([](const std::string& ini, const std::string& source) {
    rasm::fusion::TFusionParams p;
    mrpt::config::CConfigFileMemory cfg(ini);
    rasm::loadParamsStrict(cfg, "fusion", p, source);
    return std::unique_ptr<rasm::maps::SurfelFrameInserter>(
        new rasm::fusion::FusionFrameInserter(p));
  });
}
