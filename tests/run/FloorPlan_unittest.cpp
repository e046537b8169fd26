// floorplan.png / floorplan.svg (FloorPlan.h): a 4 x 3 m room with a wall, a ceiling and a table,
// a camera path through it, two goals and one object; where each thing lands on the plan follows
// from the plan's scale (metres_per_px) and the room's geometry.
#include <gtest/gtest.h>
#include <mrpt/system/string_utils.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "rasm/run/FloorPlan.h"

using namespace rasm::run;

namespace {

/// A camera at `c` looking along world +x, upright (optical y = world -z).
Eigen::Isometry3d uprightCamera(const Eigen::Vector3d& c) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = Eigen::Vector3d(0, -1, 0);
  T.linear().col(1) = Eigen::Vector3d(0, 0, -1);
  T.linear().col(2) = Eigen::Vector3d(1, 0, 0);
  T.translation() = c;
  return T;
}

void addPatch(FloorPlanInput& in, const Eigen::Vector3d& origin, const Eigen::Vector3d& u,
              const Eigen::Vector3d& v, double lu, double lv, const Eigen::Vector3d& normal) {
  for (double a = 0.0; a <= lu + 1e-9; a += 0.02)
    for (double b = 0.0; b <= lv + 1e-9; b += 0.02) {
      in.points_world.push_back((origin + a * u + b * v).cast<float>());
      in.normals_world.push_back(normal.cast<float>());
      in.radii_m.push_back(0.01f);  // 2 cm apart: discs of 1 cm radius touch
    }
}

/// The room: floor z = 0 over x 0-4, y 0-3; a wall at x = 4 up to 2.4 m; a ceiling at 2.5 m; a
/// 1 x 0.8 m table top at 0.75 m (x 1.5-2.5, y 1-1.8); the camera at 1 m along y = 0.5.
FloorPlanInput room(const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  FloorPlanInput in;
  const Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY(),
                        Z = Eigen::Vector3d::UnitZ();
  addPatch(in, {0, 0, 0}, X, Y, 4.0, 3.0, Z);
  addPatch(in, {4, 0, 0}, Y, Z, 3.0, 2.4, -X);
  addPatch(in, {0, 0, 2.5}, X, Y, 4.0, 3.0, -Z);
  addPatch(in, {1.5, 1.0, 0.75}, X, Y, 1.0, 0.8, Z);
  for (double x = 0.5; x <= 3.5 + 1e-9; x += 0.1)
    in.T_world_cam.push_back(uprightCamera({x, 0.5, 1.0}));
  in.goals = {{{3.0, 2.0, 0.0}, true}, {{1.0, 2.5, M_PI / 2}, false}};
  ObjectBox table;
  table.id = 7, table.class_name = "dining table", table.class_id = 61, table.probability = 0.87;
  table.centre_world = {2.0, 1.4, 0.375};
  table.extents_m = {1.0, 0.8, 0.75};
  in.objects = {table};
  // The same room in a frame rotated by R (hand-held data whose world is not z up).
  for (Eigen::Vector3f& p : in.points_world) p = (R * p.cast<double>()).cast<float>();
  for (Eigen::Vector3f& n : in.normals_world) n = (R * n.cast<double>()).cast<float>();
  for (Eigen::Isometry3d& T : in.T_world_cam) T = Eigen::Isometry3d(R) * T;
  for (ObjectBox& o : in.objects) o.centre_world = R * o.centre_world, o.axes_world = R;
  return in;
}

cv::Vec3b at(const FloorPlan& plan, const Eigen::Vector3d& p_world) {
  const Eigen::Vector2d px = plan.pixelOf(p_world);
  return plan.image.at<cv::Vec3b>(int(std::floor(px.y())), int(std::floor(px.x())));
}

const cv::Vec3b kFloor(232, 232, 232), kFurniture(165, 165, 165), kWall(70, 70, 70),
    kUnseen(255, 255, 255);

}  // namespace

/// `in` with every camera pitched down by `deg` about its own x axis (looking at the floor).
FloorPlanInput pitched(FloorPlanInput in, double deg) {
  for (Eigen::Isometry3d& T : in.T_world_cam)
    T.linear() = T.linear() * Eigen::AngleAxisd(-deg * M_PI / 180, Eigen::Vector3d::UnitX());
  return in;
}

TEST(FloorPlan, UpIsWorldZInTheSimulatorAndFoundFromTheMapOtherwise) {
  FloorPlanInput sim = pitched(room(), 40);
  sim.world_z_up = true;
  EXPECT_TRUE(floorPlanUp(sim).up_world.isApprox(Eigen::Vector3d::UnitZ()));
  // Without gravity: upright cameras and the floor agree on z.
  const FloorPlanUp level = floorPlanUp(room());
  EXPECT_TRUE(level.up_world.isApprox(Eigen::Vector3d::UnitZ())) << level.how;
  EXPECT_NE(level.how.find("no gravity"), std::string::npos) << level.how;
  // Cameras pitched 26 degrees down (a hand-held sweep over desks): the floor and table normals
  // still give z, 26 degrees from the cameras' own up.
  const FloorPlanUp looking_down = floorPlanUp(pitched(room(), 26));
  EXPECT_TRUE(looking_down.up_world.isApprox(Eigen::Vector3d::UnitZ())) << looking_down.how;
  EXPECT_NE(looking_down.how.find("horizontal surfaces"), std::string::npos);
  EXPECT_NE(looking_down.how.find("26.0 deg from the cameras' up"), std::string::npos)
      << looking_down.how;
  // No surfel: the cameras' up alone, 30 degrees from z, not snapped.
  FloorPlanInput bare = pitched(room(), 30);
  bare.points_world.clear(), bare.normals_world.clear();
  EXPECT_NEAR(std::acos(floorPlanUp(bare).up_world.z()) * 180 / M_PI, 30.0, 1e-6);
  // A frame whose y axis points down (the first camera's optical frame): up = world -y.
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_TRUE(floorPlanUp(pitched(room(R), 26)).up_world.isApprox(-Eigen::Vector3d::UnitY()));
}

TEST(FloorPlan, FloorIsTheCommonHeightOfUpwardSurfacesBelowTheCamera) {
  const FloorPlanInput in = room();
  // Floor points at z = 0 fall in the 2 cm bin [0, 0.02); the table top (0.75 m, upward) is
  // above the camera's 1 m minus 0.3 m and does not count, nor do the ceiling and the wall.
  EXPECT_NEAR(floorHeight(in, Eigen::Vector3d::UnitZ()), 0.0, 0.02);
  FloorPlanInput raised = in;
  for (Eigen::Vector3f& p : raised.points_world) p.z() += 0.4f;
  EXPECT_NEAR(floorHeight(raised, Eigen::Vector3d::UnitZ()), 0.4, 0.02);
}

TEST(FloorPlan, CellsShowFloorFurnitureWallsAndLeaveTheCeilingOut) {
  const FloorPlan plan = drawFloorPlan(room());
  ASSERT_FALSE(plan.image.empty());
  EXPECT_DOUBLE_EQ(plan.metres_per_px, 0.02) << "4.6 m fit 1400 px at the 2 cm default";
  // One metre is 1 / metres_per_px pixels; +x to the right, +y up the image.
  const Eigen::Vector2d o = plan.pixelOf({0, 0, 0}), ex = plan.pixelOf({1, 0, 0}),
                        ey = plan.pixelOf({0, 1, 0});
  EXPECT_NEAR((ex - o).x(), 50.0, 1e-9);
  EXPECT_NEAR((ey - o).y(), -50.0, 1e-9);
  // Under the 2.5 m ceiling (left out: above max_height_m) the floor shows.
  EXPECT_EQ(at(plan, {0.55, 2.55, 0}), kFloor);
  EXPECT_EQ(at(plan, {3.1, 0.15, 0}), kFloor);
  EXPECT_EQ(at(plan, {1.75, 1.15, 0.75}), kFurniture) << "the table top";
  EXPECT_EQ(at(plan, {4.0, 1.55, 1.0}), kWall);
  EXPECT_EQ(at(plan, {4.15, 1.55, 0}), kUnseen) << "behind the wall, inside the margin";
  // The 1 m grid over the floor (one pixel column near x = 1 m, none near 0.75 m), never over
  // the wall.
  const cv::Vec3b grid(215, 215, 215);
  int near_1m = 0, near_075m = 0;
  for (int k = -3; k <= 3; ++k) {
    near_1m += at(plan, {1.0 + 0.02 * k, 0.15, 0}) == grid;
    near_075m += at(plan, {0.75 + 0.02 * k, 0.15, 0}) == grid;
  }
  EXPECT_EQ(near_1m, 1);
  EXPECT_EQ(near_075m, 0);
  EXPECT_EQ(at(plan, {4.0, 1.0, 1.0}), kWall);
}

TEST(FloorPlan, PathGoalsAndObjectsAreDrawnWhereTheyAre) {
  const FloorPlan plan = drawFloorPlan(room());
  const cv::Vec3b path = at(plan, {2.05, 0.5, 1.0});
  EXPECT_GT(int(path[0]) - int(path[2]), 100) << "blue path at the camera's midway point";
  const cv::Vec3b start = at(plan, {0.5, 0.5, 1.0}), end = at(plan, {3.5, 0.5, 1.0});
  EXPECT_GT(int(start[1]) - int(start[2]), 80) << "green start";
  EXPECT_GT(int(end[2]) - int(end[1]), 100) << "red end";
  const cv::Vec3b goal = at(plan, {3.0, 2.0, 0});  // reached: a filled orange disc
  EXPECT_GT(int(goal[2]) - int(goal[0]), 150);
  // The table's outline: its box edge at x = 2.5 (between y 1 and 1.8) in its class colour.
  const cv::Vec3b edge = at(plan, {2.5, 1.4, 0});
  EXPECT_NE(edge, kFurniture);
  EXPECT_NE(edge, kFloor);
  EXPECT_NE(plan.svg.find(">dining table 0.87</text>"), std::string::npos);
  EXPECT_NE(plan.svg.find(">dining table (1)</text>"), std::string::npos) << "legend";
  EXPECT_EQ(plan.classes_shown, 1);
  EXPECT_NE(plan.svg.find("up = world +z (no gravity in the data"), std::string::npos);
  // The caption is wrapped to the plan's width: the image is no wider than the map and legend.
  EXPECT_LE(plan.image.cols, std::max(480, int(std::ceil(4.6 / 0.02)) + 2 * 12 + 2 * 12 + 250));
}

TEST(FloorPlan, SvgHasTheImageSizeAndEmbedsTheCells) {
  const FloorPlan plan = drawFloorPlan(room());
  const std::string size = "width=\"" + std::to_string(plan.image.cols) + "\" height=\"" +
                           std::to_string(plan.image.rows) + "\"";
  EXPECT_NE(plan.svg.find("<svg xmlns=\"http://www.w3.org/2000/svg\" " + size), std::string::npos);
  const std::string key = "data:image/png;base64,";
  const std::size_t b = plan.svg.find(key);
  ASSERT_NE(b, std::string::npos);
  const std::size_t e = plan.svg.find('"', b);
  std::vector<std::uint8_t> png;
  ASSERT_TRUE(mrpt::system::decodeBase64(plan.svg.substr(b + key.size(), e - b - key.size()), png));
  const cv::Mat cells = cv::imdecode(png, cv::IMREAD_COLOR);
  ASSERT_FALSE(cells.empty());
  // The map area: the room's 4 x 3 m plus the path, goals and 0.3 m margins, at 2 cm.
  EXPECT_NEAR(cells.cols, (4.0 + 0.6) / 0.02, 2);
  EXPECT_NEAR(cells.rows, (3.0 + 0.6) / 0.02, 2);
  EXPECT_EQ(plan.svg.substr(plan.svg.size() - 7), "</svg>\n");
}

TEST(FloorPlan, AHandHeldFrameWithYDownGivesTheSamePlan) {
  // The room in a camera-like frame (world z -> -y): a hand-held run without a gravity frame.
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  ASSERT_TRUE((R * Eigen::Vector3d::UnitZ()).isApprox(-Eigen::Vector3d::UnitY()));
  const FloorPlan plan = drawFloorPlan(room(R));
  EXPECT_TRUE(plan.up.up_world.isApprox(-Eigen::Vector3d::UnitY())) << plan.up.how;
  EXPECT_NEAR(plan.floor_height_m, 0.0, 0.02);
  EXPECT_EQ(at(plan, R * Eigen::Vector3d(0.55, 2.55, 0)), kFloor);
  EXPECT_EQ(at(plan, R * Eigen::Vector3d(1.75, 1.15, 0.75)), kFurniture);
  EXPECT_EQ(at(plan, R * Eigen::Vector3d(4.0, 1.55, 1.0)), kWall);
}

TEST(FloorPlan, LargeMapsAreScaledToFitAndEmptyInputDrawsNothing) {
  FloorPlanParams p;
  p.max_size_px = 100;
  const FloorPlan small = drawFloorPlan(room(), p);
  EXPECT_NEAR(small.metres_per_px, 4.6 / 100, 1e-9);
  EXPECT_TRUE(drawFloorPlan(FloorPlanInput{}).image.empty());
}

TEST(FloorPlan, ReadsObjectsJsonAndExplorationJson) {
  const nlohmann::json objects = nlohmann::json::parse(R"({"objects": [
    {"id": 3, "class": "chair", "class_id": 57, "probability": 0.91,
     "oriented_box": {"centre": [1, 2, 0.4], "axes": [[0, 1, 0], [-1, 0, 0], [0, 0, 1]],
                      "extents_m": [0.5, 0.6, 0.8]}},
    {"id": 4, "class": "cup", "class_id": 42, "probability": 0.7}]})");
  const std::vector<ObjectBox> o = objectBoxes(objects);
  ASSERT_EQ(o.size(), 1u) << "an entry without an oriented_box is left out";
  EXPECT_EQ(o[0].class_name, "chair");
  EXPECT_EQ(o[0].class_id, 57);
  EXPECT_TRUE(o[0].axes_world.col(0).isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_TRUE(o[0].extents_m.isApprox(Eigen::Vector3d(0.5, 0.6, 0.8)));
  const nlohmann::json expl = nlohmann::json::parse(R"({"goals": [
    {"goal": [1, 2, 0.5], "outcome": "reached"}, {"goal": [3, 1, 0], "outcome": "stuck"}]})");
  const std::vector<FloorPlanGoal> g = floorPlanGoals(expl);
  ASSERT_EQ(g.size(), 2u);
  EXPECT_TRUE(g[0].reached);
  EXPECT_FALSE(g[1].reached);
  EXPECT_DOUBLE_EQ(g[0].xy_yaw.z(), 0.5);
  EXPECT_TRUE(objectBoxes(nlohmann::json()).empty());
  EXPECT_TRUE(floorPlanGoals(nlohmann::json::array()).empty());
}
