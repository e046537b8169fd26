#pragma once
// floorplan.png and floorplan.svg: the map seen from above, what an operator looks at first.
//
//   up       world z when the world frame is known to be gravity-aligned (the simulator's);
//            otherwise (rawlogs, TUM, 7-Scenes, live cameras: nothing in the data says where
//            gravity is) the cameras' mean -y axis (optical y points down the image and a camera
//            is held or mounted roughly upright, if often pitched), refined to the mean normal of
//            the surfels within 45, then 20, then 10 degrees of it (floor and table tops; walls
//            never enter), and snapped to the nearest world axis when within 5 degrees of it.
//            The plan's caption says which and by how much.
//   floor    the most common height (2 cm bins, along up) of the upward-facing surfels (normal
//            within 25 degrees of up) at least 0.3 m below the cameras' median height; the 1st
//            percentile of every surfel's height when there is no such surfel.
//   cells    cell_m squares of the plane: floor (every surfel within floor_band_m of the floor),
//            furniture (the highest surfel below tall_m above it), walls and tall (higher), not
//            seen (white); surfels more than max_height_m above the floor (ceilings, lamps) are
//            left out, so the plan shows the room's walls and what stands in it.
//   overlay  a 1 m grid, the camera path (start green, end red), the exploration's goals (filled
//            when reached, crossed when not), each object's box seen from above (its oriented
//            box's 8 corners, their outline) in its class colour (surfel_map's classColour, as in
//            map_classes.ply) with "class probability" beside it, a legend (cell shades, path,
//            goals, each class shown and how many) and a scale bar.
// The SVG holds the cells as one embedded PNG and everything else as vectors, so the labels stay
// sharp in a browser or Inkscape. Both come from one list of shapes (no second drawing code).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace rasm::run {

/// One object of objects.json (its `objects`): what the floor plan and the 3-D scenes draw.
struct ObjectBox {
  int id = 0;
  std::string class_name;
  int class_id = 0;  ///< classes.json id (its colour)
  double probability = 0.0;
  Eigen::Vector3d centre_world = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes_world = Eigen::Matrix3d::Identity();  ///< box axes as columns
  Eigen::Vector3d extents_m = Eigen::Vector3d::Zero();       ///< full sizes along them
};

/// One goal of exploration.json: where the robot was sent (x, y m, yaw rad) and whether it got
/// there.
struct FloorPlanGoal {
  Eigen::Vector3d xy_yaw = Eigen::Vector3d::Zero();
  bool reached = false;
};

struct FloorPlanInput {
  std::vector<Eigen::Vector3f> points_world;   ///< surfel centres (stable ones)
  std::vector<Eigen::Vector3f> normals_world;  ///< their unit normals, same order
  std::vector<float> radii_m;                  ///< their radii (none: a point fills its cell)
  std::vector<Eigen::Isometry3d> T_world_cam;  ///< the camera path (optical frame)
  std::vector<FloorPlanGoal> goals;
  std::vector<ObjectBox> objects;
  bool world_z_up = false;  ///< the world frame is gravity-aligned (robot and simulated runs)
  std::string title;        ///< first caption line (e.g. the output folder)
};

struct FloorPlanParams {
  double cell_m = 0.02;        ///< side of a cell (enlarged so the plan fits max_size_px)
  double floor_band_m = 0.05;  ///< a cell whose surfels are all this close to the floor is floor
  double tall_m = 1.2;         ///< furniture below, walls and tall things above
  double max_height_m = 2.0;   ///< surfels higher above the floor are left out (ceilings)
  int max_size_px = 1400;      ///< the map area's larger side at most (pixels)
};

/// The plan's up direction (world frame, unit) and how it was found (the caption's words).
struct FloorPlanUp {
  Eigen::Vector3d up_world = Eigen::Vector3d::UnitZ();
  std::string how;
};
FloorPlanUp floorPlanUp(const FloorPlanInput& in);

/// The floor's height along `up` (see the header comment); NaN without any point.
double floorHeight(const FloorPlanInput& in, const Eigen::Vector3d& up_world);

struct FloorPlan {
  cv::Mat image;  ///< BGR: the map area, the legend beside it, the caption below
  std::string svg;
  FloorPlanUp up;
  double floor_height_m = 0.0;  ///< along up
  double metres_per_px = 0.0;
  Eigen::Matrix3d R_plan_world = Eigen::Matrix3d::Identity();  ///< rows: plan x, plan y, up
  Eigen::Vector2d origin_px = Eigen::Vector2d::Zero();         ///< pixel of plan (0, 0)
  int classes_shown = 0;

  /// The pixel (x right, y down) of a world point in `image` (the same in the SVG).
  Eigen::Vector2d pixelOf(const Eigen::Vector3d& p_world) const;
};

/// Draws the plan; an empty image when `in` has no point and no camera pose.
FloorPlan drawFloorPlan(const FloorPlanInput& in, const FloorPlanParams& params = {});

/// objects.json's `objects` (entries without an oriented_box are left out); exploration.json's
/// `goals` (reached = outcome "reached"). Empty for a document without them.
std::vector<ObjectBox> objectBoxes(const nlohmann::json& objects_json);
std::vector<FloorPlanGoal> floorPlanGoals(const nlohmann::json& exploration_json);

}  // namespace rasm::run
