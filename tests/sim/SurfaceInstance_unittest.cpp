// The ground-truth instance of the nearest world surface (SurfaceInstance.h, `rasm eval
// segmentation`): exact distances on a unit box (also beside an edge, where the ray-cast bound
// of SurfaceDistance.h overestimates), nothing within max_dist_m, points sampled on known objects
// of the shipped office (a mug on a desk, a box on the floor, the book stack on a shelf) get
// those objects' instances and classes, ray-cast samples of the whole office agree with the
// object the ray hit, and the instances' structure flags and sizes.
#include "rasm/sim/SurfaceInstance.h"

#include <gtest/gtest.h>

#include "sim/OfficeRayHits.h"

#include <cmath>
#include <random>

#include "rasm/models/ClassVocabulary.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/World.h"

using namespace rasm::sim;
using namespace rasm::models;
using V3f = Eigen::Vector3f;

namespace {

/// Points on the visible surface of instance `id`: the first hits of `n_rays` rays from random
/// eyes around it (aimed at random points of its bounds) that land on it.
std::vector<V3f> visibleSamples(const RayScene& scene, std::uint16_t id, int n_rays,
                                std::mt19937& rng) {
  const int idx = scene.world().indexOfInstance(id);
  const Eigen::AlignedBox3f b = scene.objectBounds(idx);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  std::vector<V3f> out;
  for (int i = 0; i < n_rays; ++i) {
    // An eye 0.4-0.8 m from the centre, above the floor; a ray at a random point of the bounds.
    V3f dir(u(rng), u(rng), 0.5f * u(rng) + 0.3f);
    dir.normalize();
    const V3f eye = b.center() + (0.6f + 0.2f * u(rng)) * dir;
    if (eye.z() < 0.05f) continue;
    const V3f target = b.center() + 0.5f * b.sizes().cwiseProduct(V3f(u(rng), u(rng), u(rng)));
    const RayHit h = scene.castRay(eye, (target - eye).normalized());
    if (h.hit && h.object == idx) out.push_back(h.point);
  }
  return out;
}

}  // namespace

TEST(SurfaceInstance, ExactDistanceOnABoxAndNothingBeyondMaxDist) {
  const RayScene scene(loadWorldFromString(
      "objects:\n  - {id: 7, class: box, primitive: box, size: [1, 1, 1], position: [0, 0, 0.5]}\n",
      "box"));
  const SurfaceInstanceQuery q(scene);
  const NearestSurface top = q.nearest(V3f(0.1f, 0.2f, 1.2f), 0.5f);
  EXPECT_EQ(top.object, 0);
  EXPECT_EQ(top.instance_id, 7);
  EXPECT_EQ(top.class_id, classIdFromName("box"));
  EXPECT_NEAR(top.distance_m, 0.2f, 1e-5f);
  EXPECT_TRUE(top.point.isApprox(V3f(0.1f, 0.2f, 1.0f), 1e-5f));
  // Beside the edge x = 0.5, z = 1, diagonally out: the nearest point is on the edge.
  const NearestSurface edge = q.nearest(V3f(0.6f, 0.f, 1.1f), 0.5f);
  EXPECT_NEAR(edge.distance_m, std::sqrt(0.02f), 1e-5f);
  EXPECT_TRUE(edge.point.isApprox(V3f(0.5f, 0.f, 1.f), 1e-5f));
  // Inside the box, 2 cm under the top face.
  EXPECT_NEAR(q.nearest(V3f(0.f, 0.f, 0.98f), 0.5f).distance_m, 0.02f, 1e-5f);
  // Nothing within max_dist_m; non-finite points; bad max_dist_m.
  const NearestSurface none = q.nearest(V3f(0.f, 0.f, 1.2f), 0.05f);
  EXPECT_EQ(none.object, -1);
  EXPECT_EQ(none.instance_id, 0);
  EXPECT_EQ(q.nearest(V3f(NAN, 0.f, 0.f), 0.5f).object, -1);
  EXPECT_THROW(q.nearest(V3f::Zero(), 0.f), std::invalid_argument);
  // The batch form gives the same answers.
  const std::vector<V3f> pts{V3f(0.1f, 0.2f, 1.2f), V3f(0.f, 0.f, 1.2f)};
  const auto r = q.nearest(pts, 0.1f);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].instance_id, 0);  // 0.2 m > 0.1 m
  EXPECT_EQ(r[1].instance_id, 0);
  EXPECT_EQ(q.nearest(pts, 0.5f)[0].instance_id, 7);
}

TEST(SurfaceInstance, PointsOnKnownOfficeObjectsGetTheirInstance) {
  const RayScene scene(loadWorld("office"));
  const SurfaceInstanceQuery q(scene);
  std::mt19937 rng(5);
  // 112: the red mug on desk 1; 170: the box in the south-east corner (on the floor, under box
  // 171); 161: a book between two others on shelf 1; 10: desk 1 itself.
  for (const std::uint16_t id : {112, 170, 161, 10}) {
    const std::vector<V3f> pts = visibleSamples(scene, id, 4000, rng);
    ASSERT_GE(pts.size(), 100u) << "instance " << id;
    const int cls = scene.world().objects[std::size_t(scene.world().indexOfInstance(id))].class_id;
    std::size_t same = 0;
    for (const V3f& p : pts) {
      const NearestSurface s = q.nearest(p, 0.05f);
      EXPECT_LT(s.distance_m, 1e-3f);
      if (s.instance_id == id) {
        ++same;
        EXPECT_EQ(s.class_id, cls);
      }
    }
    // Only points on a contact line (mug base on the desk) may tie with the other surface.
    EXPECT_GE(double(same), 0.99 * double(pts.size())) << "instance " << id;
  }
  // A point in the middle of the room is further than 5 cm from everything.
  EXPECT_EQ(q.nearest(V3f(4.f, 3.f, 1.5f), 0.05f).object, -1);
}

TEST(SurfaceInstance, RayCastSamplesOfTheOfficeAgreeWithTheHitObject) {
  const RayScene scene(loadWorld("office"));
  const SurfaceInstanceQuery q(scene);
  std::vector<V3f> points;
  std::vector<int> hit_object;
  for (const RayHit& h : test::officeRayHits(scene)) {
    points.push_back(h.point);
    hit_object.push_back(h.object);
  }
  const std::vector<NearestSurface> r = q.nearest(points, 0.05f);
  std::size_t agree = 0;
  for (std::size_t i = 0; i < points.size(); ++i) agree += r[i].object == hit_object[i] ? 1 : 0;
  EXPECT_GE(double(agree), 0.995 * double(points.size())) << agree << " of " << points.size();
}

TEST(SurfaceInstance, WorldInstancesFlagStructureAndMeasureSizes) {
  const World w = loadWorld("office");
  const std::vector<WorldInstanceInfo> inst = worldInstances(w);
  ASSERT_EQ(inst.size(), w.objects.size());
  const auto find = [&](std::uint16_t id) -> const WorldInstanceInfo& {
    return inst[std::size_t(w.indexOfInstance(id))];
  };
  EXPECT_TRUE(find(1).is_structure);    // floor
  EXPECT_TRUE(find(3).is_structure);    // wall_south
  EXPECT_TRUE(find(7).is_structure);    // door
  EXPECT_FALSE(find(10).is_structure);  // desk_1 (furniture)
  EXPECT_TRUE(find(10).is_static);
  EXPECT_EQ(find(10).name, "desk_1");
  EXPECT_FALSE(find(112).is_structure);
  EXPECT_EQ(find(112).class_name, "cup");
  EXPECT_EQ(find(200).class_name, "none");  // unknown clutter is an object too
  // Box 170: 0.5 x 0.4 x 0.4 m. Mouse 113: sphere r 0.03 scaled 1.8 in y: 0.108 m.
  EXPECT_NEAR(find(170).size_m, 0.5, 1e-5);
  EXPECT_NEAR(find(170).extent_m.y(), 0.4, 1e-5);
  EXPECT_NEAR(find(113).size_m, 0.108, 1e-3);
}
