// The object layer over the segments (ObjectMap.h): which segments make one object, its id over
// the run, its class histogram (the Bayes update of IV in log-odds), existence probability,
// frames and boxes.
#include <gtest/gtest.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <set>

#include "rasm/classification/ObjectMap.h"
#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

using namespace rasm;
using namespace rasm::classification;

namespace {

constexpr int kChair = 57, kDiningTable = 61;  // COCO ids of the map's class list

/// A segment of `surfels` surfels filling the axis-aligned box [lo, hi] (world, m), upright axes.
segmentation::SegmentStats segmentBox(std::uint32_t id, const Eigen::Vector3d& lo,
                                      const Eigen::Vector3d& hi, int surfels = 2000) {
  segmentation::SegmentStats s;
  s.id = id;
  s.surfels = surfels;
  s.bbox_min = lo;
  s.bbox_max = hi;
  s.centroid = 0.5 * (lo + hi);
  s.extents = hi - lo;
  s.upright_axes = Eigen::Matrix3d::Identity();
  s.upright_extents = hi - lo;
  s.upright_centre = 0.5 * (lo + hi);
  return s;
}

/// A detection of `class_id` going to `segment` with p_d and IoU weight.
struct Hit {
  std::uint32_t segment;
  int class_id;
  float p_detection;
  float iou;
  std::vector<std::uint32_t> pieces = {};  ///< other segments mostly inside its box
};

/// One detector result on `frame`: the segments it saw with their pixels, and its detections.
DetectorView view(std::size_t frame, std::vector<std::pair<std::uint32_t, int>> seen,
                  const std::vector<Hit>& hits, int detector = 0) {
  DetectorView v;
  v.frame = frame;
  v.detector = detector;
  v.segment_pixels = std::move(seen);
  for (const Hit& h : hits) {
    v.detected_segments.push_back(h.segment);
    v.evidence.push_back({h.segment, h.class_id, h.p_detection, h.iou});
    for (const std::uint32_t piece : h.pieces) v.co_detected.emplace_back(h.segment, piece);
  }
  return v;
}

/// The posterior after n detections at p_d with IoU weight w (double precision).
double posterior(int n, double p_d, double w) {
  return 1.0 / (1.0 + std::exp(-n * w * std::log(p_d / (1 - p_d))));
}

std::vector<const MapObject*> reported(const ObjectMap& m) {
  std::vector<const MapObject*> out;
  for (const MapObject& o : m.objects())
    if (o.verdict == ObjectVerdict::Object) out.push_back(&o);
  return out;
}

/// How many objects an ObjectMap with `params` reports once `feed` fed it and `table` updated it.
template <class Feed>
std::size_t reportedWith(const TObjectParams& params, const Feed& feed,
                         const std::vector<segmentation::SegmentStats>& table) {
  ObjectMap m(params, TClassificationParams{});
  feed(m);
  m.update(table);
  return reported(m).size();
}

// One quantisation step per update (ClassEvidence.h), a quarter of it in p.
constexpr double kPerUpdateP = (1.0 / 2048 + 1e-6) / 4;

}  // namespace

// A 1.6 x 0.8 m desk fell apart at its fold into the top (segment 1) and a side panel (segment 2)
// whose boxes touch; both were named "dining table" by two detections each, and the boxes of
// the detections of the top held the panel. One object, one id, the histogram of all four
// detections, the union of the boxes.
TEST(ObjectMap, TwoSegmentsOfOneDeskAreOneObject) {
  ObjectMap m;
  const std::vector<segmentation::SegmentStats> table = {
      segmentBox(1, {0.0, 0.0, 0.72}, {1.6, 0.8, 0.75}, 6000),
      segmentBox(2, {1.57, 0.0, 0.0}, {1.60, 0.8, 0.72}, 1500)};
  m.addDetectorView(view(10, {{1, 9000}, {2, 2500}}, {{1, kDiningTable, 0.9f, 0.8f, {2}}}));
  m.addDetectorView(view(15, {{1, 8000}, {2, 2000}}, {{2, kDiningTable, 0.9f, 0.6f}}));
  m.addDetectorView(view(20, {{1, 7000}, {2, 1800}}, {{1, kDiningTable, 0.9f, 0.7f, {2}}}));
  m.addDetectorView(view(25, {{1, 7000}, {2, 1900}}, {{2, kDiningTable, 0.9f, 0.7f}}));
  m.update(table);
  ASSERT_EQ(m.objects().size(), 1u);
  const MapObject& desk = m.objects()[0];
  EXPECT_EQ(desk.id, 1);
  EXPECT_EQ(desk.segments, (std::vector<std::uint32_t>{1, 2}));
  EXPECT_EQ(desk.verdict, ObjectVerdict::Object);
  EXPECT_EQ(desk.best.class_id, kDiningTable);
  // L = logit(0.9) (0.8 + 0.6 + 0.7 + 0.7): the four detections, each once.
  const double p = 1.0 / (1.0 + std::exp(-std::log(9.0) * 2.8));
  EXPECT_NEAR(desk.best.probability, p, 4 * kPerUpdateP + 1e-6);
  EXPECT_EQ(desk.detections, 4);
  // Seen and detected in all 4 frames: existence (4 + 1) / (4 + 2).
  EXPECT_EQ(desk.views, 4);
  EXPECT_EQ(desk.views_detected, 4);
  EXPECT_NEAR(desk.existence_probability, 5.0 / 6.0, 1e-12);
  EXPECT_EQ(desk.first_seen_frame, 10u);
  EXPECT_EQ(desk.last_seen_frame, 25u);
  EXPECT_EQ(desk.frames_seen, 4);
  EXPECT_EQ(desk.frames_detected, 4);
  EXPECT_EQ(desk.surfels, 7500);
  EXPECT_TRUE(desk.bbox_min.isApprox(Eigen::Vector3d(0, 0, 0)));
  EXPECT_TRUE(desk.bbox_max.isApprox(Eigen::Vector3d(1.6, 0.8, 0.75)));
  EXPECT_TRUE(desk.box_extents_m.isApprox(Eigen::Vector3d(1.6, 0.8, 0.75), 1e-9));
  EXPECT_TRUE(desk.box_centre.isApprox(Eigen::Vector3d(0.8, 0.4, 0.375), 1e-9));
  EXPECT_EQ(m.objectOfSegment(1), m.objectOfSegment(2));
}

// Two desks side by side (their tops touch), each named "dining table" by detections of its own
// boxes that held the other in one of 4 detections (a view along the row): two objects (the
// office's desk_3 and desk_4 were listed as one object while the contact of the boxes alone
// linked segments). With link_min_codetection_fraction 0 (contact alone) they are one; once the
// boxes held both in half the detections of each, one.
TEST(ObjectMap, TwoDesksSideBySideStayTwoObjects) {
  const std::vector<segmentation::SegmentStats> table = {
      segmentBox(1, {0.0, 0.0, 0.72}, {1.6, 0.8, 0.75}, 6000),
      segmentBox(2, {1.6, 0.0, 0.72}, {3.2, 0.8, 0.75}, 6000)};
  const auto feed = [](ObjectMap& m) {
    for (std::size_t f = 0; f < 3; ++f)
      m.addDetectorView(view(5 * f, {{1, 9000}, {2, 9000}},
                             {{1, kDiningTable, 0.9f, 0.8f}, {2, kDiningTable, 0.9f, 0.8f}}));
    m.addDetectorView(view(20, {{1, 9000}, {2, 4000}}, {{1, kDiningTable, 0.9f, 0.8f, {2}}}));
  };
  ObjectMap m;
  feed(m);
  m.update(table);
  ASSERT_EQ(reported(m).size(), 2u);
  EXPECT_NE(m.objectOfSegment(1)->id, m.objectOfSegment(2)->id);
  TObjectParams contact;
  contact.link_min_codetection_fraction = 0.0;
  EXPECT_EQ(reportedWith(contact, feed, table), 1u);
  // 1 of desk 2's 3 detections held both: below half. One more such view: 2 of 3, one object.
  m.addDetectorView(view(25, {{1, 9000}, {2, 4000}}, {{1, kDiningTable, 0.9f, 0.8f, {2}}}));
  m.update(table);
  EXPECT_EQ(reported(m).size(), 1u);
}

// The office's north monitor: the first pass saw the right half of its screen (segment 1), the
// second pass, 20 s later, the whole monitor with the wall behind it (segment 2); the segments
// never merged and no detection held both (they were never in view together). The first box lies
// inside the second: one object. Two monitors side by side on one desk, each with its own
// detections, touch but do not overlap: two. A desk top that the boxes of the monitor standing
// on it named "tv" (gen1001's desk named "keyboard") contains the monitor's box, but the two
// were seen together and no detection held the top: two.
TEST(ObjectMap, PiecesSeenOnDifferentVisitsOneInsideTheOtherAreOneObject) {
  constexpr int kTv = 63;  // COCO "tv"
  const std::vector<segmentation::SegmentStats> table = {
      segmentBox(1, {1.46, 5.55, 0.82}, {1.78, 5.61, 1.20}, 600),
      segmentBox(2, {1.22, 5.55, 0.84}, {1.80, 6.00, 1.32}, 4800),
      segmentBox(3, {2.00, 5.55, 0.84}, {2.55, 5.61, 1.20}, 3000),
      segmentBox(4, {2.55, 5.55, 0.84}, {3.10, 5.61, 1.20}, 3000),
      segmentBox(5, {4.00, 4.80, 0.70}, {5.60, 5.60, 1.25}, 9000),   // desk top (and wall)
      segmentBox(6, {4.50, 5.40, 0.75}, {5.05, 5.46, 1.10}, 2500)};  // the monitor on it
  const auto feed = [](ObjectMap& m) {
    for (std::size_t f = 0; f < 4; ++f)
      m.addDetectorView(view(500 + 5 * f, {{1, 5000}}, {{1, kTv, 0.9f, 0.8f}}));
    for (std::size_t f = 0; f < 4; ++f)
      m.addDetectorView(view(1700 + 5 * f, {{2, 9000}}, {{2, kTv, 0.9f, 0.8f}}));
    for (std::size_t f = 0; f < 4; ++f)
      m.addDetectorView(
          view(900 + 5 * f, {{3, 9000}, {4, 9000}}, {{3, kTv, 0.9f, 0.8f}, {4, kTv, 0.9f, 0.8f}}));
    for (std::size_t f = 0; f < 4; ++f)
      m.addDetectorView(
          view(1200 + 5 * f, {{5, 20000}, {6, 6000}}, {{f % 2 ? 5u : 6u, kTv, 0.9f, 0.8f}}));
  };
  ObjectMap m;
  feed(m);
  m.update(table);
  ASSERT_EQ(reported(m).size(), 5u);
  EXPECT_EQ(m.objectOfSegment(1), m.objectOfSegment(2));
  EXPECT_NE(m.objectOfSegment(3), m.objectOfSegment(4));
  EXPECT_NE(m.objectOfSegment(5), m.objectOfSegment(6));
  // (the first box, grown by 1 cm: 0.34 x 0.08 x 0.40 m, of which 0.34 x 0.08 x 0.38 inside)
  TObjectParams off;
  off.link_min_box_containment = 0.0;
  EXPECT_EQ(reportedWith(off, feed, table), 6u);
  TObjectParams strict;
  strict.link_min_box_containment = 0.97;  // 0.38 / 0.40 = 0.95 of the first box is inside
  EXPECT_EQ(reportedWith(strict, feed, table), 6u);
}

// A piece of the floor under a desk that the desk's boxes named "dining table" (the office:
// 2.9 x 1.5 m, 9 cm between its percentiles, 27 detections) lies in the floor's plane: part of
// the floor (structure), not an object. The desk's top (0.73 m above it) and a book lying on the
// floor (smaller than structure_piece_min_extent_m) stay objects; so does the piece when no
// structure segment is in the table.
TEST(ObjectMap, APieceOfTheFloorNamedATableIsStructure) {
  constexpr int kBook = 74;
  std::vector<segmentation::SegmentStats> table = {
      segmentBox(1, {0.0, 0.0, -0.01}, {7.0, 5.0, 0.01}, 40000),  // the floor
      segmentBox(2, {1.0, 1.0, 0.0}, {3.9, 2.5, 0.087}, 5000),    // the floor piece
      segmentBox(3, {1.0, 1.0, 0.715}, {2.6, 1.8, 0.745}, 6000),  // a desk's top
      segmentBox(4, {5.0, 3.0, 0.0}, {5.3, 3.2, 0.03}, 300)};     // a book on the floor
  ObjectMap m;
  for (std::size_t f = 0; f < 5; ++f)
    m.addDetectorView(view(
        5 * f, {{1, 20000}, {2, 5000}, {3, 9000}, {4, 400}},
        {{2, kDiningTable, 0.9f, 0.5f}, {3, kDiningTable, 0.9f, 0.8f}, {4, kBook, 0.9f, 0.8f}}));
  m.update(table);
  EXPECT_EQ(m.objectOfSegment(2)->verdict, ObjectVerdict::Structure);
  EXPECT_EQ(m.objectOfSegment(3)->verdict, ObjectVerdict::Object);
  EXPECT_EQ(m.objectOfSegment(4)->verdict, ObjectVerdict::Object);
  // 6 cm above the floor's plane (beyond structure_piece_max_offset_m 5 cm): an object.
  table[1] = segmentBox(2, {1.0, 1.0, 0.03}, {3.9, 2.5, 0.09}, 5000);
  m.update(table);
  EXPECT_EQ(m.objectOfSegment(2)->verdict, ObjectVerdict::Object);
  // Without the floor segment in the table nothing says it is the floor.
  table[1] = segmentBox(2, {1.0, 1.0, 0.0}, {3.9, 2.5, 0.087}, 5000);
  table.erase(table.begin());
  m.update(table);
  EXPECT_EQ(m.objectOfSegment(2)->verdict, ObjectVerdict::Object);
}

// Two chairs 1.5 m apart, both confidently "chair": two objects with two ids. A third piece of
// chair 3 cm from the second chair (its backrest) joins it; a dining table touching the first
// chair does not join it (another class).
TEST(ObjectMap, TwoChairsFarApartStayTwoObjects) {
  ObjectMap m;
  const std::vector<segmentation::SegmentStats> table = {
      segmentBox(1, {0.0, 0.0, 0.0}, {0.5, 0.5, 0.9}),
      segmentBox(2, {2.0, 0.0, 0.0}, {2.5, 0.5, 0.5}),
      segmentBox(3, {2.0, 0.53, 0.5}, {2.5, 0.6, 0.9}),
      segmentBox(4, {0.5, 0.0, 0.0}, {1.7, 0.8, 0.75})};
  for (std::size_t f = 0; f < 3; ++f)
    m.addDetectorView(view(5 * f, {{1, 5000}, {2, 3000}, {3, 2000}, {4, 9000}},
                           {{1, kChair, 0.9f, 0.8f},
                            {2, kChair, 0.9f, 0.7f, {3}},
                            {3, kChair, 0.9f, 0.5f},
                            {4, kDiningTable, 0.9f, 0.8f}}));
  m.update(table);
  const auto objects = reported(m);
  ASSERT_EQ(objects.size(), 3u);
  const MapObject *chair1 = m.objectOfSegment(1), *chair2 = m.objectOfSegment(2),
                  *table4 = m.objectOfSegment(4);
  ASSERT_TRUE(chair1 && chair2 && table4);
  EXPECT_EQ(chair1->segments, (std::vector<std::uint32_t>{1}));
  EXPECT_EQ(chair2->segments, (std::vector<std::uint32_t>{2, 3}));
  EXPECT_EQ(table4->segments, (std::vector<std::uint32_t>{4}));
  EXPECT_EQ(chair1->best.class_id, kChair);
  EXPECT_EQ(chair2->best.class_id, kChair);
  EXPECT_EQ(table4->best.class_id, kDiningTable);
  EXPECT_NE(chair1->id, chair2->id);
  std::set<int> ids;
  for (const MapObject* o : objects) ids.insert(o->id);
  EXPECT_EQ(ids.size(), 3u);
  // The backrest is 3 cm from the seat: joined with link_max_gap_m = 5 cm, not with 2 cm.
  TObjectParams tight;
  tight.link_max_gap_m = 0.02;
  const auto seat_and_backrest = [](ObjectMap& strict) {
    for (std::size_t f = 0; f < 3; ++f)
      strict.addDetectorView(view(5 * f, {{2, 3000}, {3, 2000}},
                                  {{2, kChair, 0.9f, 0.7f, {3}}, {3, kChair, 0.9f, 0.5f}}));
  };
  EXPECT_EQ(reportedWith(tight, seat_and_backrest, table), 2u);
}

// The id of an object survives: a new segment joining it, the segmentation merging its segments
// and renumbering them densely. A new object gets a new id; ids are never reused.
TEST(ObjectMap, AnObjectKeepsItsIdWhenSegmentsJoinMergeAndAreRenumbered) {
  ObjectMap m;
  std::vector<segmentation::SegmentStats> table = {
      segmentBox(3, {5.0, 5.0, 0.0}, {5.5, 5.5, 0.9}),           // a chair
      segmentBox(4, {0.0, 0.0, 0.72}, {1.6, 0.8, 0.75}, 6000)};  // a desk's top
  m.addDetectorView(
      view(10, {{3, 4000}, {4, 9000}}, {{3, kChair, 0.9f, 0.8f}, {4, kDiningTable, 0.9f, 0.8f}}));
  m.update(table);
  const int chair_id = m.objectOfSegment(3)->id, desk_id = m.objectOfSegment(4)->id;
  EXPECT_NE(chair_id, desk_id);
  // Later: the desk's side panel appears as segment 9 and is named "dining table": it joins.
  table.push_back(segmentBox(9, {1.57, 0.0, 0.0}, {1.60, 0.8, 0.72}, 1500));
  m.addDetectorView(view(15, {{4, 8000}, {9, 2500}}, {{9, kDiningTable, 0.9f, 0.7f, {4}}}));
  m.update(table);
  ASSERT_NE(m.objectOfSegment(9), nullptr);
  EXPECT_EQ(m.objectOfSegment(9)->id, desk_id);
  EXPECT_EQ(m.objectOfSegment(4)->segments, (std::vector<std::uint32_t>{4, 9}));
  EXPECT_EQ(m.objectOfSegment(3)->id, chair_id);
  // The segmentation merges 9 into 4, then renumbers 3 -> 1 and 4 -> 2: same ids, and the
  // merged segment holds both segments' detections (log-odds added).
  std::vector<std::uint32_t> merge(10);
  for (std::uint32_t l = 0; l < 10; ++l) merge[l] = l;
  merge[9] = 4;
  m.relabel(merge);
  m.relabel({0, 0, 0, 1, 2});
  table = {segmentBox(1, {5.0, 5.0, 0.0}, {5.5, 5.5, 0.9}),
           segmentBox(2, {0.0, 0.0, 0.0}, {1.6, 0.8, 0.75}, 7500)};
  m.update(table);
  ASSERT_EQ(m.objects().size(), 2u);
  EXPECT_EQ(m.objectOfSegment(1)->id, chair_id);
  EXPECT_EQ(m.objectOfSegment(2)->id, desk_id);
  EXPECT_EQ(m.segmentRecord(2)->detections, 2);
  EXPECT_NEAR(m.objectOfSegment(2)->best.probability, 1.0 / (1.0 + std::exp(-std::log(9.0) * 1.5)),
              2 * kPerUpdateP + 1e-6);
  // A new chair far away: a new id, above both.
  table.push_back(segmentBox(5, {3.0, 3.0, 0.0}, {3.5, 3.5, 0.9}));
  m.addDetectorView(view(20, {{5, 4000}}, {{5, kChair, 0.9f, 0.8f}}));
  m.update(table);
  EXPECT_GT(m.objectOfSegment(5)->id, std::max(chair_id, desk_id));
  EXPECT_EQ(m.objectOfSegment(1)->id, chair_id);
}

// A weak detection seen once does not make an object (its class stays below
// min_object_probability); a strong one does, unless the thing is detected in too few of the
// views it filled (a phantom). Views of a detector that cannot report the class do not count.
TEST(ObjectMap, AnObjectSeenOnceWithAWeakDetectionIsNotConfirmed) {
  const TClassificationParams cp;
  const float weak = detectionProbability(0.35f, ScoreModel::Vote, 0.9f, 0.25f);  // 0.567
  const float strong = detectionProbability(0.95f, ScoreModel::Vote, 0.9f, 0.25f);
  EXPECT_NEAR(weak, 0.5f + 0.5f * 0.1f / 0.75f, 1e-6f);
  EXPECT_FLOAT_EQ(strong, 0.9f);
  const std::vector<segmentation::SegmentStats> table = {segmentBox(1, {0, 0, 0}, {0.5, 0.5, 0.9}),
                                                         segmentBox(2, {3, 0, 0}, {3.5, 0.5, 0.9}),
                                                         segmentBox(3, {6, 0, 0}, {6.5, 0.5, 0.9})};
  ObjectMap m;
  m.setDetectorClasses(0, {kChair, kDiningTable});
  m.setDetectorClasses(1, {90});  // a zero-shot detector of another class
  m.addDetectorView(
      view(10, {{1, 3000}, {2, 3000}, {3, 3000}},
           {{1, kChair, weak, 0.5f}, {2, kChair, strong, 0.8f}, {3, kChair, strong, 0.8f}}));
  for (std::size_t f = 1; f <= 20; ++f) {
    m.addDetectorView(view(10 + 5 * f, {{3, 3000}}, {}));     // 20 views of segment 3, no hit
    m.addDetectorView(view(10 + 5 * f, {{2, 3000}}, {}, 1));  // segment 2 by the other detector
  }
  m.update(table);
  const MapObject* weak_obj = m.objectOfSegment(1);
  ASSERT_NE(weak_obj, nullptr);
  EXPECT_NEAR(weak_obj->best.probability, posterior(1, weak, 0.5), kPerUpdateP + 1e-6);
  EXPECT_LT(weak_obj->best.probability, cp.min_object_probability);
  EXPECT_EQ(weak_obj->verdict, ObjectVerdict::Unconfirmed);
  // Strong, seen once by its detector (the other's 20 views do not count): (1 + 1) / (1 + 2).
  const MapObject* once = m.objectOfSegment(2);
  EXPECT_EQ(once->views, 1);
  EXPECT_EQ(once->frames_seen, 21);
  EXPECT_NEAR(once->existence_probability, 2.0 / 3.0, 1e-12);
  EXPECT_EQ(once->verdict, ObjectVerdict::Object);
  // Strong but detected in 1 of 21 views: existence 2 / 23 < 0.1.
  const MapObject* phantom = m.objectOfSegment(3);
  EXPECT_EQ(phantom->views, 21);
  EXPECT_EQ(phantom->views_detected, 1);
  EXPECT_NEAR(phantom->existence_probability, 2.0 / 23.0, 1e-12);
  EXPECT_EQ(phantom->verdict, ObjectVerdict::RarelyDetected);
  EXPECT_STREQ(toString(phantom->verdict), "rarely_detected");
  EXPECT_EQ(reported(m).size(), 1u);
}

// A floor named "dining table" (a box reached it) is structure: it never swallows the table
// standing on it, which stays an object of its own.
TEST(ObjectMap, StructureDoesNotJoinTheObjectsOnIt) {
  ObjectMap m;
  const std::vector<segmentation::SegmentStats> table = {
      segmentBox(1, {0, 0, -0.01}, {7.7, 5.0, 0.01}, 400000),
      segmentBox(2, {1, 1, 0.0}, {2.6, 1.8, 0.75}, 8000)};
  m.addDetectorView(view(10, {{1, 90000}, {2, 20000}},
                         {{1, kDiningTable, 0.9f, 0.6f}, {2, kDiningTable, 0.9f, 0.8f}}));
  m.update(table);
  ASSERT_EQ(m.objects().size(), 2u);
  EXPECT_EQ(m.objectOfSegment(1)->verdict, ObjectVerdict::Structure);
  EXPECT_EQ(m.objectOfSegment(2)->verdict, ObjectVerdict::Object);
  EXPECT_EQ(m.objectOfSegment(2)->segments, (std::vector<std::uint32_t>{2}));
}

TEST(ObjectMap, SegmentPixelCountsCountEveryLabel) {
  Image<std::uint32_t> labels(4, 3);
  const std::uint32_t px[12] = {0, 1, 1, 2, 2, 2, 1, 0, 3, 3, 3, 3};
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) labels.row(y)[x] = px[4 * y + x];
  const auto counts = segmentPixelCounts(labels);
  const std::vector<std::pair<std::uint32_t, int>> expected = {{1, 3}, {2, 3}, {3, 4}};
  EXPECT_EQ(counts, expected);
}

// A segment that had detections but is gone from the map (no entry in the segment table) has no
// surfels: it is not reported, however confident its class.
TEST(ObjectMap, ASegmentGoneFromTheMapIsNotReported) {
  ObjectMap m;
  m.addDetectorView(
      view(10, {{1, 3000}, {2, 3000}}, {{1, kChair, 0.9f, 0.8f}, {2, kChair, 0.9f, 0.8f}}));
  m.update({segmentBox(1, {0, 0, 0}, {0.5, 0.5, 0.9})});
  ASSERT_EQ(m.objects().size(), 2u);
  EXPECT_EQ(m.objectOfSegment(1)->verdict, ObjectVerdict::Object);
  EXPECT_FALSE(m.objectOfSegment(2)->has_geometry);
  EXPECT_GT(m.objectOfSegment(2)->best.probability, 0.8f);
  EXPECT_EQ(m.objectOfSegment(2)->verdict, ObjectVerdict::Fragment);
}

// [objects] loads its keys with the other sections' rules: known keys only, ranges checked.
TEST(ObjectParams, LoadedStrictAndValidated) {
  mrpt::config::CConfigFileMemory ini;
  ini.write("objects", "link_max_gap_m", "0.02");
  ini.write("objects", "min_existence_probability", "0.3");
  TObjectParams p;
  loadParamsStrict(ini, "objects", p, "test.ini");
  EXPECT_DOUBLE_EQ(p.link_max_gap_m, 0.02);
  EXPECT_DOUBLE_EQ(p.min_existence_probability, 0.3);
  EXPECT_DOUBLE_EQ(p.link_min_probability, 0.6);  // defaults stay
  EXPECT_EQ(p.min_view_pixels, 300);
  mrpt::config::CConfigFileMemory bad;
  bad.write("objects", "link_min_probability", "0.4");  // below the 0.5 prior: links anything
  try {
    loadParamsStrict(bad, "objects", p, "test.ini");
    FAIL() << "link_min_probability 0.4 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[objects] link_min_probability"), std::string::npos)
        << e.what();
  }
  mrpt::config::CConfigFileMemory typo;
  typo.write("objects", "link_gap_m", "0.1");
  EXPECT_THROW(loadParamsStrict(typo, "objects", p, "test.ini"), InputError);
}
