// Relocaliser (issue 14 item 5) and its [relocalisation] params:
//  - keyframe spacing and replacement rules, and the keyframe's geometry (world points project
//    back onto their keypoints at the depth the frame measured);
//  - relocalisation of simulated office frames (Kinect noise and dropouts on) that are not
//    keyframes, against keyframes made at the ground-truth poses of the first 6 s of the sweep;
//  - no false positive: views of parts of the room the keyframes never saw, another world,
//    mirrored, black and depth-less frames;
//  - keyframes that went through CSurfelMap serialization relocalise identically;
//  - leave-one-out on TUM fr3_cabinet's 58 sparse keyframes (RASM_SHARED_DATA; skipped when
//    absent): each keyframe against keyframes made from the 57 others at their ground truth.
// Tolerances: the simulated sensor's depth noise at 1-3 m is 2-10 mm (Nguyen et al.), so a pose
// from 50-300 inliers lands within a few mm to 3 cm; 5 cm / 2 deg is the bar.
#include "rasm/tracking/Relocaliser.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/core/SE3.h"
#include "rasm/io/FrameSource.h"
#include "rasm/io/Trajectory.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/RgbdSensor.h"
#include "rasm/sim/Trajectory.h"
#include "rasm/sim/World.h"
#include "rasm/surfel_map/CSurfelMap.h"

using namespace rasm;
using namespace rasm::tracking;
namespace fs = std::filesystem;

namespace {

constexpr double kDeg = M_PI / 180.0;

/// A simulated world rendered by the Kinect model (640x480, noise and dropouts on) along one of
/// the shipped hand-held sweeps; built once per test process.
class SimSweep {
 public:
  static const SimSweep& office() {
    static const SimSweep s("office", "office_handheld");
    return s;
  }
  static const SimSweep& lab() {
    static const SimSweep s("cluttered_lab", "cluttered_lab_handheld");
    return s;
  }
  /// The office sweep at 320x240 (the same field of view: fx = fy = 262.5 px).
  static const SimSweep& officeQvga() {
    sim::TSensorParams p;
    p.width = 320;
    p.height = 240;
    p.fx = p.fy = 262.5;
    p.cx = 159.5;
    p.cy = 119.5;
    static const SimSweep s("office", "office_handheld", p);
    return s;
  }
  /// Frame i of the sweep (t = i / 30 s) with its ground-truth pose.
  RgbdFrame frame(std::size_t i) const {
    RgbdFrame f = sensor_->render(pose(i), 1, i);
    f.index = i;
    f.timestamp_s = double(i) / 30.0;
    return f;
  }
  Eigen::Isometry3d pose(std::size_t i) const { return path_.pose(double(i) / 30.0); }

 private:
  SimSweep(const std::string& world, const std::string& trajectory,
           const sim::TSensorParams& sensor = sim::TSensorParams())
      : scene_(std::make_unique<sim::RayScene>(sim::loadWorld(world))),
        path_(makePath(trajectory)) {
    sensor_ = std::make_unique<sim::RgbdSensor>(*scene_, sensor);
  }
  static sim::HandheldTrajectory makePath(const std::string& name) {
    const sim::TrajectorySpec spec = sim::loadTrajectorySpec(name);
    return sim::HandheldTrajectory(spec.keyframes, spec.jitter, 1);
  }
  std::unique_ptr<sim::RayScene> scene_;
  sim::HandheldTrajectory path_;
  std::unique_ptr<sim::RgbdSensor> sensor_;
};

/// Keyframes of the office sweep from frames 0..last (every `step`-th frame offered to
/// maybeAddKeyframe at its ground-truth pose).
std::vector<maps::Keyframe> officeKeyframes(Relocaliser& reloc, std::size_t last,
                                            std::size_t step = 2,
                                            const SimSweep& sim = SimSweep::office()) {
  std::vector<maps::Keyframe> db;
  for (std::size_t i = 0; i <= last; i += step)
    reloc.maybeAddKeyframe(sim.frame(i), sim.pose(i), db);
  return db;
}

double poseErrorM(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return translationDistance(a, b);
}
double poseErrorDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return rotationAngle(a, b) / kDeg;
}

Eigen::Isometry3d translated(const Eigen::Isometry3d& T, const Eigen::Vector3d& d) {
  Eigen::Isometry3d out = T;
  out.translation() += d;
  return out;
}
Eigen::Isometry3d rotatedAboutCameraY(const Eigen::Isometry3d& T, double deg) {
  Eigen::Isometry3d out = T;
  out.linear() =
      T.linear() * Eigen::AngleAxisd(deg * kDeg, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return out;
}

TRelocalisationParams loadParams(const std::string& ini) {
  mrpt::config::CConfigFileMemory cfg(ini);
  TRelocalisationParams p;
  loadParamsStrict(cfg, "relocalisation", p, "test.ini");
  return p;
}
std::string loadError(const std::string& ini) {
  try {
    loadParams(ini);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// ---- params ----

TEST(RelocalisationParams, DefaultsValidateAndRoundTrip) {
  const TRelocalisationParams d;
  EXPECT_NO_THROW(d.validate());
  EXPECT_EQ(d.orb_features, 1000);
  EXPECT_EQ(d.min_inliers, 30);

  const TRelocalisationParams p = loadParams(
      "[relocalisation]\norb_features = 600\nkeyframe_translation_m = 0.5\nmax_keyframes = 40\n"
      "match_ratio = 0.75\n");
  EXPECT_EQ(p.orb_features, 600);
  EXPECT_DOUBLE_EQ(p.keyframe_translation_m, 0.5);
  EXPECT_EQ(p.max_keyframes, 40);
  EXPECT_DOUBLE_EQ(p.match_ratio, 0.75);
  EXPECT_EQ(p.min_inliers, d.min_inliers);  // default kept

  mrpt::config::CConfigFileMemory saved;
  p.saveToConfigFile(saved, "relocalisation");
  TRelocalisationParams q;
  loadParamsStrict(saved, "relocalisation", q, "saved");
  EXPECT_EQ(q.orb_features, 600);
  EXPECT_DOUBLE_EQ(q.keyframe_translation_m, 0.5);
  EXPECT_EQ(q.max_keyframes, 40);
  EXPECT_EQ(knownKeys(d, "relocalisation").size(), 34u);  // every member is a key
}

TEST(RelocalisationParams, BadValuesNameTheKey) {
  EXPECT_NE(loadError("[relocalisation]\nmatch_ratio = 1.5\n").find("[relocalisation] match_ratio"),
            std::string::npos);
  EXPECT_NE(loadError("[relocalisation]\nmin_inliers = 3\n").find("min_inliers"),
            std::string::npos);
  EXPECT_NE(loadError("[relocalisation]\nmax_depth_m = 0.1\n").find("max_depth_m"),
            std::string::npos);
  EXPECT_NE(loadError("[relocalisation]\nranking_features = 5000\n").find("ranking_features"),
            std::string::npos);
  EXPECT_NE(loadError("[relocalisation]\norb_feature = 500\n").find("orb_feature"),
            std::string::npos);  // unknown
  TRelocalisationParams p;
  p.keyframe_min_features = 2;
  EXPECT_THROW(Relocaliser{p}, InputError);
}

// ---- keyframes ----

TEST(Relocaliser, KeyframeGeometryMatchesTheFrame) {
  const SimSweep& sim = SimSweep::office();
  const RgbdFrame f = sim.frame(40);
  const Eigen::Isometry3d T = sim.pose(40);
  const Relocaliser reloc;
  const std::optional<maps::Keyframe> kf = reloc.makeKeyframe(f, T);
  ASSERT_TRUE(kf);
  EXPECT_TRUE(kf->consistent());
  EXPECT_EQ(kf->frame_index, 40u);
  EXPECT_DOUBLE_EQ(kf->timestamp_s, 40.0 / 30.0);
  EXPECT_TRUE(kf->T_world_cam.isApprox(T));
  EXPECT_EQ(kf->intrinsics, f.intrinsics);
  EXPECT_GE(int(kf->numFeatures()), reloc.params().keyframe_min_features);
  EXPECT_LE(int(kf->numFeatures()), reloc.params().keyframe_max_features);
  // 80 px wide thumbnail of a 640x480 frame.
  EXPECT_EQ(kf->thumb_width, 80);
  EXPECT_EQ(kf->thumb_height, 60);
  // Each world point, seen from the keyframe pose, projects onto its keypoint at the depth the
  // frame measured at the keypoint's pixel (float precision of the stored points: ~1e-6 m at 3 m).
  const CameraIntrinsics& K = f.intrinsics;
  for (std::size_t i = 0; i < kf->numFeatures(); ++i) {
    const Eigen::Vector3d pc = T.inverse() * kf->points_world[i].cast<double>();
    const Eigen::Vector2f& uv = kf->keypoints_px[i];
    ASSERT_NEAR(K.fx * pc.x() / pc.z() + K.cx, uv.x(), 1e-3);
    ASSERT_NEAR(K.fy * pc.y() / pc.z() + K.cy, uv.y(), 1e-3);
    const float z = f.depth_m(int(std::lround(uv.x())), int(std::lround(uv.y())));
    ASSERT_NEAR(pc.z(), z, 1e-5);
    ASSERT_GE(pc.z(), reloc.params().min_depth_m);
    ASSERT_LE(pc.z(), reloc.params().max_depth_m);
  }
}

TEST(Relocaliser, KeyframeSpacingRules) {
  const SimSweep& sim = SimSweep::office();
  RgbdFrame f = sim.frame(40);  // textured: plenty of features; its content does not matter here
  const Eigen::Isometry3d T0 = sim.pose(40);
  TRelocalisationParams P;  // 0.3 m, 20 deg (the geometry below), >= 5 frames apart
  P.keyframe_translation_m = 0.3;
  P.keyframe_rotation_deg = 20.0;
  Relocaliser reloc(P);
  std::vector<maps::Keyframe> db;
  auto offer = [&](std::size_t index, const Eigen::Isometry3d& T) {
    f.index = index;
    return reloc.maybeAddKeyframe(f, T, db);
  };
  EXPECT_TRUE(offer(0, T0));  // empty database
  EXPECT_FALSE(offer(10, T0));
  EXPECT_FALSE(offer(11, translated(T0, {0.2, 0, 0})));  // within 0.3 m and 20 deg
  EXPECT_FALSE(offer(12, rotatedAboutCameraY(translated(T0, {0, 0.1, 0}), 15)));  // ditto
  EXPECT_TRUE(offer(13, translated(T0, {0.35, 0, 0})));  // 0.35 m from keyframe 0
  EXPECT_FALSE(offer(14, rotatedAboutCameraY(T0, 25)));  // far enough, but 1 frame later
  EXPECT_FALSE(reloc.needsKeyframe(rotatedAboutCameraY(T0, 25), 17, db));
  EXPECT_TRUE(reloc.needsKeyframe(rotatedAboutCameraY(T0, 25), 18, db));
  EXPECT_TRUE(offer(18, rotatedAboutCameraY(T0, 25)));  // turning in place adds keyframes
  ASSERT_EQ(db.size(), 3u);
  EXPECT_EQ(db[0].frame_index, 0u);
  EXPECT_EQ(db[1].frame_index, 13u);
  EXPECT_EQ(db[2].frame_index, 18u);

  // A frame without features (black, no depth) adds nothing and delays the next attempt.
  RgbdFrame blank = f;
  blank.colour.setTo(Bgr8{0, 0, 0});
  blank.depth_m.setTo(0.0f);
  blank.index = 40;
  EXPECT_FALSE(reloc.maybeAddKeyframe(blank, translated(T0, {2, 0, 0}), db));
  EXPECT_FALSE(offer(41, translated(T0, {2, 0, 0})));
  EXPECT_TRUE(offer(45, translated(T0, {2, 0, 0})));
  EXPECT_EQ(db.size(), 4u);
  reloc.reset();  // a new sequence may restart frame numbering
  EXPECT_TRUE(offer(0, translated(T0, {-2, 0, 0})));
  EXPECT_EQ(db.size(), 5u);
}

TEST(Relocaliser, FullDatabaseReplacesTheMostRedundantKeyframe) {
  const SimSweep& sim = SimSweep::office();
  RgbdFrame f = sim.frame(40);
  const Eigen::Isometry3d T0 = sim.pose(40);
  TRelocalisationParams P;
  P.max_keyframes = 3;
  P.keyframe_min_interval_frames = 1;
  Relocaliser reloc(P);
  std::vector<maps::Keyframe> db;
  auto offer = [&](std::size_t index, double x) {
    f.index = index;
    return reloc.maybeAddKeyframe(f, translated(T0, {x, 0, 0}), db);
  };
  // Spacing (in units of 0.3 m) to the nearest other keyframe: x=0 -> 1.03, 0.31 -> 1.03, 1.5
  // -> 3.97.
  ASSERT_TRUE(offer(0, 0.0));
  ASSERT_TRUE(offer(1, 0.31));
  ASSERT_TRUE(offer(2, 1.5));
  // x = 3: its nearest keyframe is 5 units away, more than keyframe 0's 1.03: keyframe 0 goes.
  EXPECT_TRUE(offer(3, 3.0));
  ASSERT_EQ(db.size(), 3u);
  EXPECT_EQ(db[0].frame_index, 3u);
  EXPECT_EQ(db[1].frame_index, 1u);
  EXPECT_EQ(db[2].frame_index, 2u);
  // x = 1.85: 1.17 units from its nearest, less than every keyframe's own (3.97, 3.97, 5): kept
  // out.
  EXPECT_FALSE(offer(4, 1.85));
  EXPECT_EQ(db[0].frame_index, 3u);
  EXPECT_EQ(db[1].frame_index, 1u);
  EXPECT_EQ(db[2].frame_index, 2u);
}

// ---- relocalisation ----

TEST(Relocaliser, RecoversSimulatedOfficePoses) {
  const SimSweep& sim = SimSweep::office();
  Relocaliser reloc;
  const std::vector<maps::Keyframe> db = officeKeyframes(reloc, 180);  // first 6 s
  ASSERT_GE(db.size(), 6u);
  // Frames that are no keyframe: midway between consecutive keyframes (6-20 frames, 0.2-0.7 s,
  // from the nearest one), and 10 and 20 frames after the last.
  std::vector<std::size_t> keyframe_index, queries;
  for (const maps::Keyframe& kf : db) keyframe_index.push_back(std::size_t(kf.frame_index));
  std::sort(keyframe_index.begin(), keyframe_index.end());
  for (std::size_t k = 0; k + 1 < keyframe_index.size(); ++k)
    if (keyframe_index[k + 1] - keyframe_index[k] >= 12)
      queries.push_back((keyframe_index[k] + keyframe_index[k + 1]) / 2 | 1);
  queries.push_back(keyframe_index.back() + 11);
  queries.push_back(keyframe_index.back() + 21);
  int tried = 0, found = 0;
  double max_err_m = 0, max_err_deg = 0, ms = 0, detect_ms = 0, match_ms = 0;
  for (std::size_t i : queries) {
    ++tried;
    const std::optional<RelocalisationResult> r = reloc.relocalise(sim.frame(i), db);
    ms += reloc.lastStats().ms;
    detect_ms += reloc.lastStats().detect_ms;
    match_ms += reloc.lastStats().match_ms;
    if (!r) {
      std::printf("frame %zu: not relocalised (%s)\n", i, reloc.lastStats().reason.c_str());
      continue;
    }
    ++found;
    const double em = poseErrorM(r->T_world_cam, sim.pose(i)),
                 ed = poseErrorDeg(r->T_world_cam, sim.pose(i));
    max_err_m = std::max(max_err_m, em);
    max_err_deg = std::max(max_err_deg, ed);
    EXPECT_LT(em, 0.05) << "frame " << i;
    EXPECT_LT(ed, 2.0) << "frame " << i;
    EXPECT_GE(r->inliers, reloc.params().min_inliers);
    EXPECT_LT(r->keyframe, db.size());
    EXPECT_LE(r->reprojection_rms_px, reloc.params().ransac_reprojection_px);
    EXPECT_GE(r->depth_agreeing, reloc.params().min_depth_agreeing);
    EXPECT_TRUE(reloc.lastStats().reason.empty());
  }
  const double n = std::max(tried, 1);
  std::printf(
      "office: %zu keyframes, %d of %d frames relocalised, max error %.3f m %.2f deg, %.1f ms per "
      "call (ORB %.1f, "
      "matching %.1f)\n",
      db.size(), found, tried, max_err_m, max_err_deg, ms / n, detect_ms / n, match_ms / n);
  ASSERT_GE(tried, 6);
  EXPECT_EQ(found, tried);
}

// At 320x240 ORB sees the frame enlarged to 640 px (orb_min_image_width): the views between and
// just after the keyframes of the sweep's first 6 s are relocalised within the 640x480 bar, and
// the views of the shelves and north desks (12-22 s), which no keyframe saw, are not.
TEST(Relocaliser, RecoversOfficePosesAtQuarterVgaAndNoUnrelatedView) {
  const SimSweep& sim = SimSweep::officeQvga();
  Relocaliser reloc;
  const std::vector<maps::Keyframe> db = officeKeyframes(reloc, 180, 2, sim);
  ASSERT_GE(db.size(), 6u);
  int found = 0, tried = 0;
  for (std::size_t i = 17; i <= 209; i += 8) {
    ++tried;
    const std::optional<RelocalisationResult> r = reloc.relocalise(sim.frame(i), db);
    if (!r) {
      std::printf("frame %zu: not relocalised (%s)\n", i, reloc.lastStats().reason.c_str());
      continue;
    }
    ++found;
    EXPECT_LT(poseErrorM(r->T_world_cam, sim.pose(i)), 0.05) << "frame " << i;
    EXPECT_LT(poseErrorDeg(r->T_world_cam, sim.pose(i)), 2.0) << "frame " << i;
  }
  std::printf("320x240: %zu keyframes, %d of %d frames relocalised\n", db.size(), found, tried);
  EXPECT_GE(found, tried - 1);
  for (std::size_t i = 360; i <= 660; i += 20)
    EXPECT_FALSE(reloc.relocalise(sim.frame(i), db)) << "unrelated frame " << i;
}

// The kidnapped sweep at 320x240: keyframes of the first 10 s, then 2 s that never arrive. The
// first frames after the cut still overlap what the keyframes saw (the camera is turning
// towards the shelves); some of them must be found close enough for the ICP verification to
// take over (its reach: 15 cm, 3 deg). With the frame as it is (orb_min_image_width = 0) none of
// the six was found and the run lost 494 of its 841 frames (docs/slam-eval.md).
TEST(Relocaliser, FindsTheFirstFramesAfterACutAtQuarterVga) {
  const SimSweep& sim = SimSweep::officeQvga();
  const auto firstAfterCut = [&](int min_width) {
    TRelocalisationParams p;
    p.orb_min_image_width = min_width;
    Relocaliser reloc(p);
    const std::vector<maps::Keyframe> db = officeKeyframes(reloc, 299, 2, sim);
    int found = 0;
    for (std::size_t i = 360; i <= 365; ++i) {
      const std::optional<RelocalisationResult> r = reloc.relocalise(sim.frame(i), db);
      if (!r) continue;
      ++found;
      EXPECT_LT(poseErrorM(r->T_world_cam, sim.pose(i)), 0.15) << "frame " << i;
      EXPECT_LT(poseErrorDeg(r->T_world_cam, sim.pose(i)), 3.0) << "frame " << i;
    }
    return found;
  };
  const int found = firstAfterCut(TRelocalisationParams().orb_min_image_width);
  std::printf("first 6 frames after the cut: %d relocalised (the frame as it is: %d)\n", found,
              firstAfterCut(0));
  EXPECT_GE(found, 2);
}

TEST(Relocaliser, NoFalsePositiveOnUnrelatedViews) {
  const SimSweep& sim = SimSweep::office();
  Relocaliser reloc;
  const std::vector<maps::Keyframe> db = officeKeyframes(reloc, 180);
  // 12-22 s of the sweep look at the shelves and the north desks, which the first 6 s never saw.
  int accepted = 0;
  for (std::size_t i = 360; i <= 660; i += 20) {
    const std::optional<RelocalisationResult> r = reloc.relocalise(sim.frame(i), db);
    if (r) {
      ++accepted;
      ADD_FAILURE() << "frame " << i << " relocalised at "
                    << poseErrorM(r->T_world_cam, sim.pose(i)) << " m from the truth ("
                    << r->inliers << " inliers)";
    }
  }
  EXPECT_EQ(accepted, 0);
  // Another world altogether.
  const SimSweep& lab = SimSweep::lab();
  for (std::size_t i = 0; i <= 420; i += 60)
    EXPECT_FALSE(reloc.relocalise(lab.frame(i), db)) << "lab frame " << i;

  // A frame the keyframes do see, mirrored left-right (colour and depth): a scene that is no
  // rigid motion of the map.
  const RgbdFrame seen = sim.frame(45);
  ASSERT_TRUE(reloc.relocalise(seen, db));
  RgbdFrame mirrored = seen;
  for (int y = 0; y < seen.height(); ++y)
    for (int x = 0; x < seen.width(); ++x) {
      mirrored.colour(x, y) = seen.colour(seen.width() - 1 - x, y);
      mirrored.depth_m(x, y) = seen.depth_m(seen.width() - 1 - x, y);
    }
  EXPECT_FALSE(reloc.relocalise(mirrored, db));

  // The same frame without depth: its pose cannot be checked against the geometry.
  RgbdFrame no_depth = seen;
  no_depth.depth_m.setTo(0.0f);
  EXPECT_FALSE(reloc.relocalise(no_depth, db));
  EXPECT_EQ(reloc.lastStats().reason, "depth check");

  // A covered lens: black colour, zero depth.
  RgbdFrame black = seen;
  black.colour.setTo(Bgr8{0, 0, 0});
  black.depth_m.setTo(0.0f);
  std::optional<RelocalisationResult> r;
  EXPECT_NO_THROW(r = reloc.relocalise(black, db));
  EXPECT_FALSE(r);
  EXPECT_EQ(reloc.lastStats().reason, "too few features");
  EXPECT_EQ(reloc.lastStats().features, 0);

  // No colour, no database.
  RgbdFrame colourless = seen;
  colourless.colour = Image<Bgr8>();
  EXPECT_FALSE(reloc.relocalise(colourless, db));
  EXPECT_EQ(reloc.lastStats().reason, "no colour");
  EXPECT_FALSE(reloc.relocalise(seen, {}));
  EXPECT_EQ(reloc.lastStats().reason, "empty database");
}

TEST(Relocaliser, KeyframesFromASavedMapRelocaliseIdentically) {
  const SimSweep& sim = SimSweep::office();
  Relocaliser reloc;
  maps::CSurfelMap map;
  map.keyframes() = officeKeyframes(reloc, 120, 4);
  ASSERT_GE(map.keyframes().size(), 4u);

  mrpt::io::CMemoryStream buf;
  auto out = mrpt::serialization::archiveFrom(buf);
  out << map;
  buf.Seek(0);
  auto in = mrpt::serialization::archiveFrom(buf);
  mrpt::serialization::CSerializable::Ptr obj;
  in >> obj;
  const auto loaded = std::dynamic_pointer_cast<maps::CSurfelMap>(obj);
  ASSERT_TRUE(loaded);
  ASSERT_EQ(loaded->keyframes().size(), map.keyframes().size());

  Relocaliser other;  // a new run: nothing shared but the map
  const RgbdFrame f = sim.frame(65);
  const auto a = reloc.relocalise(f, map.keyframes());
  const auto b = other.relocalise(f, loaded->keyframes());
  ASSERT_TRUE(a);
  ASSERT_TRUE(b);
  EXPECT_EQ(a->keyframe, b->keyframe);
  EXPECT_EQ(a->inliers, b->inliers);
  EXPECT_TRUE(a->T_world_cam.isApprox(b->T_world_cam, 1e-12));
  EXPECT_LT(poseErrorM(b->T_world_cam, sim.pose(65)), 0.05);
}

// ---- real data ----

namespace {

fs::path fr3CabinetKeyframes() {
  return fs::path(RASM_SHARED_DATA) / "tum" / "fr3_cabinet_keyframes";
}

/// The 58 keyframes and their poses (truth_cam_poses.txt: row k = keyframe k, T_world_cam).
void readFr3CabinetKeyframes(const fs::path& dir, io::Trajectory& gt,
                             std::vector<RgbdFrame>& frames) {
  gt = io::readTumTrajectory((dir / "truth_cam_poses.txt").string());
  const std::unique_ptr<io::FrameSource> src = io::openFrameSource(dir.string());
  while (std::optional<RgbdFrame> f = src->next()) frames.push_back(std::move(*f));
}

}  // namespace

TEST(Relocaliser, Fr3CabinetLeaveOneOut) {
  const fs::path dir = fr3CabinetKeyframes();
  if (!fs::is_directory(dir)) GTEST_SKIP() << dir.string() << " absent";
  io::Trajectory gt;
  std::vector<RgbdFrame> frames;
  readFr3CabinetKeyframes(dir, gt, frames);
  ASSERT_EQ(frames.size(), 58u);
  ASSERT_EQ(gt.size(), frames.size());

  Relocaliser reloc;
  std::vector<std::optional<maps::Keyframe>> kfs;
  for (std::size_t k = 0; k < frames.size(); ++k)
    kfs.push_back(reloc.makeKeyframe(frames[k], gt[k].T_world_cam));
  int within = 0, inaccurate = 0, gross = 0, none = 0;
  double ms = 0, max_ms = 0, detect_ms = 0, match_ms = 0;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    std::vector<maps::Keyframe> db;
    for (std::size_t j = 0; j < frames.size(); ++j)
      if (j != k && kfs[j]) db.push_back(*kfs[j]);
    const std::optional<RelocalisationResult> r = reloc.relocalise(frames[k], db);
    ms += reloc.lastStats().ms;
    detect_ms += reloc.lastStats().detect_ms;
    match_ms += reloc.lastStats().match_ms;
    max_ms = std::max(max_ms, reloc.lastStats().ms);
    if (!r) {
      ++none;
      continue;
    }
    const double em = poseErrorM(r->T_world_cam, gt[k].T_world_cam);
    const double ed = poseErrorDeg(r->T_world_cam, gt[k].T_world_cam);
    if (em < 0.05 && ed < 3.0)
      ++within;
    else if (em < 0.15 && ed < 6.0)
      ++inaccurate;  // within ICP's reach (the Mapper verifies every relocalisation by ICP)
    else {
      ++gross;
      ADD_FAILURE() << "keyframe " << k << ": relocalised " << em << " m / " << ed
                    << " deg from the truth";
    }
  }
  const double n = double(frames.size());
  std::printf(
      "fr3_cabinet leave-one-out: %d within 5 cm / 3 deg, %d within 15 cm / 6 deg, %d wrong, %d "
      "not "
      "relocalised; %.1f ms per call (ORB %.1f, matching %.1f; max %.1f) against 57 keyframes\n",
      within, inaccurate, gross, none, ms / n, detect_ms / n, match_ms / n, max_ms);
  EXPECT_EQ(gross, 0);
  EXPECT_GE(within, 44);  // measured 49 (2 cores, OpenCV 4.6)
  EXPECT_GE(within + inaccurate, 50);
}

// [relocalisation] last_fused_*: each fr3_cabinet keyframe against the one before it alone (the
// reference a lost frame tries first), at the looser acceptance: measured 51 of 57 pairs, the
// worst 7.6 cm / 3.8 deg; with the map-wide acceptance 33 of 57.
TEST(Relocaliser, Fr3CabinetEachKeyframeAgainstThePreviousOne) {
  const fs::path dir = fr3CabinetKeyframes();
  if (!fs::is_directory(dir)) GTEST_SKIP() << dir.string() << " absent";
  io::Trajectory gt;
  std::vector<RgbdFrame> frames;
  readFr3CabinetKeyframes(dir, gt, frames);
  ASSERT_EQ(frames.size(), 58u);
  ASSERT_EQ(gt.size(), frames.size());
  const TRelocalisationParams map_wide;
  Relocaliser strict(map_wide), loose(map_wide.forLastFusedFrame());
  int found_strict = 0, found = 0, within = 0;
  for (std::size_t k = 1; k < frames.size(); ++k) {
    std::vector<maps::Keyframe> db;
    if (auto kf = loose.makeKeyframe(frames[k - 1], gt[k - 1].T_world_cam)) db.push_back(*kf);
    found_strict += strict.relocalise(frames[k], db).has_value();
    const std::optional<RelocalisationResult> r = loose.relocalise(frames[k], db);
    if (!r) continue;
    ++found;
    const double em = poseErrorM(r->T_world_cam, gt[k].T_world_cam);
    const double ed = poseErrorDeg(r->T_world_cam, gt[k].T_world_cam);
    // ICP's reach (it verifies every candidate); beyond it a candidate is wrong.
    EXPECT_TRUE(em < 0.15 && ed < 6.0) << "keyframe " << k << ": " << em << " m / " << ed << " deg";
    within += em < 0.10 && ed < 5.0;
  }
  std::printf(
      "fr3_cabinet, each keyframe against the previous one: %d of %zu (map-wide "
      "acceptance: %d), %d within 10 cm / 5 deg\n",
      found, frames.size() - 1, found_strict, within);
  EXPECT_GE(found, 45);                 // measured 51
  EXPECT_GT(found, found_strict + 10);  // measured 33
  EXPECT_EQ(within, found);
}
