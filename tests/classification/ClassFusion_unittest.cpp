// Segment-level association and Bayes fusion of section IV (ClassFusion.h), the class list and
// the detector workers (DetectorWorker.h).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "rasm/classification/ClassFusion.h"
#include "rasm/classification/ClassList.h"
#include "rasm/classification/DetectorWorker.h"
#include "rasm/classification/ObjectVerdict.h"
#include "rasm/core/Error.h"
#include "rasm/surfel_map/SurfelStore.h"

using namespace rasm;
using namespace rasm::classification;

namespace {

/// p after the paper's update from p with detection probability pd (double precision).
double bayes(double p, double pd) {
  return pd * p / (pd * p + (1 - pd) * (1 - p));
}

/// A store of `n` surfels, surfel i in segment 1 + i % segments.
maps::SurfelStore makeStore(int n, int segments) {
  maps::SurfelStore store;
  for (int i = 0; i < n; ++i) {
    maps::Surfel s;
    s.position = Vec3f(0.01f * float(i), 0.f, 1.f);
    s.segment = std::uint32_t(1 + i % segments);
    store.append(s);
  }
  return store;
}

Detection box(float x, float y, float w, float h, int cls = 0, float score = 0.9f) {
  Detection d;
  d.box = cv::Rect2f(x, y, w, h);
  d.scores.push_back({cls, score});
  return d;
}

// One quantisation step per update (ClassEvidence.h): 1/2048 nat + float logit error, a quarter
// of that in p.
constexpr double kPerUpdateP = (1.0 / 2048 + 1e-6) / 4;

}  // namespace

TEST(ClassFusion, BayesUpdateOfASegmentFollowsThePaper) {
  maps::SurfelStore store = makeStore(300, 3);
  const std::uint64_t generation = store.generation();
  // Segment 2 seen as class 57 ("chair") three times at p_d = 0.8, segment 3 once at 0.3.
  for (int k = 0; k < 3; ++k) fuseSegmentEvidence(store.arraysForClassEvidence(), {{2, 57, 0.8f}});
  const FusionCounts c = fuseSegmentEvidence(store.arraysForClassEvidence(), {{3, 57, 0.3f}});
  EXPECT_EQ(c.surfels, 100u);
  EXPECT_EQ(store.generation(), generation);  // fusion's caches stay valid
  const double p2 = bayes(bayes(bayes(0.5, 0.8), 0.8), 0.8);
  const double p3 = bayes(0.5, 0.3);
  const maps::SurfelArrays a = static_cast<const maps::SurfelStore&>(store).arrays();
  for (int i = 0; i < a.size; ++i) {
    const double p = maps::classProbability(a.class_ev[i], 57);
    const double expected = a.segment[i] == 2 ? p2 : (a.segment[i] == 3 ? p3 : 0.5);
    ASSERT_NEAR(p, expected, 3 * kPerUpdateP + 1e-6) << "surfel " << i;
  }
}

TEST(ClassFusion, HalfIsANoOpAndOppositeEvidenceCancels) {
  maps::SurfelStore store = makeStore(10, 1);
  fuseSegmentEvidence(store.arraysForClassEvidence(), {{1, 5, 0.5f}});
  const maps::SurfelArrays a = store.arraysForClassEvidence();
  for (int i = 0; i < a.size; ++i) EXPECT_TRUE(maps::classEvidenceEmpty(a.class_ev[i]));
  // Symmetry: p_d then 1 - p_d returns to the prior exactly (log-odds add to 0).
  fuseSegmentEvidence(a, {{1, 5, 0.8f}});
  fuseSegmentEvidence(a, {{1, 5, 0.2f}});
  for (int i = 0; i < a.size; ++i) EXPECT_EQ(maps::classLogitUnits(a.class_ev[i], 5), 0);
}

TEST(ClassFusion, SaturatesAtTheClampAndStaysAbleToChange) {
  maps::SurfelStore store = makeStore(4, 1);
  const maps::SurfelArrays a = store.arraysForClassEvidence();
  for (int k = 0; k < 50; ++k) fuseSegmentEvidence(a, {{1, 9, 0.9f}});
  EXPECT_NEAR(maps::classProbability(a.class_ev[0], 9), 1.0 / (1.0 + std::exp(-7.0)), 1e-5);
  // ceil(7 / logit(0.9)) = 4 contrary detections bring it below the prior (ClassEvidence.h).
  for (int k = 0; k < 4; ++k) fuseSegmentEvidence(a, {{1, 9, 0.1f}});
  EXPECT_LT(maps::classProbability(a.class_ev[0], 9), 0.5);
}

TEST(ClassFusion, LogOddsEqualTheProductForm) {
  // n updates with different p_d: the product form p = prod pd / (prod pd + prod (1 - pd)).
  maps::SurfelStore store = makeStore(1, 1);
  const maps::SurfelArrays a = store.arraysForClassEvidence();
  const float pds[] = {0.7f, 0.9f, 0.4f, 0.65f, 0.55f};
  double num = 1, den = 1, sequential = 0.5;
  for (float pd : pds) {
    fuseSegmentEvidence(a, {{1, 3, pd}});
    num *= pd;
    den *= 1.0 - double(pd);
    sequential = bayes(sequential, pd);
  }
  const double product = num / (num + den);
  EXPECT_NEAR(product, sequential, 1e-12);
  EXPECT_NEAR(maps::classProbability(a.class_ev[0], 3), product, 5 * kPerUpdateP + 1e-6);
}

TEST(ClassFusion, AssociationPicksTheForegroundObjectNotTheWallBehindIt) {
  // 200 x 100 image: a wall (segment 1) everywhere, a 40 x 40 object (segment 2) at (80, 30).
  // The detector's box covers the object and a 10 px margin of wall on every side.
  Image<std::uint32_t> labels(200, 100, 1u);
  for (int y = 30; y < 70; ++y)
    for (int x = 80; x < 120; ++x) labels(x, y) = 2u;
  const std::vector<Association> a =
      associateDetections(labels, {box(70, 20, 60, 60), box(0, 0, 200, 100)}, 0.25f);
  // Object: I = 1600, U = 1600 + 3600 - 1600 = 3600, IoU 0.444; wall: I = 2000,
  // U = 18400 + 3600 - 2000 = 20000, IoU 0.1.
  EXPECT_EQ(a[0].segment, 2u);
  EXPECT_EQ(a[0].intersection, 1600);
  EXPECT_EQ(a[0].union_, 3600);
  EXPECT_NEAR(a[0].iou, 1600.0 / 3600.0, 1e-6);
  // The whole-image box: wall IoU 18400 / 20000 = 0.92.
  EXPECT_EQ(a[1].segment, 1u);
  EXPECT_NEAR(a[1].iou, 0.92, 1e-6);
  // A box over empty pixels, or below min_iou, has no segment.
  const auto none = associateDetections(labels, {box(70, 20, 60, 60)}, 0.5f);
  EXPECT_EQ(none[0].segment, 0u);
  const auto outside = associateDetections(labels, {box(300, 300, 10, 10)}, 0.0f);
  EXPECT_EQ(outside[0].segment, 0u);
}

// The pieces of a detection: segments other than s_d with at least the given fraction of their
// pixels inside the box (a desk's side panel under the box of its top), not a segment half in.
TEST(ClassFusion, AssociationListsTheSegmentsMostlyInsideTheBoxAsPieces) {
  // 200 x 100 wall (1); a desk top 60 x 20 (2) at (60, 40); its side panel 10 x 30 (3) at
  // (110, 60); a chair 20 x 20 (4) at (125, 40), half of it right of the box's edge at x = 135.
  Image<std::uint32_t> labels(200, 100, 1u);
  const auto fill = [&](int x0, int y0, int w, int h, std::uint32_t l) {
    for (int y = y0; y < y0 + h; ++y)
      for (int x = x0; x < x0 + w; ++x) labels(x, y) = l;
  };
  fill(60, 40, 60, 20, 2u);
  fill(110, 60, 10, 30, 3u);
  fill(125, 40, 20, 20, 4u);
  const Detection desk = box(55, 35, 80, 57);  // x 55..135, y 35..92
  const auto a = associateDetections(labels, {desk}, 0.25f, 0.6f);
  ASSERT_EQ(a[0].segment, 2u);
  // The panel lies wholly inside (300 of 300 px); the chair half (200 of 400): not a piece; the
  // wall's pixels in the box are a small part of it.
  EXPECT_EQ(a[0].pieces, (std::vector<std::uint32_t>{3}));
  // With the fraction at 0.5 the chair is a piece too; at 0 (the default) none are listed.
  EXPECT_EQ(associateDetections(labels, {desk}, 0.25f, 0.5f)[0].pieces,
            (std::vector<std::uint32_t>{3, 4}));
  EXPECT_TRUE(associateDetections(labels, {desk}, 0.25f)[0].pieces.empty());
}

TEST(ClassFusion, SegmentClassIsTheHighestMeanPosterior) {
  maps::SurfelStore store = makeStore(100, 1);
  const maps::SurfelArrays a = store.arraysForClassEvidence();
  // Half the surfels strongly class 7, all mildly class 8: mean p of 7 = 0.5 + (0.9 - 0.5) / 2
  // = 0.7; of 8 = 0.6.
  std::vector<int> half;
  for (int i = 0; i < 50; ++i) half.push_back(i);
  store.addClassEvidence(half, 7, 0.9f);
  fuseSegmentEvidence(a, {{1, 8, 0.6f}});
  const std::vector<SegmentClass> c = segmentClasses(a);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].surfels, 100);
  EXPECT_EQ(c[0].best_id, 7);
  EXPECT_NEAR(c[0].best_p, 0.7, 2 * kPerUpdateP);
  EXPECT_EQ(c[0].runner_up_id, 8);
  EXPECT_NEAR(c[0].runner_up_p, 0.6, 2 * kPerUpdateP);
}

// objects.json's verdict (ObjectVerdict.h) on shapes a room holds, with the shipped thresholds:
// a confirmed class, >= 50 surfels and > 10 cm, and not a thin plane over 2 m both ways.
TEST(ObjectVerdict, TheFloorAWallAndCrumbsAreNotObjectsATableIs) {
  const TClassificationParams p;
  SegmentClass c;
  c.best_id = 61;  // dining table
  c.best_p = 0.71f;
  c.surfels = 406000;
  EXPECT_EQ(objectVerdict(c, Eigen::Vector3d(7.7, 5.0, 0.02), p), ObjectVerdict::Structure);
  EXPECT_EQ(objectVerdict(c, Eigen::Vector3d(0.04, 2.7, 5.0), p), ObjectVerdict::Structure);
  // The default run's floor segment, which took in a few percent of low furniture surfaces: 0.31 m
  // between its 1st and 99th height percentiles, a twentieth of its 5.8 m width.
  EXPECT_EQ(objectVerdict(c, Eigen::Vector3d(7.9, 5.8, 0.31), p), ObjectVerdict::Structure);
  // A 2.5 m wardrobe, 2.2 m tall and 0.6 m deep: an object.
  EXPECT_EQ(objectVerdict(c, Eigen::Vector3d(2.5, 2.2, 0.6), p), ObjectVerdict::Object);
  // A 2.4 x 1.2 m conference table top, and a desk with its legs (thick): objects.
  EXPECT_EQ(objectVerdict(c, Eigen::Vector3d(2.4, 1.2, 0.03), p), ObjectVerdict::Object);
  EXPECT_EQ(objectVerdict(c, Eigen::Vector3d(2.5, 2.2, 0.75), p), ObjectVerdict::Object);
  // A "chair" of 1 surfel and a 5 cm crumb of 500 surfels: fragments.
  c.surfels = 1;
  EXPECT_EQ(objectVerdict(c, Eigen::Vector3d(1e-9, 1e-9, 1e-9), p), ObjectVerdict::Fragment);
  c.surfels = 49;
  EXPECT_EQ(objectVerdict(c, Eigen::Vector3d(0.3, 0.2, 0.1), p), ObjectVerdict::Fragment);
  c.surfels = 500;
  EXPECT_EQ(objectVerdict(c, Eigen::Vector3d(0.05, 0.04, 0.03), p), ObjectVerdict::Fragment);
  EXPECT_EQ(objectVerdict(c, Eigen::Vector3d(0.3, 0.2, 0.1), p), ObjectVerdict::Object);
  // Below min_object_probability, or no class: unconfirmed, whatever the shape.
  c.best_p = 0.55f;
  EXPECT_EQ(objectVerdict(c, Eigen::Vector3d(0.3, 0.2, 0.1), p), ObjectVerdict::Unconfirmed);
  c.best_id = 0;
  c.best_p = 0.9f;
  EXPECT_EQ(objectVerdict(c, Eigen::Vector3d(0.3, 0.2, 0.1), p), ObjectVerdict::Unconfirmed);
  EXPECT_STREQ(toString(ObjectVerdict::Structure), "structure");
}

TEST(ClassFusion, ScoreModels) {
  EXPECT_FLOAT_EQ(detectionProbability(0.3f, ScoreModel::Probability, 0.9f), 0.3f);
  EXPECT_FLOAT_EQ(detectionProbability(0.99f, ScoreModel::Probability, 0.9f), 0.9f);
  EXPECT_FLOAT_EQ(detectionProbability(0.3f, ScoreModel::Vote, 0.9f), 0.65f);
  EXPECT_FLOAT_EQ(detectionProbability(NAN, ScoreModel::Vote, 0.9f), 0.5f);
  // Neutral score 0.4: 0.3 is no evidence, 0.7 half way from 0.5 to 1 (0.75), 1 clamped to 0.9.
  EXPECT_FLOAT_EQ(detectionProbability(0.3f, ScoreModel::Vote, 0.9f, 0.4f), 0.5f);
  EXPECT_NEAR(detectionProbability(0.7f, ScoreModel::Vote, 0.9f, 0.4f), 0.75f, 1e-6f);
  EXPECT_FLOAT_EQ(detectionProbability(1.0f, ScoreModel::Vote, 0.9f, 0.4f), 0.9f);
}

TEST(ClassList, DefaultIsCocoThenProjectAndDetectorsJoinByName) {
  ClassList list;
  EXPECT_EQ(list.find("person"), 1);
  EXPECT_EQ(list.find("toothbrush"), 80);
  EXPECT_EQ(list.find("conference_phone"), 81);
  EXPECT_EQ(list.find("diningtable"), list.find("dining table"));  // Darknet spelling
  EXPECT_EQ(list.find("cabinet"), -1);
  const int n = list.size();
  EXPECT_EQ(list.idFor("cabinet", "zero_shot"), n + 1);
  EXPECT_EQ(list.idFor("cabinet", "other"), n + 1);  // by name, whatever the source
  EXPECT_EQ(list.classes().back().source, "zero_shot");
  EXPECT_EQ(list.name(n + 1), "cabinet");
  ClassList small(ClassList::defaultClasses(), list.size() - 1);
  EXPECT_THROW(small.idFor("gizmo", "zero_shot"), InputError);
}

namespace {

/// A detector that sleeps, can throw on demand, and reports one box at (index, 0).
class ProbeDetector : public Detector {
 public:
  explicit ProbeDetector(std::chrono::milliseconds delay, std::size_t throw_on = ~0u)
      : m_delay(delay), m_throw_on(throw_on) {}
  std::string name() const override { return "probe"; }
  const std::vector<std::string>& classNames() const override { return m_names; }
  std::vector<Detection> detect(const DetectorInput& in) override {
    std::this_thread::sleep_for(m_delay);
    if (in.frame_index == m_throw_on) throw std::runtime_error("probe failure");
    return {box(float(in.frame_index), 0.f, 1.f, 1.f)};
  }

 private:
  std::chrono::milliseconds m_delay;
  std::size_t m_throw_on;
  std::vector<std::string> m_names = {"thing"};
};

std::shared_ptr<const RgbdFrame> frameAt(std::size_t index) {
  auto f = std::make_shared<RgbdFrame>();
  f->index = index;
  f->colour = Image<Bgr8>(8, 8, Bgr8{});
  f->depth_m = Image<float>(8, 8, 1.f);
  return f;
}

}  // namespace

TEST(DetectorWorker, ABusyDetectorSkipsFramesAndResultsCarryTheirFrame) {
  DetectorWorker w(std::make_unique<ProbeDetector>(std::chrono::milliseconds(200)), 0, true);
  EXPECT_TRUE(w.offer(frameAt(10)));
  EXPECT_FALSE(w.offer(frameAt(11)));  // still on frame 10: skipped, not queued
  EXPECT_FALSE(w.offer(frameAt(12)));
  w.waitIdle();
  std::vector<DetectorResult> out;
  w.collect(out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].frame_index, 10u);
  EXPECT_FLOAT_EQ(out[0].detections.at(0).box.x, 10.f);
  const DetectorWorkerStats s = w.stats();
  EXPECT_EQ(s.offered, 3u);
  EXPECT_EQ(s.skipped, 2u);
  EXPECT_EQ(s.calls, 1u);
}

TEST(DetectorWorker, ADetectorThatThrowsIsDisabledAndReported) {
  DetectorWorker w(std::make_unique<ProbeDetector>(std::chrono::milliseconds(0), 3), 0, true);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_TRUE(w.offer(frameAt(i)));
    w.waitIdle();
  }
  EXPECT_TRUE(w.offer(frameAt(3)));
  w.waitIdle();
  EXPECT_TRUE(w.disabled());
  EXPECT_NE(w.error().find("probe failure"), std::string::npos);
  EXPECT_NE(w.error().find("frame 3"), std::string::npos);
  EXPECT_FALSE(w.offer(frameAt(4)));
  std::vector<DetectorResult> out;
  w.collect(out);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_TRUE(out[3].failed);  // the failed frame is returned empty, so its L^p is released
  EXPECT_TRUE(out[3].detections.empty());
}

TEST(DetectorWorker, SynchronousModeDetectsInsideOffer) {
  DetectorWorker w(std::make_unique<ProbeDetector>(std::chrono::milliseconds(0)), 2, false);
  EXPECT_TRUE(w.offer(frameAt(7)));
  std::vector<DetectorResult> out;
  w.collect(out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].worker, 2);
  EXPECT_EQ(out[0].frame_index, 7u);
}
