// Simulated detector: detection rate rises with apparent size and falls with occlusion, boxes
// hug the visible masks, visible fractions from ray casting, confusions, false positives, seeds.
#include "rasm/sim/SimulatedDetector.h"

#include <gtest/gtest.h>

#include <cmath>

#include "rasm/core/Error.h"
#include "rasm/models/ClassVocabulary.h"
#include "rasm/sim/CameraPoses.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/RgbdSensor.h"
#include "rasm/sim/World.h"

using namespace rasm;
using namespace rasm::sim;
using namespace rasm::models;

namespace {

// Camera at the origin looking along +x. Objects:
//  2: a cup-class box 2 m ahead, 0.4 x 0.4 m: a ~105 x 105 px mask, fully visible.
//  3: a bottle 0.04 m wide, 3.5 m ahead: a ~6 x 6 px mask.
//  4: a keyboard-class box whose left half is hidden behind box 5 (unknown clutter).
//  6: a conference phone (not a COCO class).
const char* kWorld =
    "objects:\n"
    "  - {id: 1, class: wall, primitive: box, size: [0.2, 60, 60], position: [4.1, 0, 0]}\n"
    "  - {id: 2, class: cup, primitive: box, size: [0.1, 0.4, 0.4], position: [2.0, 0.0, 0.0]}\n"
    "  - {id: 3, class: bottle, primitive: box, size: [0.04, 0.04, 0.04], position: [3.5, 0.6, "
    "0.6]}\n"
    "  - {id: 4, class: keyboard, primitive: box, size: [0.1, 0.4, 0.3], position: [2.5, 0.7, "
    "-0.5]}\n"
    "  - {id: 5, class: none, primitive: box, size: [0.1, 0.18, 0.5], position: [1.5, 0.36, "
    "-0.3]}\n"
    "  - {id: 6, class: conference_phone, primitive: box, size: [0.1, 0.4, 0.2], position: [2.5, "
    "-0.8, 0.5]}\n";

struct Fixture {
  RayScene scene{loadWorldFromString(kWorld, "detector_world")};
  RgbdFrame frame;
  Fixture() {
    TSensorParams p;
    p.noise = false;
    frame = RgbdSensor(scene, p).render(cameraPoseFromHeading(Eigen::Vector3d::Zero(), 0.0, 0.0));
  }
  int maskPixels(int id) const {
    int n = 0;
    for (int y = 0; y < frame.height(); ++y)
      for (int x = 0; x < frame.width(); ++x) n += frame.gt_instance(x, y) == id;
    return n;
  }
};

TDetectorParams noFalsePositives() {
  TDetectorParams p;
  p.false_positives_per_frame = 0;
  return p;
}

double iou(const cv::Rect2f& a, const cv::Rect2f& b) {
  const float i = (a & b).area();
  return i / (a.area() + b.area() - i);
}

}  // namespace

TEST(SimulatedDetector, VisibleFractionFromRayCasting) {
  const Fixture fx;
  const SimulatedDetector det(noFalsePositives(), &fx.scene);
  EXPECT_NEAR(det.visibleFraction(fx.frame, 2, fx.maskPixels(2)), 1.0, 1e-6);  // same rays: exact
  // Box 5 (unknown clutter, closer) hides part of box 4: strictly between 0 and 1.
  const float vis4 = det.visibleFraction(fx.frame, 4, fx.maskPixels(4));
  EXPECT_GT(vis4, 0.0f);
  EXPECT_LT(vis4, 1.0f);
  // Without the scene the detector cannot know: 1.
  const SimulatedDetector blind(noFalsePositives(), nullptr);
  EXPECT_EQ(blind.visibleFraction(fx.frame, 4, fx.maskPixels(4)), 1.0f);
}

TEST(SimulatedDetector, PartialOcclusionHalvesTheVisibleFraction) {
  // A 0.4 m square 3 m away, its left half covered by a screen 1 m away.
  const RayScene scene(loadWorldFromString(
      "objects:\n"
      "  - {id: 1, class: cup, primitive: box, size: [0.1, 0.4, 0.4], position: [3.05, 0.0, 0.0]}\n"
      "  - {id: 2, class: none, primitive: box, size: [0.02, 0.0667, 1.0], position: [1.0, "
      "0.03335, 0.0]}\n",
      "occlusion"));
  TSensorParams p;
  p.noise = false;
  const RgbdFrame f =
      RgbdSensor(scene, p).render(cameraPoseFromHeading(Eigen::Vector3d::Zero(), 0.0, 0.0));
  int mask = 0;
  for (int y = 0; y < f.height(); ++y)
    for (int x = 0; x < f.width(); ++x) mask += f.gt_instance(x, y) == 1;
  // The screen (y 0..0.0667 at x 0.99) covers rays y/x in [0, 0.0673]: at 3 m, y in [0, 0.202],
  // the left half of the square (left = +y in the world = smaller image x).
  const SimulatedDetector det(noFalsePositives(), &scene);
  EXPECT_NEAR(det.visibleFraction(f, 1, mask), 0.5, 0.03);
}

TEST(SimulatedDetector, DetectionRateFollowsSizeAndVisibility) {
  const Fixture fx;
  TDetectorParams p = noFalsePositives();
  p.confusion_rate = 0;
  const SimulatedDetector det(p, &fx.scene);
  int big = 0, tiny = 0, occluded = 0, phone = 0;
  double min_iou = 1.0;
  const int n = 200;
  for (int s = 0; s < n; ++s)
    for (const Detection& d : det.detect(fx.frame, std::uint64_t(s))) {
      EXPECT_GE(d.score, 0.f);
      EXPECT_LE(d.score, 1.f);
      EXPECT_EQ(d.class_id, classIdFromName(d.class_name));
      EXPECT_FALSE(d.confused);
      big += d.gt_instance == 2;
      tiny += d.gt_instance == 3;
      occluded += d.gt_instance == 4;
      phone += d.gt_instance == 6;
      if (d.gt_instance == 2) {
        EXPECT_EQ(d.class_name, "cup");
        // Box of the visible mask: 105 x 105 px around the image centre.
        min_iou =
            std::min(min_iou, iou(d.box, cv::Rect2f(319.5f - 52.5f, 239.5f - 52.5f, 105.f, 105.f)));
      }
    }
  // Expected rate p = p_max * s(size) * v(visibility) for each object.
  auto expected = [&](int id) {
    const int m = fx.maskPixels(id);
    if (m < p.min_mask_pixels) return 0.0;
    const double vis = det.visibleFraction(fx.frame, id, m);
    return p.p_max / (1 + std::exp(-(std::sqrt(double(m)) - p.size50_px) / p.size_scale_px)) *
           std::clamp((vis - p.min_visible_fraction) / (1 - p.min_visible_fraction), 0.0, 1.0);
  };
  auto tol = [&](double q) { return 4 * std::sqrt(q * (1 - q) / n) + 0.01; };
  // Big and fully visible: p = p_max * s(105 px) ~ 0.95.
  EXPECT_NEAR(expected(2), 0.95, 0.01);
  EXPECT_NEAR(big / double(n), expected(2), tol(expected(2)));
  EXPECT_GT(min_iou, 0.7);
  // Tiny (6 x 6 px): rarely.
  EXPECT_LT(expected(3), 0.1);
  EXPECT_NEAR(tiny / double(n), expected(3), tol(expected(3)));
  // Partly hidden: less often than the fully visible one, but sometimes.
  EXPECT_GT(expected(4), 0.05);
  EXPECT_NEAR(occluded / double(n), expected(4), tol(expected(4)));
  EXPECT_LT(occluded, big);
  // The conference phone is not a COCO class: a COCO detector never reports it.
  EXPECT_EQ(phone, 0);
  // ... unless asked to.
  TDetectorParams all = p;
  all.detectable_classes = "all";
  int phone_all = 0;
  for (int s = 0; s < 50; ++s)
    for (const Detection& d : SimulatedDetector(all, &fx.scene).detect(fx.frame, std::uint64_t(s)))
      phone_all += d.gt_instance == 6 && d.class_name == "conference_phone";
  EXPECT_GT(phone_all, 25);
}

TEST(SimulatedDetector, ConfusionsAndFalsePositives) {
  const Fixture fx;
  TDetectorParams p;
  p.confusion_rate = 1.0;
  p.false_positives_per_frame = 2.0;
  p.occlusion_aware = false;  // not what this test is about (and ray casting costs time)
  const SimulatedDetector det(p, &fx.scene);
  int fps = 0, confused = 0, cup = 0;
  const int n = 300;
  for (int s = 0; s < n; ++s)
    for (const Detection& d : det.detect(fx.frame, std::uint64_t(s))) {
      EXPECT_GE(d.box.x, 0.f);
      EXPECT_GE(d.box.y, 0.f);
      EXPECT_LE(d.box.x + d.box.width, 640.f + 1e-3f);
      EXPECT_LE(d.box.y + d.box.height, 480.f + 1e-3f);
      EXPECT_TRUE(isCocoClass(d.class_id));
      if (d.gt_instance == 0) {
        ++fps;
        EXPECT_LT(d.score, 0.8f);
      } else if (d.gt_instance == 2) {
        ++cup;
        confused += d.confused;
        // The cup is mistaken for a similar class.
        EXPECT_TRUE(d.class_name == "bottle" || d.class_name == "vase" || d.class_name == "bowl")
            << d.class_name;
      }
    }
  EXPECT_NEAR(fps / double(n), 2.0, 4 * std::sqrt(2.0 / n));
  EXPECT_EQ(confused, cup);
}

TEST(SimulatedDetector, DeterministicBySeedAndFrame) {
  const Fixture fx;
  TDetectorParams p;
  p.false_positives_per_frame = 1.0;
  const SimulatedDetector det(p, &fx.scene);
  auto key = [](const std::vector<Detection>& v) {
    std::string s;
    for (const auto& d : v)
      s += std::to_string(d.class_id) + ":" + std::to_string(d.box.x) + "," +
           std::to_string(d.box.y) + "," + std::to_string(d.score) + ";";
    return s;
  };
  EXPECT_EQ(key(det.detect(fx.frame, 5)), key(det.detect(fx.frame, 5)));
  std::set<std::string> distinct;
  for (int s = 0; s < 10; ++s) distinct.insert(key(det.detect(fx.frame, std::uint64_t(s))));
  EXPECT_GT(distinct.size(), 5u);
  RgbdFrame other = fx.frame;
  other.index = 1;
  EXPECT_NE(key(det.detect(fx.frame, 5)), key(det.detect(other, 5)));
}

TEST(SimulatedDetector, ParamsValidation) {
  TDetectorParams p;
  p.detectable_classes = "cup, keyboard,headphones";
  EXPECT_EQ(p.detectableClassIds().size(), 3u);
  p.detectable_classes = "cup, spaceship";
  EXPECT_THROW(p.validate(), rasm::InputError);
  TDetectorParams q;
  q.p_max = 1.5;
  EXPECT_THROW(q.validate(), rasm::InputError);
}
