// Distance of map points to a world's ground-truth surface (SurfaceDistance.h, `rasm sim
// check-map`): points on a face are within, points 10 cm off are beyond, the bound is exact
// along a face normal and an overestimate (never an under-) beside an edge, points sampled on
// the shipped office by ray casting are all on the surface; and ViewStats (the hand-held view
// rule of the generated trajectories): one plane, two planes, a corner, objects.
#include "rasm/sim/SurfaceDistance.h"

#include <gtest/gtest.h>

#include "sim/OfficeRayHits.h"

#include <cmath>
#include <random>

#include "rasm/sim/CameraPoses.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/RgbdSensor.h"
#include "rasm/sim/ViewStats.h"
#include "rasm/sim/World.h"

using namespace rasm::sim;
using V3f = Eigen::Vector3f;

namespace {

/// One unit box: x, y in [-0.5, 0.5], z in [0, 1].
RayScene boxScene() {
  return RayScene(loadWorldFromString(
      "objects:\n  - {id: 1, class: box, primitive: box, size: [1, 1, 1], position: [0, 0, 0.5]}\n",
      "box"));
}

}  // namespace

TEST(SurfaceDistance, PointsOnAFaceAreWithinPointsOffItBeyond) {
  const RayScene scene = boxScene();
  std::vector<V3f> on, off, normals;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-0.45f, 0.45f);
  for (int i = 0; i < 200; ++i) {
    const float x = u(rng), y = u(rng);
    on.emplace_back(x, y, 1.0f);   // top face
    off.emplace_back(x, y, 1.1f);  // 10 cm above it
    normals.emplace_back(0.f, 0.f, 1.f);
  }
  std::vector<float> d;
  const SurfaceDistanceStats s_on = surfaceDistanceStats(scene, on, normals, 0.05, 0.5, &d);
  EXPECT_EQ(s_on.points, 200u);
  EXPECT_EQ(s_on.within, 200u);
  EXPECT_EQ(s_on.beyond, 0u);
  EXPECT_LT(s_on.max_m, 1e-4);
  const SurfaceDistanceStats s_off = surfaceDistanceStats(scene, off, normals, 0.05, 0.5, &d);
  EXPECT_EQ(s_off.within, 0u);
  EXPECT_EQ(s_off.beyond, 200u);
  EXPECT_DOUBLE_EQ(s_off.fraction_beyond, 1.0);
  for (float v : d) EXPECT_NEAR(v, 0.1f, 1e-4f);  // exact along the face normal
  EXPECT_NEAR(s_off.p50_m, 0.1, 1e-4);
  // Without normals (or with wrong ones) the axis rays still find an axis-aligned face.
  const SurfaceDistanceStats s_none = surfaceDistanceStats(scene, off, {}, 0.05, 0.5, &d);
  for (float v : d) EXPECT_NEAR(v, 0.1f, 1e-4f);
  EXPECT_EQ(s_none.beyond, 200u);
  const std::vector<V3f> wrong(off.size(), V3f(1.f, 0.f, 0.f));
  surfaceDistanceStats(scene, off, wrong, 0.05, 0.5, &d);
  for (float v : d) EXPECT_NEAR(v, 0.1f, 1e-4f);
  // Each side: a point 3 cm in front of the side x = 0.5 or below the bottom.
  EXPECT_NEAR(surfaceDistanceBound(scene, V3f(0.53f, 0.1f, 0.5f), V3f(1, 0, 0), 0.5f), 0.03f,
              1e-4f);
  EXPECT_NEAR(surfaceDistanceBound(scene, V3f(0.1f, -0.2f, -0.03f), V3f::Zero(), 0.5f), 0.03f,
              1e-4f);
  // Inside the box, 2 cm under the top face.
  EXPECT_NEAR(surfaceDistanceBound(scene, V3f(0.f, 0.f, 0.98f), V3f(0, 0, 1), 0.5f), 0.02f, 1e-4f);
}

TEST(SurfaceDistance, NearAnEdgeTheBoundNeverUnderestimates) {
  const RayScene scene = boxScene();
  // 3 cm from the edge x = 0.5, z = 1, diagonally out (beyond both faces' extents).
  const float r = 0.03f, c = r / std::sqrt(2.f);
  const V3f p(0.5f + c, 0.1f, 1.0f + c);
  // With the bisecting normal the -n ray passes through the edge: exact.
  EXPECT_NEAR(surfaceDistanceBound(scene, p, V3f(1, 0, 1).normalized(), 0.5f), r, 2e-4f);
  // With the top face's normal (or none) the nearest ray hit is a cube diagonal reaching the top
  // face at the edge: sqrt(3) c = 0.0367 m, more than the true 0.03, never less.
  for (const V3f& n : {V3f(0, 0, 1), V3f(0, 0, 0)}) {
    const float d = surfaceDistanceBound(scene, p, n, 0.5f);
    EXPECT_GE(d, r - 1e-4f);
    EXPECT_NEAR(d, std::sqrt(3.f) * c, 2e-4f);
  }
  // A point on the top face next to the edge, and one just beside the side face: exact.
  EXPECT_LT(surfaceDistanceBound(scene, V3f(0.499f, 0.f, 1.f), V3f(0, 0, 1), 0.5f), 1e-4f);
  EXPECT_NEAR(surfaceDistanceBound(scene, V3f(0.51f, 0.f, 0.999f), V3f(1, 0, 0), 0.5f), 0.01f,
              1e-4f);
  // Nothing within the cap: the cap, counted beyond.
  const std::vector<V3f> far{V3f(3.f, 3.f, 3.f)};
  const SurfaceDistanceStats s = surfaceDistanceStats(scene, far, {}, 10.0, 0.5);
  EXPECT_EQ(s.beyond, 1u);
  EXPECT_DOUBLE_EQ(s.max_m, 0.5);
  EXPECT_THROW(surfaceDistanceStats(scene, far, {V3f::Zero(), V3f::Zero()}, 0.05),
               std::invalid_argument);
}

TEST(SurfaceDistance, RayCastSamplesOfTheOfficeAreOnItsSurface) {
  const RayScene scene(loadWorld("office"));
  std::vector<V3f> points, normals;
  for (const RayHit& h : test::officeRayHits(scene)) {
    points.push_back(h.point);
    normals.push_back(h.normal);
  }
  ASSERT_EQ(points.size(), 9000u);
  for (const std::vector<V3f>& n : {normals, std::vector<V3f>{}}) {
    const SurfaceDistanceStats s = surfaceDistanceStats(scene, points, n, 0.05);
    EXPECT_EQ(s.within, s.points);
    EXPECT_LT(s.p99_m, 1e-3);
  }
  // Moved 10 cm along their normals, away from the surface: beyond, unless another surface is
  // that close (corners, objects on desks): most of them.
  std::vector<V3f> moved;
  for (std::size_t i = 0; i < points.size(); ++i) moved.push_back(points[i] + 0.1f * normals[i]);
  const SurfaceDistanceStats s = surfaceDistanceStats(scene, moved, normals, 0.05);
  EXPECT_GT(s.fraction_beyond, 0.8);
  EXPECT_LE(s.max_m, 0.1 + 1e-4);  // the surface they came from is 10 cm back along -n
}

TEST(ViewStats, OnePlaneTwoPlanesACornerAndObjects) {
  const World w = loadWorldFromString(
      "static:\n"
      "  - {id: 1, class: floor, primitive: box, size: [20, 20, 0.1], position: [0, 0, -0.05]}\n"
      "  - {id: 2, class: wall, primitive: box, size: [0.1, 20, 6], position: [3.05, 0, 3]}\n"
      "  - {id: 3, class: wall, primitive: box, size: [20, 0.1, 6], position: [0, 3.05, 3]}\n"
      "objects:\n"
      "  - {id: 10, class: none, primitive: box, size: [0.4, 0.4, 0.4], position: [1.2, -1.5, "
      "0.2], yaw_deg: 30}\n",
      "views");
  const RayScene scene(w);
  TSensorParams p;
  p.width = 80;
  p.height = 60;
  p.fx = p.fy = 525.0 / 8.0;
  p.cx = 39.5;
  p.cy = 29.5;
  p.noise = false;
  p.max_depth_m = 4.0;
  const RgbdSensor sensor(scene, p);
  const auto stats = [&](const Eigen::Vector3d& eye, const Eigen::Vector3d& at) {
    return viewStats(sensor.render(cameraPoseLookingAt(eye, at), 0, 0), 4.0);
  };
  // The floor alone (looking down at it, away from the walls).
  const ViewStats floor = stats({0, -4, 1.5}, {0, -5, 0});
  EXPECT_GT(floor.valid_fraction, 0.9);
  EXPECT_DOUBLE_EQ(floor.object_fraction, 0.0);
  EXPECT_LT(floor.normal_min_eig, 1e-6);
  EXPECT_LT(floor.icp_min_eig, 1e-6);
  // Floor and one wall: the normals span a plane, still 0.
  const ViewStats two = stats({1.5, -4, 1.5}, {3, -4, 0.5});
  EXPECT_GT(two.valid_fraction, 0.9);
  EXPECT_LT(two.normal_min_eig, 1e-6);
  // The corner of floor and two walls: three directions.
  const ViewStats corner = stats({1.5, 1.5, 1.5}, {3, 3, 0.5});
  EXPECT_GT(corner.normal_min_eig, 0.05);
  EXPECT_DOUBLE_EQ(corner.object_fraction, 0.0);
  // The box on the floor: an object, and its rotated faces add the third direction.
  const ViewStats box = stats({0.2, -1.5, 1.0}, {1.2, -1.5, 0.2});
  EXPECT_GT(box.object_fraction, 0.15) << box.object_fraction;
  EXPECT_GT(box.normal_min_eig, 0.01);
  // Without labels the object fraction is 0; an empty frame gives zeros.
  rasm::RgbdFrame f = sensor.render(cameraPoseLookingAt({0.2, -1.5, 1.0}, {1.2, -1.5, 0.2}), 0, 0);
  f.gt_instance = {};
  f.gt_class = {};
  EXPECT_DOUBLE_EQ(viewStats(f, 4.0).object_fraction, 0.0);
  EXPECT_DOUBLE_EQ(viewStats(rasm::RgbdFrame{}).valid_fraction, 0.0);
}
