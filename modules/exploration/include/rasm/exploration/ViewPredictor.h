#pragma once
// What one candidate view would gain (V): the surfel map is rendered once at the candidate camera
// pose (SurfelRenderer splats, at the reduced predict_width x predict_height), its depth map is
// cast through the occupancy octree for dH (V-A) and its surfel index map gives dIC (V-B).

#include <Eigen/Geometry>

#include "rasm/core/CameraIntrinsics.h"
#include "rasm/exploration/ObjectInformation.h"
#include "rasm/exploration/OccupancyOctree.h"
#include "rasm/exploration/TExplorationParams.h"
#include "rasm/surfel_map/SurfelRenderer.h"
#include "rasm/surfel_map/SurfelStore.h"

namespace rasm::exploration {

/// The map the predictions render: `full` itself when it holds at most
/// params.predict_max_surfels alive surfels (or the limit is 0), else `thinned`, filled with
/// every k-th surfel of it (SurfelStore::copyThinnedFrom, radius x sqrt(k)) and indexed.
const maps::SurfelStore& predictionStore(const maps::SurfelStore& full,
                                         const TExplorationParams& params,
                                         maps::SurfelStore& thinned);

struct ViewPrediction {
  double entropy_reduction = 0.0;  ///< dH (nats) of the workspace
  InformationGain information;     ///< dIC
};

class ViewPredictor {
 public:
  ViewPredictor(const TExplorationParams& params, const ViewInfoModel& model);

  /// dH and dIC of a view from T_world_cam (optical frame) with the camera K, rendered at the
  /// params' predict size. The store must have its spatial index (a snapshot after
  /// rebuildIndex()). Not thread safe (one renderer and buffers per predictor).
  ViewPrediction predict(const maps::SurfelStore& store, const OccupancyOctree& octree,
                         const Eigen::Isometry3d& T_world_cam, const CameraIntrinsics& K);

  /// The maps of the last predict() (depth and index).
  const maps::RenderedMaps& lastRender() const { return m_maps; }

 private:
  TExplorationParams m_params;
  ViewInfoModel m_model;
  maps::SurfelRenderer m_renderer;
  maps::RenderOptions m_options;
  maps::RenderedMaps m_maps;
  ViewCells m_cells;
};

}  // namespace rasm::exploration
