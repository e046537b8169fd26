#pragma once
// The 3-D scenes of a run (map.3Dscene, map_segments.3Dscene, map_classes.3Dscene and `rasm
// view`): the surfel map (MapExport.h surfelScene) with what the run did drawn over it, and a
// camera that starts on the map.
//
// Objects, by name (COpenGLScene::getByName):
//   "trajectory"       the estimated camera path, an orange line strip with a dot per pose
//   "groundtruth"      the ground-truth camera path, a green line strip (when the run has it)
//   "camera"           the last estimated camera: its frustum (white; MRPT's +X forward), axes
//   "candidate_views"  exploration views as arrows from the camera centre along its optical axis
//                      (the paper's Fig. 6): the last plan's candidates coloured by information
//                      gain (jet: blue low, red high; grey = unreachable), the goals driven to
//                      in magenta and thicker
//   "objects"          each object of objects.json: its oriented box as a wireframe in its class
//                      colour (labelColour, as map_classes.ply at probability 1) and a text label
//                      "class probability" above it
// The main viewport's camera points at the map's centre from a distance that shows it whole, and
// the scene is marked followCamera, so SceneViewer3D and CDisplayWindow3D start there.

#include <Eigen/Geometry>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "rasm/autonomy/SceneView.h"
#include "rasm/core/CameraIntrinsics.h"
#include "rasm/io/Trajectory.h"
#include "rasm/run/FloorPlan.h"
#include "rasm/surfel_map/MapExport.h"

namespace mrpt::opengl {
class COpenGLScene;
}

namespace rasm::run {

/// What is drawn over the map.
struct RunOverlay {
  io::Trajectory estimate, groundtruth;  ///< T_world_cam (optical) per frame
  CameraIntrinsics K;                    ///< of the last frame: the frustum's field of view
  std::vector<autonomy::SceneView> views;
  std::vector<ObjectBox> objects;  ///< objects.json's objects
};

/// From a run folder: trajectory.txt (required: InputError naming it otherwise), groundtruth.txt,
/// exploration.json's "candidate_views" and objects.json's objects when present. K keeps its
/// default (the folder does not record it).
RunOverlay readRunOverlay(const std::string& dir);

/// Inserts the named objects above (those with data) into the main viewport of `scene`.
void addRunOverlay(mrpt::opengl::COpenGLScene& scene, const RunOverlay& overlay);

/// The map's extent: per axis the 1st to 99th percentile of the alive surfels (a few stray ones do
/// not move the camera away), grown to hold the estimated path; empty box when both are empty.
Eigen::AlignedBox3d sceneBounds(const maps::SurfelStore& map, const RunOverlay& overlay);

/// Points the main viewport's camera at the centre of `box`, looking down at 50 degrees from 1.7
/// times its larger horizontal extent (it fills most of the view), and sets followCamera so that
/// viewers take it. An empty box leaves the camera alone.
void pointCameraAt(mrpt::opengl::COpenGLScene& scene, const Eigen::AlignedBox3d& box);

/// surfelScene(map, vis) + addRunOverlay + pointCameraAt(sceneBounds): a .3Dscene of the run.
std::shared_ptr<mrpt::opengl::COpenGLScene> runScene(const maps::SurfelStore& map,
                                                     const maps::SurfelVisualOptions& vis,
                                                     const RunOverlay& overlay);

}  // namespace rasm::run
