// Candidate views, reachability pruning (MRPT PlannerSimple2D) and the ranking of section V, on
// hand-made grids and on an octree mapped from synthetic depth of a closed box room.

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "rasm/core/Error.h"
#include "rasm/exploration/ViewPlanner.h"

namespace rasm::exploration {
namespace {

/// A free 6 x 6 m grid at 10 cm.
mrpt::maps::COccupancyGridMap2D freeGrid() {
  mrpt::maps::COccupancyGridMap2D g;
  g.setSize(0.0f, 6.0f, 0.0f, 6.0f, 0.1f, 1.0f);
  return g;
}

void occupyRect(mrpt::maps::COccupancyGridMap2D& g, double x0, double y0, double x1, double y1) {
  for (double y = y0; y <= y1 + 1e-9; y += 0.05)
    for (double x = x0; x <= x1 + 1e-9; x += 0.05) g.setPos(float(x), float(y), 0.0f);
}

ViewCandidate at(double x, double y) {
  ViewCandidate c;
  c.pose = Eigen::Vector3d(x, y, 0.0);
  return c;
}

TEST(ViewCandidates, CandidateInAClosedRoomOrBeyondAWallIsPruned) {
  mrpt::maps::COccupancyGridMap2D g = freeGrid();
  // A closed room [3.5, 5.5]^2 (10 cm walls) and a wall across the grid at x = 2.5 for y < 3.
  occupyRect(g, 3.5, 3.5, 5.5, 3.6);
  occupyRect(g, 3.5, 5.4, 5.5, 5.5);
  occupyRect(g, 3.5, 3.5, 3.6, 5.5);
  occupyRect(g, 5.4, 3.5, 5.5, 5.5);
  occupyRect(g, 2.5, 0.0, 2.6, 3.0);
  TExplorationParams p;
  std::vector<ViewCandidate> c = {at(4.5, 4.5), at(4.0, 1.0), at(1.0, 5.0), at(4.0, 2.5)};
  const Eigen::Vector3d robot(1.0, 1.0, 0.0);
  planPaths(g, robot, p, c);
  EXPECT_FALSE(c[0].reachable);  // inside the closed room
  EXPECT_TRUE(c[1].reachable);   // around the wall's end at y = 3 (the grid is open above it)
  EXPECT_TRUE(c[2].reachable);
  EXPECT_TRUE(c[3].reachable);
  // Around the wall: at least up over its end (clear of it by the footprint) and back down.
  const double detour = std::hypot(2.5 - 1.0, 3.0 + 0.25 - 1.0) + std::hypot(4.0 - 2.6, 3.25 - 1.0);
  EXPECT_GE(c[1].path_length_m, detour - 0.2);
  EXPECT_LE(c[1].path_length_m, 1.3 * detour);
  // Straight up: the length is the distance (grid paths are 8-connected: within 8%).
  EXPECT_NEAR(c[2].path_length_m, 4.0, 0.08 * 4.0);
  EXPECT_NEAR(
      c[2].travel_time_s,
      c[2].path_length_m / p.speed_mps + c[2].rotation_rad / (p.turn_rate_degps * M_PI / 180),
      1e-9);
  EXPECT_GE(c[2].rotation_rad, M_PI / 2 - 0.2);  // heading 0 -> up -> final heading 0
  // A wall across the whole grid: nothing beyond it is reachable.
  occupyRect(g, 2.5, 0.0, 2.6, 6.0);
  std::vector<ViewCandidate> beyond = {at(4.0, 1.0), at(1.0, 5.0)};
  planPaths(g, robot, p, beyond);
  EXPECT_FALSE(beyond[0].reachable);
  EXPECT_TRUE(beyond[1].reachable);
}

TEST(ViewCandidates, RandomViewsStandInKnownFreeSpaceAndRepeatWithTheSeed) {
  mrpt::maps::COccupancyGridMap2D g;
  g.setSize(0.0f, 6.0f, 0.0f, 6.0f, 0.1f, 0.5f);  // unknown ...
  for (int iy = 10; iy < 30; ++iy)  // ... but a known free 3 x 2 m patch [1, 4] x [1, 3]
    for (int ix = 10; ix < 40; ++ix) g.setCell(ix, iy, 1.0f);
  TExplorationParams p;
  std::mt19937_64 rng(7), same(7), other(8);
  const auto views = sampleRandomViews(g, p, rng);
  ASSERT_EQ(int(views.size()), p.random_candidates);
  for (const ViewCandidate& v : views) {
    EXPECT_TRUE(footprintFree(g, v.pose.x(), v.pose.y(), p.footprint_radius_m));
    EXPECT_GE(v.pose.x(), 1.0 + p.footprint_radius_m - 0.1);
    EXPECT_LE(v.pose.y(), 3.0 - p.footprint_radius_m + 0.1);
  }
  const auto again = sampleRandomViews(g, p, same);
  const auto different = sampleRandomViews(g, p, other);
  int moved = 0;
  for (std::size_t k = 0; k < views.size(); ++k) {
    EXPECT_EQ(views[k].pose, again[k].pose);
    moved += views[k].pose != different[k].pose;
  }
  EXPECT_GT(moved, 0);
}

TEST(ViewCandidates, ObjectViewsLookAlongTheUprightAxesAtTheStandoff) {
  const mrpt::maps::COccupancyGridMap2D g = freeGrid();
  segmentation::SegmentStats box;
  box.id = 5;
  box.centroid = Eigen::Vector3d(3.0, 3.0, 0.4);
  const double c = std::cos(0.3), s = std::sin(0.3);  // turned 0.3 rad about z
  box.upright_axes << c, -s, 0, s, c, 0, 0, 0, 1;
  box.upright_extents = Eigen::Vector3d(0.6, 0.4, 0.8);
  segmentation::SegmentStats wall = box;
  wall.id = 6;
  wall.upright_extents = Eigen::Vector3d(4.0, 0.1, 2.5);  // too large to be an object
  TExplorationParams p;
  const auto views = objectViews({box, wall}, g, p);
  ASSERT_EQ(views.size(), 4u);
  for (const ViewCandidate& v : views) {
    EXPECT_EQ(v.segment, 5u);
    EXPECT_EQ(v.source, ViewCandidate::Source::Object);
    const Eigen::Vector2d to_object = box.centroid.head<2>() - v.pose.head<2>();
    EXPECT_NEAR(std::remainder(std::atan2(to_object.y(), to_object.x()) - v.pose.z(), 2 * M_PI),
                0.0, 1e-9);  // facing the centroid
    // Along one of the two horizontal axes, half the extent plus the standoff away.
    const double along0 = std::abs(to_object.dot(box.upright_axes.col(0).head<2>()));
    const double along1 = std::abs(to_object.dot(box.upright_axes.col(1).head<2>()));
    const bool on0 = std::abs(along0 - (0.3 + p.object_standoff_m)) < 1e-9 && along1 < 1e-9;
    const bool on1 = std::abs(along1 - (0.2 + p.object_standoff_m)) < 1e-9 && along0 < 1e-9;
    EXPECT_TRUE(on0 || on1) << v.pose.transpose();
  }
}

TEST(ViewPlanner, RankingNormalisesEachTermAndDividesByTravelTime) {
  TExplorationParams p;
  p.w_entropy = 1.0, p.w_ic = 2.0, p.min_travel_time_s = 1.0;
  std::vector<ViewCandidate> c(3);
  c[0].entropy_reduction = 100.0, c[0].information = 0.0, c[0].travel_time_s = 1.0;
  c[1].entropy_reduction = 50.0, c[1].information = 4.0, c[1].travel_time_s = 9.0;
  c[2].entropy_reduction = 0.0, c[2].information = 2.0, c[2].travel_time_s = 0.0;
  rankCandidates(p, c);
  // gains: 1 (rate 0.5), 0.5 + 2 = 2.5 (rate 0.25), 1 (rate 1)
  EXPECT_DOUBLE_EQ(c[0].gain, 1.0);
  EXPECT_DOUBLE_EQ(c[0].rate, 1.0);
  EXPECT_EQ(c[0].entropy_reduction, 0.0);
  EXPECT_EQ(c[1].entropy_reduction, 100.0);
  EXPECT_DOUBLE_EQ(c[2].gain, 2.5);
  p.rank_by_rate = false;
  rankCandidates(p, c);
  EXPECT_DOUBLE_EQ(c[0].gain, 2.5);
}

// ---- the whole plan on an octree mapped from a closed box room ----

const Eigen::Vector3d kRoomMin(-2.0, -2.0, 0.0), kRoomMax(4.0, 2.0, 2.5);
const CameraIntrinsics kK(60.0, 60.0, 39.5, 29.5, 80, 60);

/// The robot's camera mount: 0.1 m forward, 0.55 m up, pitched 10 degrees down (the [robot]
/// defaults), as an optical frame in the base frame.
Eigen::Isometry3d mount() {
  Eigen::Matrix3d R_body_optical;
  R_body_optical << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(10.0 * M_PI / 180, Eigen::Vector3d::UnitY()) * R_body_optical;
  T.translation() = Eigen::Vector3d(0.1, 0.0, 0.55);
  return T;
}

/// Depth of the room's walls, floor and ceiling seen from inside (the ray's exit from the box).
Image<float> roomDepth(const Eigen::Isometry3d& T) {
  Image<float> depth(kK.width, kK.height, 0.0f);
  for (int y = 0; y < kK.height; ++y)
    for (int x = 0; x < kK.width; ++x) {
      const Eigen::Vector3d r =
          T.linear() * Eigen::Vector3d((x - kK.cx) / kK.fx, (y - kK.cy) / kK.fy, 1.0);
      double t = 1e9;
      for (int a = 0; a < 3; ++a)
        if (std::abs(r[a]) > 1e-12)
          t = std::min(t, ((r[a] > 0 ? kRoomMax[a] : kRoomMin[a]) - T.translation()[a]) / r[a]);
      depth(x, y) = float(t);
    }
  return depth;
}

class RoomPlanTest : public ::testing::Test {
 protected:
  void SetUp() override {
    params_.workspace_min_x_m = -2.5, params_.workspace_max_x_m = 4.5;
    params_.workspace_min_y_m = -2.5, params_.workspace_max_y_m = 2.5;
    params_.predict_width = 80, params_.predict_height = 60;
    params_.random_candidates = 12;
    octree_ = std::make_unique<OccupancyOctree>(params_);
    for (int k = 0; k < 16; ++k) {  // the robot turns in place at the origin
      const Eigen::Isometry3d T = cameraPoseOf(Eigen::Vector3d(0, 0, k * M_PI / 8), mount());
      octree_->insertDepthFrame(roomDepth(T), kK, T);
    }
    segmentation::SegmentStats object;
    object.id = 3;
    object.centroid = Eigen::Vector3d(2.0, 0.0, 0.4);
    object.upright_extents = Eigen::Vector3d(0.4, 0.3, 0.8);
    segments_ = {object};
    in_.store = &store_;
    in_.segments = &segments_;
    in_.octree = octree_.get();
    in_.T_base_cam = mount();
    in_.K = kK;
  }
  TExplorationParams params_;
  std::unique_ptr<OccupancyOctree> octree_;
  maps::SurfelStore store_;
  std::vector<segmentation::SegmentStats> segments_;
  PlannerInputs in_;
};

TEST_F(RoomPlanTest, PlansReachableRankedViewsAndTheSameSeedGivesTheSamePlan) {
  const Plan plan = ViewPlanner(params_).plan(in_);
  ASSERT_GE(plan.ranked.size(), 8u);
  int objects = 0;
  for (std::size_t k = 0; k < plan.ranked.size(); ++k) {
    const ViewCandidate& c = plan.ranked[k];
    EXPECT_TRUE(c.reachable);
    EXPECT_TRUE(footprintFree(plan.grid, c.pose.x(), c.pose.y(), params_.footprint_radius_m));
    EXPECT_TRUE(c.T_world_cam.isApprox(cameraPoseOf(c.pose, mount())));
    EXPECT_GT(c.pose.x(), kRoomMin.x());
    EXPECT_LT(c.pose.x(), kRoomMax.x());
    EXPECT_GT(c.pose.y(), kRoomMin.y());
    EXPECT_LT(c.pose.y(), kRoomMax.y());
    EXPECT_EQ(c.information, 0.0);  // no surfels
    EXPECT_GE(c.entropy_reduction, 0.0);
    if (k > 0) {
      EXPECT_GE(plan.ranked[k - 1].rate, c.rate);
    }
    objects += c.source == ViewCandidate::Source::Object;
  }
  EXPECT_EQ(objects, 4);  // the object's four views stand in the mapped free space, reachable
  EXPECT_DOUBLE_EQ(std::max_element(plan.ranked.begin(), plan.ranked.end(),
                                    [](const auto& a, const auto& b) { return a.gain < b.gain; })
                       ->gain,
                   params_.w_entropy);

  const Plan again = ViewPlanner(params_).plan(in_);
  ASSERT_EQ(again.ranked.size(), plan.ranked.size());
  for (std::size_t k = 0; k < plan.ranked.size(); ++k) {
    EXPECT_EQ(again.ranked[k].pose, plan.ranked[k].pose);
    EXPECT_EQ(again.ranked[k].rate, plan.ranked[k].rate);
  }
}

// The candidates are predicted on all threads, each by one thread: the plan must not depend on
// the thread count (a run must replay the same on a laptop and on CI).
TEST_F(RoomPlanTest, ThePlanDoesNotDependOnTheThreadCount) {
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const Plan one = ViewPlanner(params_).plan(in_);
  omp_set_num_threads(3);
  const Plan three = ViewPlanner(params_).plan(in_);
  omp_set_num_threads(threads);
  ASSERT_GE(one.ranked.size(), 8u);
  ASSERT_EQ(three.ranked.size(), one.ranked.size());
  for (std::size_t k = 0; k < one.ranked.size(); ++k) {
    EXPECT_EQ(three.ranked[k].pose, one.ranked[k].pose);
    EXPECT_EQ(three.ranked[k].entropy_reduction, one.ranked[k].entropy_reduction);
    EXPECT_EQ(three.ranked[k].gain, one.ranked[k].gain);
  }
  EXPECT_EQ(three.unreachable.size(), one.unreachable.size());
}

// The coarse screen ([exploration] predict_screen_keep): the kept views are predicted exactly as
// without it (same dH at the full size), the others are left out and counted, and the best view
// survives the screen (40x30 rays of this camera are 13 cm apart at the 4 m range, about the
// octree's 10 cm cell).
TEST_F(RoomPlanTest, TheScreenPredictsTheBestViewsInFullAndCountsTheRest) {
  const Plan full = ViewPlanner(params_).plan(in_);
  ASSERT_GE(full.ranked.size(), 10u);
  EXPECT_EQ(full.screened_out, 0u);
  TExplorationParams screen = params_;
  screen.predict_screen_keep = 5;
  screen.predict_screen_width = 40, screen.predict_screen_height = 30;
  const Plan screened = ViewPlanner(screen).plan(in_);
  ASSERT_EQ(screened.ranked.size(), 5u);  // no frontier views in this plan (frontier_candidates)
  EXPECT_EQ(screened.screened_out, full.ranked.size() - 5);
  EXPECT_EQ(screened.unreachable.size(), full.unreachable.size());
  for (const ViewCandidate& c : screened.ranked) {
    const auto same = std::find_if(full.ranked.begin(), full.ranked.end(),
                                   [&](const ViewCandidate& f) { return f.pose == c.pose; });
    ASSERT_NE(same, full.ranked.end());
    EXPECT_EQ(c.entropy_reduction, same->entropy_reduction);
  }
  EXPECT_EQ(screened.ranked.front().pose, full.ranked.front().pose);
  // Keeping at least every candidate is no screen at all.
  screen.predict_screen_keep = int(full.ranked.size());
  const Plan all = ViewPlanner(screen).plan(in_);
  ASSERT_EQ(all.ranked.size(), full.ranked.size());
  for (std::size_t k = 0; k < all.ranked.size(); ++k) {
    EXPECT_EQ(all.ranked[k].pose, full.ranked[k].pose);
    EXPECT_EQ(all.ranked[k].rate, full.ranked[k].rate);
  }
}

TEST_F(RoomPlanTest, MissingInputIsAnInputError) {
  in_.octree = nullptr;
  EXPECT_THROW(ViewPlanner(params_).plan(in_), InputError);
}

}  // namespace
}  // namespace rasm::exploration
