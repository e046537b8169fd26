// OccupancyOctree (V-A): entropy of the workspace, updates from depth frames, predicted entropy
// reduction of a view, the 2-D projection. Geometry: synthetic depth of a flat wall facing the
// camera (depth = the wall's distance on every pixel), cameras at octree cell centres.

#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cmath>
#include <limits>

#include "rasm/core/Error.h"
#include "rasm/exploration/OccupancyOctree.h"

namespace rasm::exploration {
namespace {

const double kLog2 = std::log(2.0);

/// Optical camera at `eye` looking horizontally along world heading `yaw` (x right = heading
/// turned clockwise, y down = -z).
Eigen::Isometry3d horizontalCamera(const Eigen::Vector3d& eye, double yaw) {
  const Eigen::Vector3d fwd(std::cos(yaw), std::sin(yaw), 0.0);
  const Eigen::Vector3d right(std::sin(yaw), -std::cos(yaw), 0.0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = right;
  T.linear().col(1) = -Eigen::Vector3d::UnitZ();
  T.linear().col(2) = fwd;
  T.translation() = eye;
  return T;
}

TExplorationParams wallParams() {
  TExplorationParams p;
  p.resolution_m = 0.1;
  p.pixel_stride = 1;
  p.workspace_min_x_m = -5.0, p.workspace_max_x_m = 4.0;
  p.workspace_min_y_m = -3.0, p.workspace_max_y_m = 3.0;
  p.workspace_min_z_m = -1.0, p.workspace_max_z_m = 3.0;
  return p;
}

// 64 x 48 pixels at f = 40 px: 77 x 62 degrees; at 1.98 m the pixels are 5 cm apart, finer than
// the 10 cm cells, so every cell the frustum crosses is crossed by a ray.
const CameraIntrinsics kWallK(40.0, 40.0, 31.5, 23.5, 64, 48);
const double kWallDepth = 1.98;
const Eigen::Vector3d kEye(0.05, 0.05, 0.35);  // a cell centre

TEST(OccupancyOctree, AllUnknownBoxHasCellsTimesLog2) {
  TExplorationParams p;
  p.resolution_m = 0.1;
  p.workspace_min_x_m = 0.0, p.workspace_max_x_m = 1.0;  // cell centres 0.05 .. 0.95: 10
  p.workspace_min_y_m = 0.0, p.workspace_max_y_m = 2.0;  // 20
  p.workspace_min_z_m = 0.0, p.workspace_max_z_m = 0.5;  // 5
  OccupancyOctree octree(p);
  EXPECT_EQ(octree.workspaceCells(), 1000);
  EXPECT_DOUBLE_EQ(octree.entropy(), 1000 * kLog2);
  const auto counts = octree.countCells();
  EXPECT_EQ(counts.unknown, 1000);
}

TEST(OccupancyOctree, OneAxisAlignedRayFreesTheCellsBeforeItsEnd) {
  // One pixel on the optical axis, along world +x from the centre of cell 0 to the centre of
  // cell 10: cells 0..9 free, cell 10 occupied.
  OccupancyOctree octree(wallParams());
  const CameraIntrinsics K(1.0, 1.0, 0.0, 0.0, 1, 1);
  Image<float> depth(1, 1, 1.0f);
  const Eigen::Isometry3d T = horizontalCamera(kEye, 0.0);
  const double h0 = octree.entropy();
  const double predicted = octree.predictedEntropyReduction(T, K, depth);
  octree.insertDepthFrame(depth, K, T);
  const TExplorationParams& p = octree.params();
  const double expected =
      10 * (kLog2 - cellEntropy(p.prob_miss)) + (kLog2 - cellEntropy(p.prob_hit));
  EXPECT_NEAR(h0 - octree.entropy(), expected, 1e-5);  // float log-odds in the tree
  EXPECT_NEAR(predicted, h0 - octree.entropy(), 1e-9);
  const auto counts = octree.countCells();
  EXPECT_EQ(counts.free, 10);
  EXPECT_EQ(counts.occupied, 1);
  EXPECT_TRUE(octree.tree().isNodeOccupied(octree.tree().search(1.05, 0.05, 0.35)));
}

TEST(OccupancyOctree, WallScanLowersEntropyByTheSensorModelOverTheFrustum) {
  OccupancyOctree octree(wallParams());
  Image<float> depth(kWallK.width, kWallK.height, float(kWallDepth));
  const Eigen::Isometry3d T = horizontalCamera(kEye, 0.0);
  const double h0 = octree.entropy();
  const double predicted = octree.predictedEntropyReduction(T, kWallK, depth);
  octree.insertDepthFrame(depth, kWallK, T);
  const double drop = h0 - octree.entropy();
  const auto counts = octree.countCells();
  // Each cell got exactly one update: the drop is the sensor model's per cell.
  const TExplorationParams& p = octree.params();
  EXPECT_NEAR(drop,
              counts.free * (kLog2 - cellEntropy(p.prob_miss)) +
                  counts.occupied * (kLog2 - cellEntropy(p.prob_hit)),
              1e-6 * drop);
  EXPECT_NEAR(predicted, drop, 1e-9 * drop);
  // Occupied: the wall's layer of cells inside the frustum's footprint, w x h at the wall, give or
  // take the cells its border crosses.
  const double res = 0.1, d = kWallDepth;
  const double w = kWallK.width / kWallK.fx * d / res, h = kWallK.height / kWallK.fy * d / res;
  EXPECT_GE(counts.occupied, (w - 2) * (h - 2));
  EXPECT_LE(counts.occupied, (w + 2) * (h + 2));
  // Free: the pyramid from the camera to the wall, volume w h d / 3 (in cells), give or take the
  // cells its four side faces cross (sqrt(3) cells per cell of face area at most).
  const double volume = w * h * (d / res) / 3.0;
  const double side_w = std::hypot(d / res, h / 2), side_h = std::hypot(d / res, w / 2);
  const double faces = w * side_w + h * side_h;
  EXPECT_NEAR(double(counts.free), volume, std::sqrt(3.0) * faces);
  EXPECT_GT(counts.free, volume * 0.5);
}

// insertDepthFrame casts its rays itself (OctoMap's computeUpdate shares one ray buffer per
// tree, which the planner's threads cannot): the tree must be the one OctoMap's own
// insertPointCloud (discretized) builds from the same points, cell for cell. The wall is slanted
// so that its far part lies beyond max_range_m (those rays free their first 4 m only).
TEST(OccupancyOctree, DepthFrameUpdatesTheCellsOctoMapsOwnInsertWould) {
  OccupancyOctree octree(wallParams());
  const TExplorationParams& p = octree.params();
  Image<float> depth(kWallK.width, kWallK.height, 0.0f);
  for (int y = 0; y < kWallK.height; ++y)
    for (int x = 0; x < kWallK.width; ++x) depth(x, y) = float(1.2 + 0.08 * x);  // 1.2 .. 6.2 m
  const Eigen::Isometry3d T = horizontalCamera(kEye, 0.3);
  octree.insertDepthFrame(depth, kWallK, T);

  octomap::OcTree ref(p.resolution_m);
  ref.setProbHit(p.prob_hit);
  ref.setProbMiss(p.prob_miss);
  ref.setClampingThresMin(p.clamp_min);
  ref.setClampingThresMax(p.clamp_max);
  octomap::Pointcloud cloud;
  for (int y = 0; y < kWallK.height; ++y)
    for (int x = 0; x < kWallK.width; ++x) {
      const Eigen::Vector3d ray((x - kWallK.cx) / kWallK.fx, (y - kWallK.cy) / kWallK.fy, 1.0);
      const Eigen::Vector3d q = T * (ray * double(depth(x, y)));
      cloud.push_back(float(q.x()), float(q.y()), float(q.z()));
    }
  const Eigen::Vector3d o = T.translation();
  ref.insertPointCloud(cloud, octomap::point3d(float(o.x()), float(o.y()), float(o.z())),
                       p.max_range_m, false, true);

  const octomap::OcTree& tree = octree.tree();
  ASSERT_GT(ref.getNumLeafNodes(), 1000u);
  EXPECT_EQ(tree.getNumLeafNodes(), ref.getNumLeafNodes());
  std::size_t compared = 0;
  for (auto it = ref.begin_leafs(), end = ref.end_leafs(); it != end; ++it, ++compared) {
    const octomap::OcTreeNode* n = tree.search(it.getKey(), it.getDepth());
    ASSERT_NE(n, nullptr) << "cell " << it.getCoordinate() << " missing";
    EXPECT_EQ(n->getLogOdds(), it->getLogOdds()) << "cell " << it.getCoordinate();
  }
  EXPECT_EQ(compared, ref.getNumLeafNodes());
}

TEST(OccupancyOctree, ViewIntoUnknownSpacePredictsMoreGainThanTheSeenWall) {
  OccupancyOctree octree(wallParams());
  Image<float> wall(kWallK.width, kWallK.height, float(kWallDepth));
  octree.insertDepthFrame(wall, kWallK, horizontalCamera(kEye, 0.0));
  // Facing the wall again (the surfel map predicts it at the same depth) vs facing away from it
  // into unknown space (nothing rendered: free up to max_range_m = 4 m).
  const double again = octree.predictedEntropyReduction(horizontalCamera(kEye, 0.0), kWallK, wall);
  Image<float> nothing(kWallK.width, kWallK.height, 0.0f);
  const double away =
      octree.predictedEntropyReduction(horizontalCamera(kEye, M_PI), kWallK, nothing);
  EXPECT_GT(again, 0.0);  // a second observation still sharpens the cells (not clamped yet)
  // Into unknown space the pyramid is (4 / 1.98)^3 = 8.2 times the wall's (the workspace clips
  // some), and a first observation lowers a cell's entropy more than a second one.
  EXPECT_GT(away, 4.0 * again);
}

TEST(OccupancyOctree, DefaultSensorModelGainsMostFromAFirstObservation) {
  // The property the default prob_hit / prob_miss are chosen for (TExplorationParams.h).
  const TExplorationParams p;
  const auto logit = [](double q) { return std::log(q / (1.0 - q)); };
  const auto prob = [](double l) { return 1.0 / (1.0 + std::exp(-l)); };
  const double lo = logit(p.clamp_min), hi = logit(p.clamp_max);
  for (const double q : {p.prob_hit, p.prob_miss}) {
    const double l1 = std::min(std::max(logit(q), lo), hi);
    const double l2 = std::min(std::max(2.0 * logit(q), lo), hi);
    const double first = kLog2 - cellEntropy(prob(l1));
    const double second = cellEntropy(prob(l1)) - cellEntropy(prob(l2));
    EXPECT_GT(first, second) << "P = " << q;
  }
}

TEST(OccupancyOctree, ProjectionMarksTheWallOccupiedAndTheSpaceBeforeItFree) {
  OccupancyOctree octree(wallParams());
  Image<float> wall(kWallK.width, kWallK.height, float(kWallDepth));
  octree.insertDepthFrame(wall, kWallK, horizontalCamera(kEye, 0.0));
  mrpt::maps::COccupancyGridMap2D grid;
  octree.projectToGrid(grid);
  EXPECT_NEAR(grid.getResolution(), 0.1, 1e-6);
  EXPECT_GT(grid.getPos(1.05f, 0.05f), 0.9f);            // free (MRPT: probability of being free)
  EXPECT_LT(grid.getPos(2.05f, 0.05f), 0.1f);            // the wall
  EXPECT_NEAR(grid.getPos(3.05f, 0.05f), 0.5f, 0.01f);   // behind it: unknown
  EXPECT_NEAR(grid.getPos(-1.05f, 0.05f), 0.5f, 0.01f);  // behind the camera
}

TEST(OccupancyOctree, BadInputIsAnInputErrorNamingIt) {
  OccupancyOctree octree(wallParams());
  Image<float> small(10, 10, 1.0f);
  EXPECT_THROW(octree.insertDepthFrame(small, kWallK, Eigen::Isometry3d::Identity()), InputError);
  Image<float> depth(kWallK.width, kWallK.height, 1.0f);
  depth(3, 4) = std::numeric_limits<float>::quiet_NaN();
  try {
    octree.insertDepthFrame(depth, kWallK, Eigen::Isometry3d::Identity());
    FAIL() << "NaN depth accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("pixel (3, 4)"), std::string::npos) << e.what();
  }
  TExplorationParams p;
  p.workspace_max_z_m = p.workspace_min_z_m - 1.0;
  EXPECT_THROW(OccupancyOctree{p}, InputError);
  p = TExplorationParams();
  p.resolution_m = 0.0;
  EXPECT_THROW(OccupancyOctree{p}, InputError);
}

}  // namespace
}  // namespace rasm::exploration
