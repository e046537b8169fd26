#pragma once
// rasm::tracking::MapPartSource: the map, or a part of it, rendered as the tracker sees it, for
// the tracking policies that register a frame against something other than the tracking model:
// loop closure (LoopCloser: the inactive and the active map) and relocalisation
// (RelocalisationPolicy: the whole map at a candidate pose). The tracking stage implements it
// with the render of its tracking model, so a part is valid until the next render.

#include <Eigen/Geometry>

#include "rasm/surfel_map/SurfelRenderer.h"
#include "rasm/tracking/IcpTracker.h"

namespace rasm::tracking {

/// A part of the map as the tracker sees it, rendered by the caller.
struct MapPart {
  ModelMaps model;
  int valid_pixels = 0;  ///< model pixels a surfel drew
};

/// Renders the map, or the part of it a time filter selects, as the tracking model is rendered.
class MapPartSource {
 public:
  virtual ~MapPartSource() = default;
  /// The map's surfels that pass `time_filter` (created_before_s / created_after_s; a default
  /// RenderOptions: every surfel) rendered at T_world_cam; with the colour when `with_colour`.
  /// Valid until the next call.
  virtual MapPart render(const Eigen::Isometry3d& T_world_cam, bool with_colour,
                         const maps::RenderOptions& time_filter) = 0;
  /// Median creation time (absolute s) of the surfels the last render drew.
  virtual double medianInitTimeOfLastRender() const = 0;
};

}  // namespace rasm::tracking
