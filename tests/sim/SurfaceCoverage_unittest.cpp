// Surface coverage of a world's ground truth (SurfaceCoverage.h) on the shipped office: the
// samples' weights add up to the surface area; the samples themselves (and the samples moved
// 1.9 cm along their normals) cover everything observable, samples moved 5 cm cover almost
// nothing, no points cover nothing; points on the floor alone cover structure only; one object's
// samples cover that object; what a 0.55 m camera pitched 10 deg down cannot see (desk tops and
// undersides, the ceiling, high walls) is not observable, while a 1.5 m camera pitched down sees
// the desk tops; the same result for any thread count; the options of a robot's camera.
#include "rasm/sim/SurfaceCoverage.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "rasm/core/CameraIntrinsics.h"
#include "rasm/models/ClassVocabulary.h"
#include "rasm/sim/SimulatedDiffDriveRobot.h"

using namespace rasm::sim;
using namespace rasm::models;
using V3f = Eigen::Vector3f;

namespace {

struct Office {
  World world = loadWorld("office");
  RayScene scene{world};
  SurfaceCoverage cov{world, scene};
};

/// Built once for the suite (about 1 s on 2 cores).
const Office& office() {
  static const std::unique_ptr<Office> o = std::make_unique<Office>();
  return *o;
}

std::vector<V3f> samplePositions(const SurfaceCoverage& cov, float along_normal_m = 0.f) {
  std::vector<V3f> pts;
  for (const auto& s : cov.samples()) pts.push_back(s.position + along_normal_m * s.normal);
  return pts;
}

int objectNamed(const World& w, const std::string& name) {
  for (std::size_t i = 0; i < w.objects.size(); ++i)
    if (w.objects[i].name == name) return int(i);
  return -1;
}

}  // namespace

TEST(SurfaceCoverage, SamplesAddUpToTheSurfaceArea) {
  const Office& o = office();
  std::vector<double> area(o.world.objects.size(), 0.0);
  for (const auto& s : o.cov.samples()) {
    ASSERT_GE(s.object, 0);
    EXPECT_NEAR(s.normal.norm(), 1.f, 1e-4f);
    area[std::size_t(s.object)] += s.area_m2;
  }
  for (std::size_t i = 0; i < area.size(); ++i)
    EXPECT_NEAR(area[i], o.world.objects[i].worldMesh().surfaceArea(),
                1e-4 * o.world.objects[i].worldMesh().surfaceArea())
        << o.world.objects[i].name;
  // About one sample per spacing^2 (0.03 m): the office's 436 m^2.
  double total = 0;
  for (double a : area) total += a;
  EXPECT_NEAR(double(o.cov.samples().size()), total / (0.03 * 0.03), 0.2 * total / (0.03 * 0.03));
  EXPECT_GT(o.cov.observableSamples(), 0u);
  EXPECT_LT(o.cov.observableSamples(), o.cov.samples().size());
  EXPECT_FALSE(o.cov.robotPositions().empty());
}

TEST(SurfaceCoverage, OwnSamplesCoverAllAndNoPointsNothing) {
  const Office& o = office();
  const SurfaceCoverage::Result all = o.cov.evaluate(samplePositions(o.cov));
  EXPECT_DOUBLE_EQ(all.fraction, 1.0);
  EXPECT_DOUBLE_EQ(all.structure, 1.0);
  EXPECT_DOUBLE_EQ(all.furniture_and_objects, 1.0);
  EXPECT_EQ(all.covered, all.observable);
  EXPECT_EQ(all.observable, o.cov.observableSamples());
  EXPECT_EQ(all.samples, o.cov.samples().size());
  ASSERT_EQ(all.per_object.size(), o.world.objects.size());
  for (double f : all.per_object) EXPECT_TRUE(f == 1.0 || f == -1.0) << f;
  // Within the 2 cm: each sample's own point 1.9 cm off the surface still covers it.
  EXPECT_DOUBLE_EQ(o.cov.evaluate(samplePositions(o.cov, 0.019f)).fraction, 1.0);

  const SurfaceCoverage::Result none = o.cov.evaluate({});
  EXPECT_EQ(none.fraction, 0.0);
  EXPECT_EQ(none.structure, 0.0);
  EXPECT_EQ(none.furniture_and_objects, 0.0);
  EXPECT_EQ(none.covered, 0u);
  EXPECT_EQ(none.observable, o.cov.observableSamples());
  EXPECT_GT(none.observable_area_m2, 10.0);
  for (std::size_t i = 0; i < none.per_object.size(); ++i)
    EXPECT_EQ(none.per_object[i], all.per_object[i] == 1.0 ? 0.0 : -1.0);
  // Non-finite and far-away points are ignored.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(o.cov.evaluate({V3f(nan, 0, 0), V3f(1e9f, 0, 0), V3f(-3e4f, 2e5f, 0)}).covered, 0u);
}

TEST(SurfaceCoverage, PointsFiveCentimetresOffTheSurfaceCoverAlmostNothing) {
  const Office& o = office();
  // The observable samples moved 5 cm out along their normals: each point is 5 cm from its own
  // face and within 2 cm only of another surface, near a concave edge (the floor beside a wall
  // or a box, a shelf board beside the shelf's side, books standing side by side), a band at
  // most 2 cm wide on each face of the edge: 2.7 % of the office's observable area.
  std::vector<V3f> pts;
  for (const auto& s : o.cov.samples())
    if (s.observable) pts.push_back(s.position + 0.05f * s.normal);
  const SurfaceCoverage::Result r = o.cov.evaluate(pts);
  EXPECT_LT(r.fraction, 0.04);
  EXPECT_LT(r.structure, 0.04);
}

TEST(SurfaceCoverage, PointsOnTheFloorCoverStructureOnly) {
  const Office& o = office();
  const int floor = objectNamed(o.world, "floor");
  ASSERT_GE(floor, 0);
  // The floor's observable samples away from everything that reaches down to it (its xy bounds
  // plus 3 cm: nothing else is then within 2 cm of a point).
  std::vector<Eigen::AlignedBox3f> near_floor;
  for (std::size_t i = 0; i < o.world.objects.size(); ++i) {
    const Eigen::AlignedBox3f& b = o.scene.objectBounds(int(i));
    if (int(i) != floor && b.min().z() < 0.03f) near_floor.push_back(b);
  }
  std::vector<V3f> pts;
  double given = 0, obs = 0, obs_structure = 0;
  for (const auto& s : o.cov.samples()) {
    if (!s.observable) continue;
    obs += s.area_m2;
    if (isStructureClass(o.world.objects[std::size_t(s.object)].class_id))
      obs_structure += s.area_m2;
    if (s.object != floor) continue;
    bool clear = true;
    for (const auto& b : near_floor)
      clear =
          clear && !(s.position.x() > b.min().x() - 0.03f && s.position.x() < b.max().x() + 0.03f &&
                     s.position.y() > b.min().y() - 0.03f && s.position.y() < b.max().y() + 0.03f);
    if (!clear) continue;
    pts.push_back(s.position);
    given += s.area_m2;
  }
  ASSERT_GT(pts.size(), 1000u);
  const SurfaceCoverage::Result r = o.cov.evaluate(pts);
  EXPECT_EQ(r.furniture_and_objects, 0.0);
  EXPECT_GT(r.structure, 0.0);
  // The given samples plus, at most, a few floor samples within 2 cm of them (the lattice pitch
  // is 3 cm; only where the top face's two triangles meet can samples be closer).
  EXPECT_GE(r.fraction, given / obs - 1e-9);
  EXPECT_LE(r.fraction, given / obs + 0.002);
  EXPECT_NEAR(r.structure, r.fraction * obs / obs_structure, 1e-9);
  EXPECT_GT(r.per_object[std::size_t(floor)], 0.5);
  for (std::size_t i = 0; i < r.per_object.size(); ++i)
    if (int(i) != floor) {
      EXPECT_LE(r.per_object[i], 0.0) << o.world.objects[i].name;
    }
}

TEST(SurfaceCoverage, OneObjectsSamplesCoverThatObject) {
  const Office& o = office();
  for (const char* name : {"plant", "backpack"}) {
    const int k = objectNamed(o.world, name);
    ASSERT_GE(k, 0) << name;
    std::vector<V3f> pts;
    for (const auto& s : o.cov.samples())
      if (s.object == k) pts.push_back(s.position);
    const SurfaceCoverage::Result r = o.cov.evaluate(pts);
    EXPECT_DOUBLE_EQ(r.per_object[std::size_t(k)], 1.0) << name;
    EXPECT_GT(r.furniture_and_objects, 0.0);
    EXPECT_LT(r.furniture_and_objects, 0.1);
    EXPECT_LT(r.fraction, 0.02);
  }
}

TEST(SurfaceCoverage, WhatTheRobotsCameraCannotSeeIsNotObservable) {
  const Office& o = office();
  // Camera 0.55 m, pitched 10 deg down, vertical field of view 49.1 deg: it looks up at most
  // 14.6 deg, so a horizontal face above it is seen at an incidence over 75 deg (not counted):
  // the desk tops (0.74 m) and their undersides (0.71 m) and the ceiling are not observable;
  // nor are the walls above 0.55 m + sin(14.6 deg) 4 m / cos(24.6 deg) = 1.66 m (the top row
  // at the 4 m depth limit).
  std::size_t desk_top = 0, desk_under = 0, desk_observable = 0;
  for (const auto& s : o.cov.samples()) {
    const WorldObject& obj = o.world.objects[std::size_t(s.object)];
    if (obj.class_id == classIdFromName("dining table")) {
      if (s.position.z() > 0.6f && s.normal.z() < -0.9f) {
        ++desk_under;
        EXPECT_FALSE(s.observable) << obj.name << " underside at " << s.position.transpose();
      }
      if (s.position.z() > 0.6f && s.normal.z() > 0.9f) {
        ++desk_top;
        EXPECT_FALSE(s.observable) << obj.name << " top at " << s.position.transpose();
      }
      desk_observable += s.observable ? 1 : 0;  // legs and the edges of the tops
    }
    if (obj.class_id == classIdFromName("ceiling")) {
      EXPECT_FALSE(s.observable);
    }
    if (obj.class_id == classIdFromName("wall") && s.position.z() > 1.67f) {
      EXPECT_FALSE(s.observable) << obj.name << " at " << s.position.transpose();
    }
  }
  EXPECT_GT(desk_under, 1000u);
  EXPECT_GT(desk_top, 1000u);
  EXPECT_GT(desk_observable, 100u);
  // The floor in the middle of the room and the walls low down are observable; so is the floor
  // under the desks (between their legs), but not the floor under the walls.
  const int floor = objectNamed(o.world, "floor");
  std::size_t floor_mid = 0, floor_mid_obs = 0, under_wall_obs = 0;
  for (const auto& s : o.cov.samples()) {
    if (s.object != floor || s.normal.z() < 0.9f) continue;
    const V3f& p = s.position;
    if (p.x() > 4.9f && p.x() < 5.6f && p.y() > 1.2f && p.y() < 1.9f) {  // nothing near
      ++floor_mid;
      floor_mid_obs += s.observable ? 1 : 0;
    }
    if (p.y() < -0.01f || p.x() < -0.01f) under_wall_obs += s.observable ? 1 : 0;
  }
  EXPECT_GT(floor_mid, 400u);
  EXPECT_EQ(floor_mid_obs, floor_mid);
  EXPECT_EQ(under_wall_obs, 0u);
}

TEST(SurfaceCoverage, AHigherCameraSeesTheDeskTops) {
  const Office& o = office();
  CoverageOptions opts;
  opts.camera_height_m = 1.5;  // a hand-held camera, looking down
  opts.camera_pitch_deg = -30;
  const SurfaceCoverage high(o.world, o.scene, opts);
  ASSERT_EQ(high.samples().size(), o.cov.samples().size());  // the same samples
  std::size_t top = 0, top_obs = 0;
  for (const auto& s : high.samples()) {
    const WorldObject& obj = o.world.objects[std::size_t(s.object)];
    if (obj.name == "desk_1" && s.position.z() > 0.7f && s.normal.z() > 0.9f) {
      ++top;
      top_obs += s.observable ? 1 : 0;
    }
  }
  ASSERT_GT(top, 500u);
  // The top is 1.6 x 0.8 m; the monitor, keyboard, mug, mouse and bottle hide part of it.
  EXPECT_GT(double(top_obs), 0.6 * double(top));
}

TEST(SurfaceCoverage, TheSameForAnyThreadCount) {
  const Office& o = office();
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const SurfaceCoverage serial(o.world, o.scene);
  std::vector<V3f> pts = samplePositions(serial, 0.015f);
  pts.resize(pts.size() / 3);  // part of the room
  const SurfaceCoverage::Result r1 = serial.evaluate(pts);
  omp_set_num_threads(std::max(2, threads));
  const SurfaceCoverage::Result r2 = o.cov.evaluate(pts);
  omp_set_num_threads(threads);
  ASSERT_EQ(serial.samples().size(), o.cov.samples().size());
  for (std::size_t i = 0; i < serial.samples().size(); ++i) {
    ASSERT_EQ(serial.samples()[i].observable, o.cov.samples()[i].observable) << i;
    ASSERT_EQ(serial.samples()[i].position, o.cov.samples()[i].position) << i;
  }
  EXPECT_GT(r1.fraction, 0.0);
  EXPECT_LT(r1.fraction, 1.0);
  EXPECT_EQ(r1.fraction, r2.fraction);
  EXPECT_EQ(r1.structure, r2.structure);
  EXPECT_EQ(r1.furniture_and_objects, r2.furniture_and_objects);
  EXPECT_EQ(r1.covered, r2.covered);
  EXPECT_EQ(r1.per_object, r2.per_object);
}

TEST(SurfaceCoverage, OptionsForARobotsCamera) {
  TRobotParams robot;
  robot.camera_height_m = 0.8;
  robot.camera_pitch_deg = -20;
  robot.camera_x_m = 0.15;
  const rasm::CameraIntrinsics K = rasm::CameraIntrinsics::preset("kinect_v1");
  const CoverageOptions o = coverageOptionsForRobot(robot, K, 3.5);
  EXPECT_EQ(o.camera_height_m, 0.8);
  EXPECT_EQ(o.camera_pitch_deg, -20);
  EXPECT_EQ(o.camera_forward_m, 0.15);
  EXPECT_EQ(o.max_range_m, 3.5);
  EXPECT_NEAR(o.vertical_fov_deg, 2 * std::atan(240.0 / 525.0) * 180 / M_PI, 1e-9);
  EXPECT_EQ(o.robot_radius_m, robot.footprint_radius_m);
  EXPECT_EQ(o.robot_z_min_m, robot.ground_clearance_m);
  EXPECT_EQ(o.robot_z_max_m, robot.height_m);
  EXPECT_EQ(o.max_dist_m, 0.02);
  // Its T_base_cam agrees: the optical axis (camera z) at the mount's height and pitch.
  const Eigen::Isometry3d T = robot.T_base_cam();
  EXPECT_NEAR(T.translation().z(), o.camera_height_m, 1e-12);
  EXPECT_NEAR(std::asin(T.linear().col(2).z()) * 180 / M_PI, o.camera_pitch_deg, 1e-9);
  // A polygon footprint: the largest distance of its vertices from the rotation centre.
  robot.footprint_radius_m = 0;
  robot.footprint_xs = {0.3, -0.2, -0.2, 0.3};
  robot.footprint_ys = {-0.2, -0.2, 0.2, 0.2};
  EXPECT_NEAR(coverageOptionsForRobot(robot, K).robot_radius_m, std::hypot(0.3, 0.2), 1e-6);
}
