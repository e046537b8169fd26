// A hand-held pan along a long plain wall that carries a colour texture, with the floor in view
// and no odometry: the geometry of wall + floor leaves one direction free (the translation along
// their intersection, the direction of the pan), the colour does not. Every frame the tracker
// reports tracked must be where the camera is (checked against the simulator's truth in the
// world frame, no alignment); a frame it cannot support must be reported lost, never accepted off.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "rasm/core/SE3.h"
#include "rasm/io/Trajectory.h"
#include "rasm/run/MappingRun.h"
#include "run/RunTestFiles.h"

namespace fs = std::filesystem;
using namespace rasm;
using namespace rasm::pipeline;
using namespace rasm::autonomy;
using namespace rasm::run;
using namespace rasm::run::testing;

namespace {

/// A 14 m wall in the plane y = 0 (its ends never in view) with a 0.25 m checker of two greys
/// (a plain wall in geometry, not in colour) and a uniformly coloured floor in front of it.
const char* kPlainWallWorld = R"(world: plain_wall
light: {direction: [0.3, 0.2, -1.0], ambient: 0.35, diffuse: 0.65}
static:
  - {id: 1, class: floor, primitive: box, size: [14, 6, 0.1], position: [3, 3, -0.05],
     colour: [150, 150, 145]}
  - {id: 2, class: wall, primitive: box, size: [14, 0.1, 2.7], position: [3, -0.05, 1.35],
     colour: [215, 210, 190], texture: {pattern: checker, colour2: [150, 140, 120], period_m: 0.25}}
)";

/// A hand-held camera 1.8 m from the wall, 1.3 m high, pitched ~24 deg down (the wall and the
/// floor's last 0.65 m before it in view), walking 1.6 m along the wall in 3 s (up to 0.74 m/s
/// in the middle: 2.5 cm per frame) and panning by ~8 deg, with hand tremor.
const char* kPanAlongWall = R"(type: handheld
rate_hz: 30
jitter: {translation_m: 0.002, rotation_deg: 0.2, frequency_hz: 1.5}
keyframes:
  - {t: 0, position: [1.0, 1.8, 1.30], look_at: [1.0, 0.0, 0.5]}
  - {t: 1.5, position: [1.8, 1.75, 1.32], look_at: [1.9, 0.0, 0.5]}
  - {t: 3, position: [2.6, 1.8, 1.30], look_at: [2.85, 0.0, 0.5]}
)";

struct PanOutcome {
  int frames = 0, tracked = 0;
};

/// Runs the pan in `world` and checks that every frame reported tracked is within 2 cm of the
/// truth (the bound of a pan the colour constrains); prints and returns the tracked share.
PanOutcome runPan(const std::string& name, const std::string& world_yaml) {
  const std::string dir = tempDir(name);
  const std::string world = dir + "/world.yaml", traj = dir + "/pan.yaml";
  std::ofstream(world) << world_yaml;
  std::ofstream(traj) << kPanAlongWall;
  RunConfig cfg = RunConfig::embeddedDefault();
  cfg.set("output", "dir", dir + "/out");
  cfg.set("exploration", "enabled", "false");
  cfg.set("sim", "world", world);
  cfg.set("sim", "trajectory", traj);
  cfg.set("classification", "detectors", "");
  setQuarterVgaCamera(cfg);
  cfg.set("output", "write_3dscene", "false");
  cfg.set("output", "write_ply", "false");
  cfg.set("output", "preview_png", "false");
  MappingRun run(cfg);
  std::vector<FrameResult> frames;
  run.run([&](const FrameResult& r) { frames.push_back(r); });
  const io::Trajectory gt = io::readTumTrajectory(dir + "/out/groundtruth.txt");
  EXPECT_EQ(gt.size(), frames.size());
  PanOutcome o;
  o.frames = int(std::min(gt.size(), frames.size()));
  double worst_tracked_m = 0.0, worst_any_m = 0.0;
  for (int i = 0; i < o.frames; ++i) {
    const FrameResult& r = frames[i];
    const double err = translationDistance(gt[i].T_world_cam, r.T_world_cam);
    worst_any_m = std::max(worst_any_m, err);
    if (!r.tracked) continue;
    ++o.tracked;
    worst_tracked_m = std::max(worst_tracked_m, err);
    EXPECT_LT(err, 0.02) << name << ": frame " << r.index << " reported tracked " << err * 100
                         << " cm from the truth (status " << toString(r.tracking.status) << ")";
  }
  std::cout << name << ": " << o.tracked << " of " << o.frames << " frames tracked; worst tracked "
            << worst_tracked_m * 100 << " cm, worst of all " << worst_any_m * 100 << " cm\n";
  fs::remove_all(dir);
  return o;
}

}  // namespace

/// The textured wall: the colour holds the direction the geometry leaves free, so the pan is
/// tracked, not only refused. Without the photometric retry of degenerate frames
/// ([tracking] photometric_weight_degenerate = 0) 4 of 91 frames were tracked and the rest lost
/// (the stable model covers a third of the view after 4 frames, a degenerate frame needs 70%),
/// and relocalisation on the checker's repeated corners accepted one frame 50 cm (two periods)
/// off; with it, 91 of 91 within 0.3 cm. The share asked of hand-held runs is 99%; over 91
/// frames 95% leaves 4 frames of margin for another platform's arithmetic.
TEST(PlainWallPan, TexturedWallIsTrackedWithinTwoCentimetres) {
  const PanOutcome o = runPan("plain_wall_pan_textured", kPlainWallWorld);
  ASSERT_GE(o.frames, 80);
  EXPECT_GE(double(o.tracked) / o.frames, 0.95);
}

/// The same wall without its texture: nothing holds the slide along it, so the frames must be
/// reported lost (the motion model's guess, not fused), never accepted off.
TEST(PlainWallPan, UntexturedWallIsReportedLostNotAcceptedOff) {
  std::string plain = kPlainWallWorld;
  const std::string texture =
      ", texture: {pattern: checker, colour2: [150, 140, 120], period_m: 0.25}";
  const std::size_t at = plain.find(texture);
  ASSERT_NE(at, std::string::npos);
  plain.erase(at, texture.size());
  const PanOutcome o = runPan("plain_wall_pan_untextured", plain);
  ASSERT_GE(o.frames, 80);
  EXPECT_LT(o.tracked, o.frames / 2) << "tracked along a wall nothing constrains";
}
