#include "rasm/exploration/ViewPredictor.h"

#include <cmath>

namespace rasm::exploration {

const maps::SurfelStore& predictionStore(const maps::SurfelStore& full,
                                         const TExplorationParams& params,
                                         maps::SurfelStore& thinned) {
  if (params.predict_max_surfels <= 0 || full.size() <= params.predict_max_surfels) return full;
  const maps::SurfelArrays a = full.arrays();
  int alive = 0;
  for (int i = 0; i < a.size; ++i) alive += a.alive(i);
  if (alive <= params.predict_max_surfels) return full;
  const int stride = (alive + params.predict_max_surfels - 1) / params.predict_max_surfels;
  thinned.copyThinnedFrom(full, stride, std::sqrt(float(stride)));
  thinned.rebuildIndex();
  return thinned;
}

ViewPredictor::ViewPredictor(const TExplorationParams& params, const ViewInfoModel& model)
    : m_params(params), m_model(model) {
  m_params.validate();
  m_options.min_depth_m = float(m_params.min_depth_m);
  m_options.max_depth_m = float(m_params.max_range_m);
  // V-B: occluded and back-facing surfels gain nothing (fusion would not update them).
  m_options.cull_back_faces = true;
  m_options.splat = true;
  m_options.outputs = maps::kRenderDepth;
}

ViewPrediction ViewPredictor::predict(const maps::SurfelStore& store, const OccupancyOctree& octree,
                                      const Eigen::Isometry3d& T_world_cam,
                                      const CameraIntrinsics& K) {
  const CameraIntrinsics Kp = K.resized(m_params.predict_width, m_params.predict_height);
  m_renderer.render(store, T_world_cam, Kp, m_options, m_maps);
  ViewPrediction p;
  // V-A: the predicted depth cast through the octree (empty pixels: unknown, seen through).
  p.entropy_reduction = octree.predictedEntropyReduction(T_world_cam, Kp, m_maps.depth_m, m_cells);
  p.information = predictedInformationGain(store, m_maps.index, T_world_cam, m_model,
                                           float(m_params.ic_weight_floor));
  return p;
}

}  // namespace rasm::exploration
