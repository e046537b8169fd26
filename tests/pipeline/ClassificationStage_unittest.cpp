// Section IV in the Mapper: a detection computed on frame t is fused with frame t's L^p, however
// late it arrives and however far the camera has moved since (analytic scene, ground-truth poses).
#include <gtest/gtest.h>

#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <condition_variable>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>

#include "pipeline/AnalyticScene.h"
#include "rasm/core/Error.h"
#include "rasm/pipeline/Mapper.h"
#include "rasm/pipeline/stages/ClassificationStage.h"

using namespace rasm;
using namespace rasm::pipeline;
using namespace rasm::pipeline::testing;

namespace {

/// Projects box b into the camera at T: the pixel bounds of its 8 corners.
cv::Rect2f projectBox(const Box& b, const Eigen::Isometry3d& T) {
  float x0 = 1e9f, y0 = 1e9f, x1 = -1e9f, y1 = -1e9f;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d w(c & 1 ? b.hi.x() : b.lo.x(), c & 2 ? b.hi.y() : b.lo.y(),
                            c & 4 ? b.hi.z() : b.lo.z());
    const Eigen::Vector3d p = T.inverse() * w;
    const float u = float(kK.cx + kK.fx * p.x() / p.z()), v = float(kK.cy + kK.fy * p.y() / p.z());
    x0 = std::min(x0, u), y0 = std::min(y0, v), x1 = std::max(x1, u), y1 = std::max(y1, v);
  }
  return {x0, y0, x1 - x0, y1 - y0};
}

/// Reports box `target` as seen in the frame it is given ("tv", class index 0), but only once
/// the test releases it: its result for frame 0 arrives many frames later.
class HeldDetector : public classification::Detector {
 public:
  HeldDetector(Box target, std::mutex& m, std::condition_variable& cv, bool& released)
      : m_target(target), m_mutex(m), m_cv(cv), m_released(released) {}
  std::string name() const override { return "held"; }
  const std::vector<std::string>& classNames() const override { return m_names; }
  std::vector<classification::Detection> detect(const classification::DetectorInput& in) override {
    {
      std::unique_lock<std::mutex> lock(m_mutex);
      m_cv.wait(lock, [&] { return m_released; });
    }
    classification::Detection d;
    d.box = projectBox(m_target, *in.frame->gt_T_world_cam);
    d.scores.push_back({0, 0.9f});
    ++frames;
    return {d};
  }
  int frames = 0;

 private:
  Box m_target;
  std::mutex& m_mutex;
  std::condition_variable& m_cv;
  bool& m_released;
  std::vector<std::string> m_names = {"tv"};
};

/// Reports each of its boxes that is in front of the camera with at least half of its projection
/// inside the image, as class index k (its position in `boxes`), score 0.9.
class BoxDetector : public classification::Detector {
 public:
  BoxDetector(std::vector<Box> boxes, std::vector<std::string> names)
      : m_boxes(std::move(boxes)), m_names(std::move(names)) {}
  std::string name() const override { return "boxes"; }
  const std::vector<std::string>& classNames() const override { return m_names; }
  std::vector<classification::Detection> detect(const classification::DetectorInput& in) override {
    std::vector<classification::Detection> out;
    const Eigen::Isometry3d& T = *in.frame->gt_T_world_cam;
    for (std::size_t k = 0; k < m_boxes.size(); ++k) {
      if ((T.inverse() * m_boxes[k].lo).z() <= 0.1) continue;
      const cv::Rect2f r = projectBox(m_boxes[k], T);
      const cv::Rect2f inside = r & cv::Rect2f(0, 0, float(kK.width), float(kK.height));
      if (inside.area() < 0.5f * r.area()) continue;
      classification::Detection d;
      d.box = inside;
      d.scores.push_back({int(k), 0.9f});
      out.push_back(d);
    }
    return out;
  }

 private:
  std::vector<Box> m_boxes;
  std::vector<std::string> m_names;
};

/// [classification] of a test run: `detectors`, on the mapping thread unless `threaded`, every
/// frame offered.
void writeClassificationKeys(mrpt::config::CConfigFileMemory& ini, const std::string& detectors,
                             bool threaded = false) {
  ini.write("classification", "detectors", detectors);
  ini.write("classification", "threaded", threaded ? "true" : "false");
  ini.write("classification", "every_n_frames", "1");
}

}  // namespace

// The simulator's detector is a detector kind the stage adds (pipeline/SimDetector.h): its
// section [sim_detector] comes before the built-in detectors' (config.ini keeps that order), is
// loaded strictly and validated, and `detectors = sim_detector` builds it; on frames without the
// simulator's ground truth it refuses to run and is disabled.
TEST(ClassificationStage, TheSimulatedDetectorIsADetectorKindOfTheStage) {
  Mapper defaults;
  std::vector<std::string> names;
  for (const ParamsSection& s : defaults.stage<ClassificationStage>().sections())
    names.push_back(s.name);
  EXPECT_EQ(names, (std::vector<std::string>{"classification", "objects", "sim_detector",
                                             "dnn_detector", "zero_shot"}));
  mrpt::config::CConfigFileMemory unknown_key, out_of_range;
  unknown_key.write("sim_detector", "no_such_key", 1);
  EXPECT_THROW(Mapper(unknown_key, "test.ini"), InputError);
  out_of_range.write("sim_detector", "p_max", 2.0);
  EXPECT_THROW(Mapper(out_of_range, "test.ini"), InputError);

  mrpt::config::CConfigFileMemory ini;
  writeClassificationKeys(ini, "sim_detector");
  Mapper mapper(ini, "test");
  mapper.addStage(std::make_unique<GroundTruthPose>(), "index_map");
  const Box a{{-0.5, -0.2, 1.8}, {-0.1, 0.2, 2.2}};
  for (int k = 0; k < 3; ++k) mapper.processFrame(render({a}, at(0.0), k));
  mapper.finishRun();
  nlohmann::json rep;
  mapper.report(rep);
  const nlohmann::json& detectors = rep["classification"]["detectors"];
  ASSERT_EQ(detectors.size(), 1u);
  EXPECT_EQ(detectors[0]["name"], "sim_detector");
  ASSERT_TRUE(detectors[0].contains("disabled"));
  EXPECT_NE(detectors[0]["disabled"].get<std::string>().find("ground truth"), std::string::npos);
}

// The camera looks at a tv (A) and a chair (B), slides 2.6 m to the right until both have left
// the view, and comes back: the object layer lists each once, with the id it had from its first
// detections, seen at the start and at the end but not in the middle.
TEST(ClassificationStage, AnObjectLeftAndSeenAgainIsListedOnce) {
  const Box a{{-0.5, -0.2, 1.8}, {-0.1, 0.2, 2.2}}, b{{0.1, -0.2, 1.8}, {0.5, 0.2, 2.2}};
  mrpt::config::CConfigFileMemory ini;
  writeClassificationKeys(ini, "");
  Mapper mapper(ini, "test");
  mapper.addStage(std::make_unique<GroundTruthPose>(), "index_map");
  auto& stage = mapper.stage<ClassificationStage>();
  stage.addDetector(std::make_unique<BoxDetector>(std::vector<Box>{a, b},
                                                  std::vector<std::string>{"tv", "chair"}));
  const int n = 41;              // x: 0 -> 2.6 m (frame 20) -> 0
  std::map<int, int> first_ids;  // class -> id of the object after the first detections
  for (int k = 0; k < n; ++k) {
    const double x = 2.6 * (k <= 20 ? k : 40 - k) / 20.0;
    ASSERT_TRUE(mapper.processFrame(render({a, b}, at(x), k)).fused) << k;
    if (k == 3)  // after the first detections (before the segment table has the boxes' segments)
      for (const auto& o : stage.objectMap().objects())
        if (o.best.class_id != 0) first_ids.emplace(o.best.class_id, o.id);
  }
  mapper.finishRun();
  const int tv = stage.classList().find("tv"), chair = stage.classList().find("chair");
  ASSERT_EQ(first_ids.size(), 2u);
  std::vector<const classification::MapObject*> reported;
  for (const auto& o : stage.objectMap().objects())
    if (o.verdict == classification::ObjectVerdict::Object) reported.push_back(&o);
  ASSERT_EQ(reported.size(), 2u);
  const classification::MapObject* obj_a =
      reported[0]->best.class_id == tv ? reported[0] : reported[1];
  const classification::MapObject* obj_b = reported[0] == obj_a ? reported[1] : reported[0];
  EXPECT_EQ(obj_a->best.class_id, tv);
  EXPECT_EQ(obj_b->best.class_id, chair);
  EXPECT_EQ(obj_a->id, first_ids[tv]);
  EXPECT_EQ(obj_b->id, first_ids[chair]);
  EXPECT_NE(obj_a->id, obj_b->id);
  for (const classification::MapObject* o : {obj_a, obj_b}) {
    EXPECT_EQ(o->first_seen_frame, 0u);
    EXPECT_EQ(o->last_seen_frame, std::size_t(n - 1));
    EXPECT_LT(o->frames_seen, n - 10);  // not from 2.6 m to the right
    EXPECT_GT(o->existence_probability, 0.7);
  }
  // Its oriented box is about A's centre across the view (the faces the camera saw: this scene's
  // z is depth, so "upright" z is A's depth), 0.4 m across: the percentile box, not the
  // axis-aligned one that a few stray surfels at the silhouette stretch (to x = -0.68 here).
  EXPECT_NEAR(obj_a->box_centre.x(), -0.3, 0.05);
  EXPECT_NEAR(obj_a->box_centre.y(), 0.0, 0.05);
  EXPECT_NEAR(obj_a->box_extents_m.cwiseAbs().head<2>().maxCoeff(), 0.4, 0.05);
}

TEST(ClassificationStage, ALateResultLandsOnTheSegmentsOfItsOwnFrame) {
  // Boxes A and B 0.6 m apart; the camera slides 0.6 m to the right, so at the end B is where A
  // was in frame 0. The detector's frame-0 result (A's box in frame 0) is held back until then:
  // fused with the current L^p it would label B, with frame 0's it labels A.
  const Box a{{-0.5, -0.2, 1.8}, {-0.1, 0.2, 2.2}}, b{{0.1, -0.2, 1.8}, {0.5, 0.2, 2.2}};
  mrpt::config::CConfigFileMemory ini;
  writeClassificationKeys(ini, "", true);
  ini.write("segmentation", "remap_every_n_frames", "5");  // relabellings while it is held
  Mapper mapper(ini, "test");
  mapper.addStage(std::make_unique<GroundTruthPose>(), "index_map");
  std::mutex m;
  std::condition_variable cv;
  bool released = false;
  auto held = std::make_unique<HeldDetector>(a, m, cv, released);
  HeldDetector* probe = held.get();
  auto& stage = mapper.stage<ClassificationStage>();
  stage.addDetector(std::move(held));
  const int n = 30;
  for (int k = 0; k < n; ++k) {
    if (k == n - 2) {
      {
        std::lock_guard<std::mutex> lock(m);
        released = true;
      }
      cv.notify_all();
    }
    ASSERT_TRUE(mapper.processFrame(render({a, b}, at(0.6 * k / (n - 3)), k)).fused) << k;
  }
  mapper.finishRun();
  EXPECT_GE(probe->frames, 1);
  // Surfels with evidence for "tv" lie on A, none on B.
  const int tv = stage.classList().find("tv");
  ASSERT_GT(tv, 0);
  const maps::SurfelArrays s = static_cast<const maps::SurfelStore&>(mapper.map().store()).arrays();
  const auto inside = [](const Box& box, const Eigen::Vector3d& p) {
    return (p.array() >= box.lo.array() - 0.01).all() && (p.array() <= box.hi.array() + 0.01).all();
  };
  int on_a = 0, on_b = 0, elsewhere = 0, a_total = 0;
  for (int i = 0; i < s.size; ++i) {
    if (!s.alive(i)) continue;
    const Eigen::Vector3d p = s.position(i).cast<double>();
    a_total += inside(a, p);
    if (maps::classLogitUnits(s.class_ev[i], tv) <= 0) continue;
    if (inside(a, p))
      ++on_a;
    else if (inside(b, p))
      ++on_b;
    else
      ++elsewhere;
  }
  EXPECT_EQ(on_b, 0);
  EXPECT_GE(on_a, 0.9 * a_total) << "A has " << a_total << " surfels";
  EXPECT_LE(elsewhere, 0.05 * on_a);
  // Frames offered while the detector was held were skipped, not queued.
  nlohmann::json rep;
  mapper.report(rep);
  EXPECT_GE(rep["classification"]["detectors"][0]["frames_skipped"].get<int>(), n - 4);
}

namespace {

/// A zero-shot-like detector: reports box `real` with the template viewpoint it really shows
/// (the camera's direction from the box in the model frame, on the bank's 5-degree grid; the
/// model's up is the scene's -y) as class 0, and box `phantom` as class 1 with one fixed
/// viewpoint whatever the view, as an outline that merely resembles a template does.
class PosedBoxDetector : public classification::Detector {
 public:
  PosedBoxDetector(Box real, Box phantom) : m_real(real), m_phantom(phantom) {}
  std::string name() const override { return "posed"; }
  const std::vector<std::string>& classNames() const override { return m_names; }
  std::vector<classification::Detection> detect(const classification::DetectorInput& in) override {
    const Eigen::Isometry3d& T = *in.frame->gt_T_world_cam;
    // Model frame: z up = the scene's -y (Rx(90 deg) maps model z to world -y).
    const Eigen::Matrix3d R_world_model =
        Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
    const Eigen::Vector3d centre = 0.5 * (m_real.lo + m_real.hi);
    const Eigen::Vector3d d = R_world_model.transpose() * (T.translation() - centre).normalized();
    classification::Detection real, phantom;
    real.box = projectBox(m_real, T);
    real.scores.push_back({0, 0.9f});
    real.pose.valid = true;
    real.pose.azimuth_deg = 5.f * std::round(float(std::atan2(d.y(), d.x()) * 180 / M_PI) / 5.f);
    real.pose.elevation_deg = 5.f * std::round(float(std::asin(d.z()) * 180 / M_PI) / 5.f);
    phantom.box = projectBox(m_phantom, T);
    phantom.scores.push_back({1, 0.9f});
    phantom.pose = real.pose;
    phantom.pose.azimuth_deg = -90.f;
    phantom.pose.elevation_deg = 0.f;
    return {real, phantom};
  }

 private:
  Box m_real, m_phantom;
  std::vector<std::string> m_names = {"cup", "bowl"};
};

}  // namespace

// VII-A: the camera slides 1.6 m sideways past two boxes 2 m away (their bearing changes by
// about 43 degrees). The real box's template poses imply one orientation and name it; the
// phantom's fixed viewpoint implies orientations that turn with the camera, so its detections are
// held and never fused, into the surfels or the object layer. Without the consensus (the paper's
// IV-A) the phantom is named too.
TEST(ClassificationStage, ZeroShotDetectionsAreFusedOnlyWhenTheirPosesAgreeAcrossViews) {
  const Box real{{0.05, -0.2, 1.8}, {0.45, 0.2, 2.2}},
      phantom{{-0.45, -0.2, 1.8}, {-0.05, 0.2, 2.2}};
  const auto run = [&](bool consensus) {
    mrpt::config::CConfigFileMemory ini;
    writeClassificationKeys(ini, "");
    ini.write("classification", "pose_consensus", consensus ? "true" : "false");
    Mapper mapper(ini, "test");
    mapper.addStage(std::make_unique<GroundTruthPose>(), "index_map");
    auto& stage = mapper.stage<ClassificationStage>();
    stage.addDetector(std::make_unique<PosedBoxDetector>(real, phantom));
    for (int k = 0; k <= 16; ++k)
      EXPECT_TRUE(mapper.processFrame(render({real, phantom}, at(-0.8 + 0.1 * k), k)).fused) << k;
    mapper.finishRun();
    std::map<std::string, int> named;
    // The object layer's class of each object (its histogram of the detections fused): this
    // short slide leaves the boxes' segments unconfirmed, so the verdicts are not asserted.
    for (const auto& o : stage.objectMap().objects())
      if (o.best.class_id != 0) ++named[stage.classList().name(o.best.class_id)];
    nlohmann::json rep;
    stage.report(rep);
    return std::make_pair(named, rep["classification"]["pose_consensus"]);
  };
  const auto [with, counts] = run(true);
  EXPECT_EQ(with.count("cup") ? with.at("cup") : 0, 1);
  EXPECT_EQ(with.count("bowl"), 0u) << "the phantom was fused";
  EXPECT_GE(counts["detections_released"].get<int>(), 10);  // the real box, from most views
  EXPECT_GE(counts["detections_held"].get<int>(), 15);      // the phantom, from every view
  const auto [without, none] = run(false);
  EXPECT_EQ(without.count("cup") ? without.at("cup") : 0, 1);
  EXPECT_EQ(without.count("bowl") ? without.at("bowl") : 0, 1);
  EXPECT_EQ(none["detections_held"].get<int>(), 0);
}
