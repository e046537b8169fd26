// Segmentation metrics against ground truth (SegmentationMetrics.h, `rasm eval segmentation`) on
// hand-made label vectors whose values are worked out by hand in each test: a perfect
// segmentation, an object split in two, two objects merged into one segment, IoU just above and
// just below 0.5, void surfels, structure segments, the size and surfel-count filters, stable
// surfels only, empty and inconsistent input, and the label-stability ratio.
#include "rasm/segmentation/SegmentationMetrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using namespace rasm::segmentation;

namespace {

constexpr std::uint32_t kFloor = 1;  // structure: not an object
constexpr std::uint32_t kA = 10, kB = 11;

/// Surfel labels built by appending runs of (segment, instance).
struct Labels {
  std::vector<std::uint32_t> seg, inst;
  std::vector<std::uint8_t> stable;
  Labels& add(std::size_t n, std::uint32_t s, std::uint32_t g, bool st = true) {
    seg.insert(seg.end(), n, s);
    inst.insert(inst.end(), n, g);
    stable.insert(stable.end(), n, st ? 1 : 0);
    return *this;
  }
};

GtObject object(std::uint32_t id, double size_m = 0.3) {
  GtObject o;
  o.instance_id = id;
  o.class_id = 41;
  o.class_name = "cup";
  o.size_m = size_m;
  return o;
}

const std::vector<GtObject> kAB = {object(kA), object(kB)};

SegmentationMetricsParams params(std::size_t min_surfels = 10) {
  SegmentationMetricsParams p;
  p.min_object_surfels = min_surfels;
  return p;
}

SegmentationMetrics run(const Labels& l, const std::vector<GtObject>& objs = kAB,
                        const SegmentationMetricsParams& p = params()) {
  return computeSegmentationMetrics(l.seg, l.inst, {}, objs, p);
}

const ObjectResult& row(const SegmentationMetrics& m, std::uint32_t id) {
  for (const ObjectResult& r : m.per_object)
    if (r.object.instance_id == id) return r;
  throw std::logic_error("no row");
}

}  // namespace

TEST(SegmentationMetrics, PerfectSegmentationHasPqOne) {
  // A: 100 surfels in segment 1, B: 60 in segment 2, the floor (structure) in segment 3 with 5
  // void surfels: every object recovered with IoU 1, no FP, PQ = SQ = RQ = 1.
  Labels l;
  l.add(100, 1, kA).add(60, 2, kB).add(200, 3, kFloor).add(5, 3, 0);
  const SegmentationMetrics m = run(l);
  EXPECT_EQ(m.surfels, 365u);
  EXPECT_EQ(m.void_surfels, 5u);
  EXPECT_EQ(m.segments, 3u);
  EXPECT_EQ(m.objects_evaluated, 2u);
  EXPECT_EQ(m.recovered, 2u);
  EXPECT_DOUBLE_EQ(m.objects_recovered_fraction, 1.0);
  EXPECT_EQ(m.tp, 2u);
  EXPECT_EQ(m.fp, 0u);
  EXPECT_EQ(m.fn, 0u);
  EXPECT_DOUBLE_EQ(m.sq, 1.0);
  EXPECT_DOUBLE_EQ(m.rq, 1.0);
  EXPECT_DOUBLE_EQ(m.pq, 1.0);
  EXPECT_DOUBLE_EQ(m.segments_per_object, 1.0);
  EXPECT_EQ(m.objects_without_segment, 0u);
  EXPECT_EQ(m.undersegmented_objects, 0u);
  EXPECT_EQ(row(m, kA).best_segment, 1u);
  EXPECT_DOUBLE_EQ(row(m, kA).iou, 1.0);
  EXPECT_EQ(row(m, kB).best_segment, 2u);
}

TEST(SegmentationMetrics, ObjectSplitInTwo) {
  // A split 60 / 40 into segments 1 and 2, B whole in 3. IoU(1, A) = 60/100 = 0.6 > 0.5: A is
  // recovered; segment 2 (majority A, unmatched) is a FP. TP 2, FP 1, FN 0:
  // SQ = (0.6 + 1) / 2 = 0.8, RQ = 2 / (2 + 0.5) = 0.8, PQ = 0.64; segments per object (2 + 1)/2.
  Labels l;
  l.add(60, 1, kA).add(40, 2, kA).add(60, 3, kB);
  const SegmentationMetrics m = run(l);
  EXPECT_EQ(m.recovered, 2u);
  EXPECT_EQ(m.tp, 2u);
  EXPECT_EQ(m.fp, 1u);
  EXPECT_EQ(m.fn, 0u);
  EXPECT_DOUBLE_EQ(m.sq, 0.8);
  EXPECT_DOUBLE_EQ(m.rq, 0.8);
  EXPECT_NEAR(m.pq, 0.64, 1e-12);
  EXPECT_DOUBLE_EQ(m.segments_per_object, 1.5);
  EXPECT_EQ(row(m, kA).owned_segments, 2u);
  EXPECT_DOUBLE_EQ(row(m, kA).iou, 0.6);
  EXPECT_EQ(m.undersegmented_objects, 0u);

  // 50 / 50: IoU 0.5 is not > 0.5, A is lost and both halves are FPs. TP 1 (B), FP 2, FN 1:
  // SQ 1, RQ = 1 / (1 + 1 + 0.5) = 0.4, PQ 0.4; recovered 1/2.
  Labels h;
  h.add(50, 1, kA).add(50, 2, kA).add(60, 3, kB);
  const SegmentationMetrics m2 = run(h);
  EXPECT_EQ(m2.recovered, 1u);
  EXPECT_DOUBLE_EQ(m2.objects_recovered_fraction, 0.5);
  EXPECT_EQ(m2.fp, 2u);
  EXPECT_EQ(m2.fn, 1u);
  EXPECT_DOUBLE_EQ(m2.sq, 1.0);
  EXPECT_DOUBLE_EQ(m2.rq, 0.4);
  EXPECT_DOUBLE_EQ(m2.pq, 0.4);
  EXPECT_FALSE(row(m2, kA).recovered);
  EXPECT_DOUBLE_EQ(row(m2, kA).iou, 0.5);
}

TEST(SegmentationMetrics, TwoObjectsMergedIntoOneSegment) {
  // A (100) and B (60) both in segment 1. IoU(1, A) = 100/160 = 0.625: A recovered;
  // IoU(1, B) = 60/160 = 0.375: B lost. TP 1, FP 0 (segment 1 is matched), FN 1:
  // SQ 0.625, RQ = 1 / 1.5, PQ = 0.625 / 1.5. Both share the segment: B's 60 >= 0.5 * 100 and
  // A's 100 >= 0.5 * 60, so both are under-segmented. Segment 1 is owned by A; B owns none.
  Labels l;
  l.add(100, 1, kA).add(60, 1, kB);
  const SegmentationMetrics m = run(l);
  EXPECT_EQ(m.recovered, 1u);
  EXPECT_EQ(m.tp, 1u);
  EXPECT_EQ(m.fp, 0u);
  EXPECT_EQ(m.fn, 1u);
  EXPECT_DOUBLE_EQ(m.sq, 0.625);
  EXPECT_DOUBLE_EQ(m.rq, 1.0 / 1.5);
  EXPECT_DOUBLE_EQ(m.pq, 0.625 / 1.5);
  EXPECT_EQ(m.undersegmented_objects, 2u);
  EXPECT_DOUBLE_EQ(m.undersegmented_fraction, 1.0);
  EXPECT_TRUE(row(m, kA).undersegmented);
  EXPECT_EQ(row(m, kA).merged_with, kB);
  EXPECT_EQ(row(m, kB).merged_with, kA);
  EXPECT_EQ(row(m, kB).dominant_segment, 1u);
  EXPECT_DOUBLE_EQ(m.segments_per_object, 1.0);
  EXPECT_EQ(m.objects_without_segment, 1u);

  // A small leak is not under-segmentation: 100 of A and 20 floor surfels in segment 1
  // (20 < 0.5 * 100), B whole in segment 2. An object merged into the floor's segment is:
  // B (60) in the floor's segment 3 with 200 floor surfels.
  Labels k;
  k.add(100, 1, kA).add(20, 1, kFloor).add(60, 3, kB).add(200, 3, kFloor);
  const SegmentationMetrics m2 = run(k);
  EXPECT_FALSE(row(m2, kA).undersegmented);
  EXPECT_TRUE(row(m2, kB).undersegmented);
  EXPECT_EQ(row(m2, kB).merged_with, kFloor);
  EXPECT_EQ(m2.undersegmented_objects, 1u);
  EXPECT_EQ(m2.fp, 0u);  // segment 3 belongs to the floor: ignored, not a FP
  EXPECT_EQ(m2.fn, 1u);

  // A share below a quarter of the object does not make it under-segmented: A (100) with 1
  // surfel in the floor's segment 3 and 99 unsegmented (its dominant segment is 3, but 1 < 25).
  // B (100) split 40 / 30 / 30 with the 30 of segment 5 merged with 40 floor surfels: 30 >= 25
  // and 40 >= 0.5 * 30, so B is under-segmented although its dominant segment 4 is clean.
  Labels j;
  j.add(1, 3, kA).add(99, 0, kA).add(200, 3, kFloor);
  j.add(40, 4, kB).add(30, 6, kB).add(30, 5, kB).add(40, 5, kFloor);
  const SegmentationMetrics m3 = run(j);
  EXPECT_EQ(row(m3, kA).dominant_segment, 3u);
  EXPECT_FALSE(row(m3, kA).undersegmented);
  EXPECT_EQ(row(m3, kB).dominant_segment, 4u);
  EXPECT_TRUE(row(m3, kB).undersegmented);
  EXPECT_EQ(row(m3, kB).merged_with, kFloor);
  EXPECT_EQ(m3.undersegmented_objects, 1u);
  // B: IoU(4, B) = 0.4, not recovered; segments 4 and 6 are FPs (majority B), segment 5's
  // majority is the floor (40 > 30): ignored. TP 0, FP 2, FN 2: RQ 0, PQ 0.
  EXPECT_EQ(m3.fp, 2u);
  EXPECT_EQ(m3.fn, 2u);
  EXPECT_DOUBLE_EQ(m3.pq, 0.0);
}

TEST(SegmentationMetrics, IouJustAboveAndBelowHalf) {
  // A (100) in segment 1 with k floor surfels: IoU = 100 / (100 + k).
  const auto iouWith = [](std::size_t k, std::size_t void_n) {
    Labels l;
    l.add(100, 1, kA).add(k, 1, kFloor).add(void_n, 1, 0).add(60, 2, kB);
    return run(l);
  };
  const SegmentationMetrics above = iouWith(99, 0);  // 100/199 = 0.5025
  EXPECT_TRUE(row(above, kA).recovered);
  EXPECT_DOUBLE_EQ(row(above, kA).iou, 100.0 / 199.0);
  EXPECT_EQ(above.recovered, 2u);
  const SegmentationMetrics equal = iouWith(100, 0);  // exactly 0.5: not > 0.5
  EXPECT_FALSE(row(equal, kA).recovered);
  EXPECT_EQ(equal.recovered, 1u);
  const SegmentationMetrics below = iouWith(101, 0);  // 100/201 = 0.4975
  EXPECT_FALSE(row(below, kA).recovered);
  EXPECT_EQ(below.fn, 1u);
  EXPECT_EQ(below.fp, 0u);  // segment 1's majority is the floor (101 > 100): ignored
  // Void surfels in a segment do not count: 99 floor + 1000 void is still 0.5025.
  const SegmentationMetrics voided = iouWith(99, 1000);
  EXPECT_TRUE(row(voided, kA).recovered);
  EXPECT_DOUBLE_EQ(row(voided, kA).iou, 100.0 / 199.0);
  EXPECT_EQ(voided.void_surfels, 1000u);

  // Unsegmented surfels of the object count against it: 51 in segment 1 and 49 with segment 0
  // gives 0.51 (recovered), 50 / 50 gives 0.5 (not).
  Labels u1, u2;
  u1.add(51, 1, kA).add(49, 0, kA).add(60, 2, kB);
  u2.add(50, 1, kA).add(50, 0, kA).add(60, 2, kB);
  EXPECT_TRUE(row(run(u1), kA).recovered);
  EXPECT_EQ(row(run(u1), kA).unsegmented, 49u);
  EXPECT_FALSE(row(run(u2), kA).recovered);
}

TEST(SegmentationMetrics, NothingSegmentedIsZeroNotUndefined) {
  // The baseline before segmentation exists: every surfel has segment 0.
  Labels l;
  l.add(100, 0, kA).add(60, 0, kB).add(300, 0, kFloor);
  const SegmentationMetrics m = run(l);
  EXPECT_EQ(m.objects_evaluated, 2u);
  EXPECT_EQ(m.segments, 0u);
  EXPECT_DOUBLE_EQ(m.objects_recovered_fraction, 0.0);
  EXPECT_DOUBLE_EQ(m.pq, 0.0);
  EXPECT_DOUBLE_EQ(m.sq, 0.0);
  EXPECT_DOUBLE_EQ(m.rq, 0.0);
  EXPECT_EQ(m.fn, 2u);
  EXPECT_EQ(m.undersegmented_objects, 0u);
  EXPECT_EQ(m.objects_without_segment, 2u);
  EXPECT_TRUE(std::isnan(m.segments_per_object));  // no object owns a segment
  EXPECT_EQ(row(m, kA).best_segment, 0u);
  EXPECT_EQ(row(m, kA).dominant_segment, 0u);
}

TEST(SegmentationMetrics, SizeAndSurfelCountFilters) {
  // C is 8 cm (not > 10 cm): no row, its segment is not a FP. D has 5 surfels (< 10): a row,
  // not evaluated, not a FN. Floor split in three segments: no FP.
  const std::uint32_t kC = 12, kD = 13;
  const std::vector<GtObject> objs = {object(kA), object(kC, 0.08), object(kD)};
  Labels l;
  l.add(100, 1, kA)
      .add(30, 2, kC)
      .add(5, 3, kD)
      .add(100, 4, kFloor)
      .add(100, 5, kFloor)
      .add(100, 6, kFloor);
  const SegmentationMetrics m = run(l, objs);
  EXPECT_EQ(m.objects_listed, 3u);
  EXPECT_EQ(m.objects_over_size, 2u);
  EXPECT_EQ(m.objects_unseen, 1u);
  EXPECT_EQ(m.objects_evaluated, 1u);
  EXPECT_EQ(m.per_object.size(), 2u);
  EXPECT_FALSE(row(m, kD).evaluated);
  EXPECT_EQ(m.tp, 1u);
  EXPECT_EQ(m.fp, 0u);
  EXPECT_EQ(m.fn, 0u);
  EXPECT_DOUBLE_EQ(m.pq, 1.0);
}

TEST(SegmentationMetrics, StableOnly) {
  // A: 60 stable in segment 1, 40 unstable in segment 2. All surfels: IoU 0.6 and a FP;
  // stable only: IoU 1, PQ 1.
  Labels l;
  l.add(60, 1, kA, true).add(40, 2, kA, false).add(60, 3, kB, true);
  SegmentationMetricsParams p = params();
  const SegmentationMetrics all = computeSegmentationMetrics(l.seg, l.inst, l.stable, kAB, p);
  EXPECT_EQ(all.fp, 1u);
  p.stable_only = true;
  const SegmentationMetrics st = computeSegmentationMetrics(l.seg, l.inst, l.stable, kAB, p);
  EXPECT_EQ(st.surfels, 120u);
  EXPECT_EQ(st.fp, 0u);
  EXPECT_DOUBLE_EQ(st.pq, 1.0);
  EXPECT_THROW(computeSegmentationMetrics(l.seg, l.inst, {}, kAB, p), std::invalid_argument);
}

TEST(SegmentationMetrics, EmptyAndInconsistentInputAreErrors) {
  EXPECT_THROW(computeSegmentationMetrics({}, {}, {}, kAB), std::invalid_argument);
  EXPECT_THROW(computeSegmentationMetrics({1, 2}, {10}, {}, kAB), std::invalid_argument);
  EXPECT_THROW(computeSegmentationMetrics({1}, {10}, {1, 1}, kAB), std::invalid_argument);
  EXPECT_THROW(computeSegmentationMetrics({1}, {10}, {}, {object(0)}), std::invalid_argument);
  EXPECT_THROW(computeSegmentationMetrics({1}, {10}, {}, {object(kA), object(kA)}),
               std::invalid_argument);
  SegmentationMetricsParams p;
  p.iou_threshold = 0.3;  // matches would not be unique
  EXPECT_THROW(computeSegmentationMetrics({1}, {10}, {}, kAB, p), std::invalid_argument);
  Labels unstable;
  unstable.add(10, 1, kA, false);
  p = params();
  p.stable_only = true;
  EXPECT_THROW(computeSegmentationMetrics(unstable.seg, unstable.inst, unstable.stable, kAB, p),
               std::invalid_argument);
}

TEST(SegmentationMetrics, NoObjectsGivesUndefinedRatios) {
  // Only structure in view: nothing to evaluate, every ratio NaN (null in JSON).
  Labels l;
  l.add(100, 1, kFloor);
  const SegmentationMetrics m = run(l);
  EXPECT_EQ(m.objects_evaluated, 0u);
  EXPECT_EQ(m.objects_unseen, 2u);
  EXPECT_TRUE(std::isnan(m.objects_recovered_fraction));
  EXPECT_TRUE(std::isnan(m.pq));
  EXPECT_TRUE(std::isnan(m.segments_per_object));
}

TEST(SegmentationMetrics, LabelChangesPerStableSurfel) {
  EXPECT_DOUBLE_EQ(labelChangesPerStableSurfel(10, 1000), 0.01);
  EXPECT_DOUBLE_EQ(labelChangesPerStableSurfel(0, 5), 0.0);
  EXPECT_TRUE(std::isnan(labelChangesPerStableSurfel(3, 0)));
}
