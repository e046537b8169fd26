// Object-level precision and recall of `rasm eval classification` (ClassificationMetrics.h): a
// reported object counts when it covers an object of its class with IoU > 0.5 of their surfels.
// A small map by hand: the floor, a desk, a keyboard on it and a chair the map never segmented.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "rasm/classification/ClassificationMetrics.h"

using namespace rasm::classification;

namespace {

struct Map {
  std::vector<std::uint32_t> segment, instance;
  void add(std::size_t n, std::uint32_t seg, std::uint32_t inst) {
    segment.insert(segment.end(), n, seg);
    instance.insert(instance.end(), n, inst);
  }
};

// Instances: 1 floor (structure), 2 desk, 3 keyboard, 4 chair, 5 a shelf (not a COCO class).
const std::vector<GtClassObject> kObjects = {{1, "floor", "floor", 7.0, true},
                                             {2, "dining table", "desk_1", 1.4, false},
                                             {3, "keyboard", "keyboard_1", 0.45, false},
                                             {4, "chair", "chair_1", 0.9, false},
                                             {5, "shelf", "shelf_1", 1.8, false}};

ClassificationMetricsParams params() {
  ClassificationMetricsParams p;
  p.detectable_classes = {"dining table", "keyboard", "chair"};
  return p;
}

/// Floor segment 10 (1000 surfels), desk 20 (400), keyboard 21 (60), chair unsegmented (120),
/// shelf 40 (300), and 3 desk surfels in a segment 30 of their own (a phantom).
Map roomMap() {
  Map m;
  m.add(1000, 10, 1);
  m.add(400, 20, 2);
  m.add(60, 21, 3);
  m.add(120, 0, 4);
  m.add(300, 40, 5);
  m.add(3, 30, 2);
  return m;
}

}  // namespace

TEST(ObjectLevelMetrics, CountsWrongClassesPhantomsAndMissedObjects) {
  const Map map = roomMap();
  const std::vector<ReportedObject> reported = {{1, "dining table", {10}},  // the floor
                                                {2, "dining table", {20}},
                                                {3, "keyboard", {21}},
                                                {4, "laptop", {30}}};  // 3 surfels of the desk
  const ObjectLevelMetrics m =
      computeObjectLevelMetrics(map.segment, map.instance, reported, kObjects, params());
  ASSERT_EQ(m.per_reported.size(), 4u);
  // The floor listed as a table: it covers the floor exactly (IoU 1) but the floor is no table.
  EXPECT_DOUBLE_EQ(m.per_reported[0].iou, 1.0);
  EXPECT_EQ(m.per_reported[0].best_class, "floor");
  EXPECT_FALSE(m.per_reported[0].correct);
  EXPECT_TRUE(m.per_reported[1].correct);
  EXPECT_DOUBLE_EQ(m.per_reported[1].iou, 400.0 / 403.0);  // the phantom's 3 desk surfels missing
  EXPECT_TRUE(m.per_reported[2].correct);
  // The phantom: 3 of the desk's 403 surfels.
  EXPECT_DOUBLE_EQ(m.per_reported[3].iou, 3.0 / 403.0);
  EXPECT_FALSE(m.per_reported[3].correct);
  EXPECT_EQ(m.reported, 4u);
  EXPECT_EQ(m.reported_correct, 2u);
  EXPECT_DOUBLE_EQ(m.precision, 0.5);
  // Recall over desk, keyboard and chair (the floor is structure, the shelf no COCO class).
  EXPECT_EQ(m.objects, 3u);
  EXPECT_EQ(m.objects_found, 2u);
  EXPECT_DOUBLE_EQ(m.recall, 2.0 / 3.0);
  ASSERT_EQ(m.missed.size(), 1u);
  EXPECT_EQ(m.missed[0], "chair_1");
}

TEST(ObjectLevelMetrics, ADeskAndItsKeyboardAsOneObjectFindTheDeskOnly) {
  const Map map = roomMap();
  const std::vector<ReportedObject> reported = {{7, "dining table", {20, 21, 30}}};
  const ObjectLevelMetrics m =
      computeObjectLevelMetrics(map.segment, map.instance, reported, kObjects, params());
  // 403 desk surfels of the object's 463: IoU 403 / 463 with the desk.
  EXPECT_DOUBLE_EQ(m.per_reported[0].iou, 403.0 / 463.0);
  EXPECT_TRUE(m.per_reported[0].correct);
  EXPECT_DOUBLE_EQ(m.precision, 1.0);
  EXPECT_EQ(m.objects_found, 1u);
  EXPECT_EQ(m.missed, (std::vector<std::string>{"keyboard_1", "chair_1"}));
}

TEST(ObjectLevelMetrics, HalfAnObjectIsNotFound) {
  // A desk split in two halves of 200 surfels, each reported as a table: IoU 0.5 each, not > 0.5.
  Map map;
  map.add(200, 20, 2);
  map.add(200, 22, 2);
  const std::vector<ReportedObject> reported = {{1, "dining table", {20}},
                                                {2, "dining table", {22}}};
  const ObjectLevelMetrics m =
      computeObjectLevelMetrics(map.segment, map.instance, reported, kObjects, params());
  EXPECT_DOUBLE_EQ(m.per_reported[0].iou, 0.5);
  EXPECT_EQ(m.reported_correct, 0u);
  EXPECT_EQ(m.objects_found, 0u);
  EXPECT_DOUBLE_EQ(m.precision, 0.0);
}

TEST(ObjectLevelMetrics, EmptyAndInconsistentInputs) {
  const Map map = roomMap();
  const ObjectLevelMetrics none =
      computeObjectLevelMetrics(map.segment, map.instance, {}, kObjects, params());
  EXPECT_TRUE(std::isnan(none.precision));
  EXPECT_DOUBLE_EQ(none.recall, 0.0);
  EXPECT_THROW(
      computeObjectLevelMetrics(map.segment, map.instance, {{1, "chair", {20}}, {2, "chair", {20}}},
                                kObjects, params()),
      std::invalid_argument);
  EXPECT_THROW(computeObjectLevelMetrics({1, 2}, {1}, {}, kObjects, params()),
               std::invalid_argument);
}
