// Generated worlds and trajectories (`rasm sim generate`): deterministic by seed, load with the
// world loader, furniture footprints never overlap, objects rest on their surfaces, the free area
// is free, the robot loop starts collision-free and drives without colliding while the camera
// sees geometry, the hand-held keyframes look at things 1-3 m away and every hand-held frame sees
// objects and furniture with normals in three directions, the fast variant peaks at 120-150
// deg/s about each camera axis, bad sizes and kinds fail naming the option. Flats: every room is
// reachable from the hallway through its doorway (and only through it), footprints keep off the
// doorways and each other, the robot starts in the hallway; plain sides stay bare and break rooms
// have their counter; the room layout's text is what it was before flats existed.
#include "rasm/sim/WorldGenerator.h"

#include <gtest/gtest.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <queue>
#include <sstream>

#include "rasm/core/Error.h"
#include "rasm/models/ClassVocabulary.h"
#include "rasm/sim/OccupancyRaster.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/RgbdSensor.h"
#include "rasm/sim/SimulatedDiffDriveRobot.h"
#include "rasm/sim/SimulatedSequence.h"
#include "rasm/sim/Trajectory.h"
#include "rasm/sim/TrajectoryGenerator.h"
#include "rasm/sim/ViewStats.h"
#include "rasm/sim/World.h"

namespace fs = std::filesystem;
using namespace rasm::sim;
using namespace rasm::models;

namespace {

TWorldGenParams params(std::uint64_t seed, RoomKind kind = RoomKind::Mixed, double w = 0,
                       double d = 0) {
  TWorldGenParams p;
  p.seed = seed;
  p.kind = kind;
  p.width_m = w;
  p.depth_m = d;
  return p;
}

std::string readFile(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& tag) {
    path = fs::temp_directory_path() / ("rasm_gen_" + tag + "_" + std::to_string(::getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

/// The loaded world's object of a placement.
const WorldObject& objectOf(const World& w, std::uint16_t id) {
  const int i = w.indexOfInstance(id);
  if (i < 0) throw std::runtime_error("no instance " + std::to_string(id));
  return w.objects[std::size_t(i)];
}

/// Sensor overrides for a 160 x 120 camera with the Kinect's field of view.
std::map<std::string, std::string> smallCamera() {
  return {{"width", "160"}, {"height", "120"}, {"fx", "131.25"},   {"fy", "131.25"},
          {"cx", "79.5"},   {"cy", "59.5"},    {"labels", "false"}};
}

/// Fraction of the pixels with a depth (> 0, the sensor's range is 0.4-4.5 m) up to max_m.
double validFraction(const rasm::RgbdFrame& f, float max_m = 100.f) {
  std::size_t n = 0;
  for (int y = 0; y < f.depth_m.height(); ++y)
    for (int x = 0; x < f.depth_m.width(); ++x) {
      const float z = f.depth_m.row(y)[x];
      n += z > 0.f && z <= max_m ? 1 : 0;
    }
  return double(n) / double(f.depth_m.width() * f.depth_m.height());
}

}  // namespace

TEST(WorldGenerator, SameSeedSameTextOtherSeedsDiffer) {
  for (RoomKind k : {RoomKind::Office, RoomKind::Lab, RoomKind::Mixed}) {
    const GeneratedWorld a = generateWorld(params(7, k)), b = generateWorld(params(7, k));
    EXPECT_EQ(a.yaml, b.yaml);
    EXPECT_NE(a.yaml, generateWorld(params(8, k)).yaml);
  }
  // A drawn size, given explicitly, gives the same room.
  const GeneratedWorld drawn = generateWorld(params(11));
  const GeneratedWorld given =
      generateWorld(params(11, RoomKind::Mixed, drawn.params.width_m, drawn.params.depth_m));
  EXPECT_EQ(drawn.yaml, given.yaml);
  EXPECT_GE(drawn.params.width_m, 5.5);
  EXPECT_LE(drawn.params.width_m, 9.0);
}

TEST(WorldGenerator, FilesAreByteIdenticalForTheSameSeed) {
  TempDir t1("det1"), t2("det2");
  GenerateFilesResult r1 = generateWorldFiles(params(3, RoomKind::Office, 6, 5),
                                              (t1.path / "room.yaml").string(), "", true);
  GenerateFilesResult r2 = generateWorldFiles(params(3, RoomKind::Office, 6, 5),
                                              (t2.path / "room.yaml").string(), "", true);
  ASSERT_EQ(r1.trajectory_paths.size(), 4u);
  EXPECT_EQ(readFile(r1.world_path), readFile(r2.world_path));
  for (const char* f : {"room_handheld.yaml", "room_robot.yaml", "room_handheld_fast.yaml",
                        "room_robot_fast.yaml"}) {
    EXPECT_TRUE(fs::is_regular_file(t1.path / f)) << f;
    EXPECT_EQ(readFile(t1.path / f), readFile(t2.path / f)) << f;
    // The spec names its world by a path relative to itself, and loads.
    const TrajectorySpec spec = loadTrajectorySpec((t1.path / f).string());
    EXPECT_EQ(fs::path(spec.world), t1.path / "room.yaml") << f;
  }
  EXPECT_FALSE(fs::exists(t1.path / "room.yaml.part"));
  // --trajectories as a folder and as a prefix.
  generateWorldFiles(params(3, RoomKind::Office, 6, 5), (t1.path / "w2.yaml").string(),
                     (t1.path / "specs/").string());
  EXPECT_TRUE(fs::is_regular_file(t1.path / "specs/w2_robot.yaml"));
  EXPECT_EQ(loadTrajectorySpec((t1.path / "specs/w2_robot.yaml").string()).world,
            (t1.path / "specs/../w2.yaml").lexically_normal().string());
  generateWorldFiles(params(3, RoomKind::Office, 6, 5), (t1.path / "w3.yaml").string(),
                     (t1.path / "p/run").string());
  EXPECT_TRUE(fs::is_regular_file(t1.path / "p/run_handheld.yaml"));
}

TEST(WorldGenerator, LoadsWithValidClassesAndUniqueIds) {
  for (std::uint64_t seed : {1, 2, 3, 4}) {
    for (RoomKind k : {RoomKind::Office, RoomKind::Lab, RoomKind::Mixed}) {
      const GeneratedWorld g = generateWorld(params(seed, k));
      World w;
      ASSERT_NO_THROW(w = loadWorldFromString(g.yaml, g.name + ".yaml")) << g.name;
      EXPECT_EQ(w.name, g.name);
      ASSERT_EQ(w.objects.size(), g.placements.size());
      int counts[5] = {0, 0, 0, 0, 0};
      for (std::size_t i = 0; i < w.objects.size(); ++i) {
        const GeneratedWorld::Placement& p = g.placements[i];
        EXPECT_EQ(w.objects[i].instance_id, p.id);
        EXPECT_EQ(int(w.objects[i].class_id), classIdFromName(p.class_name));
        ++counts[int(p.rest)];
      }
      // Structure (floor, ceiling, four walls), furniture and things on surfaces.
      EXPECT_EQ(counts[int(GeneratedWorld::Rest::Structure)], 6) << g.name;
      EXPECT_GE(counts[int(GeneratedWorld::Rest::Floor)], 4) << g.name;
      EXPECT_GE(counts[int(GeneratedWorld::Rest::Surface)], 8) << g.name;
      for (const char* cls : {"floor", "wall", "ceiling", "door"}) {
        bool found = false;
        for (const auto& o : w.objects) found = found || o.class_id == classIdFromName(cls);
        EXPECT_TRUE(found) << g.name << " has no " << cls;
      }
    }
  }
}

TEST(WorldGenerator, FurnitureFootprintsDoNotOverlapAndTheFreeAreaIsFree) {
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    const RoomKind kind = RoomKind(seed % 3);
    const GeneratedWorld g = generateWorld(params(seed, kind));
    const World w = loadWorldFromString(g.yaml, g.name);
    const double W = g.params.width_m, D = g.params.depth_m;
    const double keep = g.params.robot_radius_m + g.params.clearance_m;
    EXPECT_GE(g.free_area.width(), 1.0 - 1e-9) << g.name;
    EXPECT_GE(g.free_area.depth(), 1.0 - 1e-9) << g.name;
    std::vector<std::pair<std::string, Eigen::AlignedBox3f>> furniture;
    for (const auto& p : g.placements) {
      if (p.rest == GeneratedWorld::Rest::Structure) continue;
      const Eigen::AlignedBox3f b = objectOf(w, p.id).worldMesh().bounds();
      // Inside the room.
      EXPECT_GE(b.min().x(), -1e-3) << p.name;
      EXPECT_GE(b.min().y(), -1e-3) << p.name;
      EXPECT_LE(b.max().x(), W + 1e-3) << p.name;
      EXPECT_LE(b.max().y(), D + 1e-3) << p.name;
      // Whatever reaches into the robot's height band keeps its distance from the free area.
      if (b.min().z() < 0.6) {
        const bool clear = b.max().x() <= g.free_area.x0 - keep + 1e-3 ||
                           b.min().x() >= g.free_area.x1 + keep - 1e-3 ||
                           b.max().y() <= g.free_area.y0 - keep + 1e-3 ||
                           b.min().y() >= g.free_area.y1 + keep - 1e-3;
        EXPECT_TRUE(clear) << g.name << ": " << p.id << " " << p.class_name << " " << p.name;
      }
      if (p.furniture) furniture.emplace_back(std::to_string(p.id) + " " + p.class_name, b);
    }
    EXPECT_GE(furniture.size(), 4u) << g.name;
    for (std::size_t i = 0; i < furniture.size(); ++i)
      for (std::size_t j = i + 1; j < furniture.size(); ++j) {
        const auto &a = furniture[i].second, &b = furniture[j].second;
        const bool overlap = a.min().x() < b.max().x() - 1e-3 && b.min().x() < a.max().x() - 1e-3 &&
                             a.min().y() < b.max().y() - 1e-3 && b.min().y() < a.max().y() - 1e-3;
        EXPECT_FALSE(overlap) << g.name << ": " << furniture[i].first << " and "
                              << furniture[j].first;
      }
  }
}

TEST(WorldGenerator, ObjectsRestOnTheirSurfaces) {
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const GeneratedWorld g = generateWorld(params(seed, RoomKind(seed % 3)));
    const RayScene scene(loadWorldFromString(g.yaml, g.name));
    const World& w = scene.world();
    int on_surfaces = 0;
    for (const auto& p : g.placements) {
      const int i = w.indexOfInstance(p.id);
      ASSERT_GE(i, 0);
      const Eigen::AlignedBox3f b = scene.objectBounds(i);
      if (p.rest == GeneratedWorld::Rest::Floor) {
        EXPECT_NEAR(b.min().z(), 0.0, 0.01) << g.name << " " << p.id << " " << p.name;
      } else if (p.rest == GeneratedWorld::Rest::Surface) {
        ++on_surfaces;
        EXPECT_NEAR(b.min().z(), p.surface_z_m, 0.01) << g.name << " " << p.id << " " << p.name;
        // Straight below the object's middle, its support's surface is at that height.
        const int s = w.indexOfInstance(p.support_id);
        ASSERT_GE(s, 0);
        const Eigen::Vector3f c = b.center();
        const RayHit h = scene.castRayAlone(s, Eigen::Vector3f(c.x(), c.y(), b.min().z() + 0.005f),
                                            Eigen::Vector3f(0, 0, -1));
        ASSERT_TRUE(h.hit) << g.name << " " << p.id << " " << p.class_name << " on "
                           << p.support_id;
        EXPECT_NEAR(h.point.z(), b.min().z(), 0.01)
            << g.name << " " << p.id << " " << p.class_name << " on " << p.support_id;
      }
    }
    EXPECT_GT(on_surfaces, 8) << g.name;
  }
}

TEST(WorldGenerator, BadSizeAndKindNameTheOption) {
  auto error = [](const TWorldGenParams& p) {
    try {
      generateWorld(p);
    } catch (const rasm::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  std::string e = error(params(1, RoomKind::Mixed, 1, 1));
  EXPECT_NE(e.find("--size 1x1"), std::string::npos) << e;
  EXPECT_NE(e.find("too small"), std::string::npos) << e;
  e = error(params(1, RoomKind::Mixed, 30, 5));
  EXPECT_NE(e.find("too large"), std::string::npos) << e;
  e = error(params(1, RoomKind::Mixed, 5, -2));
  EXPECT_NE(e.find("--size"), std::string::npos) << e;
  try {
    roomKindFromName("kitchen", "--kind");
    ADD_FAILURE();
  } catch (const rasm::InputError& ex) {
    EXPECT_NE(std::string(ex.what()).find("--kind kitchen"), std::string::npos) << ex.what();
    EXPECT_NE(std::string(ex.what()).find("office, lab, mixed or break_room"), std::string::npos);
  }
  // The smallest room still gets furniture and a free area.
  const GeneratedWorld small = generateWorld(params(2, RoomKind::Office, 3, 3));
  EXPECT_GE(small.free_area.width(), 1.0 - 1e-9);
  EXPECT_NO_THROW(loadWorldFromString(small.yaml, "small"));
}

TEST(TrajectoryGenerator, HandheldLooksAtThingsFromChestHeight) {
  for (std::uint64_t seed : {1, 5}) {
    const GeneratedWorld g = generateWorld(params(seed));
    const World w = loadWorldFromString(g.yaml, g.name);
    TTrajectoryGenParams tp;
    tp.seed = seed;
    const GeneratedTrajectory h = generateHandheldTrajectory(g, w, tp);
    const TrajectorySpec spec = loadTrajectorySpecFromString(h.yaml, "handheld");
    EXPECT_GE(spec.keyframes.back().t_s, 20.0);
    EXPECT_LE(spec.keyframes.back().t_s, 30.0);
    for (std::size_t i = 1; i < spec.keyframes.size(); ++i) {
      const double dt = spec.keyframes[i].t_s - spec.keyframes[i - 1].t_s;
      EXPECT_GE(dt, 2.9);
      EXPECT_LE(dt, 6.0);
    }
    const RayScene scene(w);
    const YAML::Node doc = YAML::Load(h.yaml);
    ASSERT_EQ(doc["keyframes"].size(), spec.keyframes.size());
    for (std::size_t i = 0; i < spec.keyframes.size(); ++i) {
      const Eigen::Isometry3d& T = spec.keyframes[i].T_world_cam;
      const Eigen::Vector3d p = T.translation();
      EXPECT_GE(p.z(), 1.2 - 1e-9);
      EXPECT_LE(p.z(), 1.7 + 1e-9);
      // It looks at a target 1-3 m away, in plain view.
      const YAML::Node at = doc["keyframes"][i]["look_at"];
      ASSERT_TRUE(at.IsSequence());
      const Eigen::Vector3d target(at[0].as<double>(), at[1].as<double>(), at[2].as<double>());
      EXPECT_GE((target - p).norm(), 1.0 - 1e-3);
      EXPECT_LE((target - p).norm(), 3.0 + 1e-3);
      const RayHit hit = scene.castRay(p.cast<float>(), (target - p).cast<float>(), 0.f, 1.f);
      EXPECT_TRUE(!hit.hit || hit.t * (target - p).norm() > (target - p).norm() - 0.25);
      // Along the optical axis, something within the sensor's range.
      const RayHit axis = scene.castRay(p.cast<float>(), T.linear().col(2).cast<float>());
      ASSERT_TRUE(axis.hit);
      EXPECT_GE(axis.t, 0.5);
      EXPECT_LE(axis.t, 4.5);
    }
    EXPECT_GE(h.min_valid_fraction, tp.min_valid_handheld) << h.summary;
    EXPECT_GE(h.min_object_fraction, tp.min_object_fraction_handheld) << h.summary;
    EXPECT_GE(h.min_normal_eig, tp.min_normal_eig_handheld) << h.summary;
    EXPECT_EQ(h.summary.find("WARNING"), std::string::npos) << h.summary;
  }
}

// Every frame of the hand-held specs (as written and loaded, at 30 Hz, without the recorder's
// jitter) sees objects and furniture, with normals in three directions: the view rule at the
// check's own resolution (80 x 60, exact depth), on the very frames the generator checked. Seed
// 7's fast spec used to stare at the striped floor alone around t = 1.5 s.
TEST(TrajectoryGenerator, HandheldFramesSeeObjectsAndThreeNormalDirections) {
  for (std::uint64_t seed : {7}) {
    const GeneratedWorld g = generateWorld(params(seed));
    const World w = loadWorldFromString(g.yaml, g.name);
    const RayScene scene(w);
    TSensorParams sp;
    sp.width = 80;
    sp.height = 60;
    sp.fx = sp.fy = 525.0 / 8.0;
    sp.cx = 39.5;
    sp.cy = 29.5;
    sp.noise = false;
    sp.max_depth_m = 4.0;
    const RgbdSensor sensor(scene, sp);
    for (bool fast : {false, true}) {
      TTrajectoryGenParams tp;
      tp.seed = seed;
      tp.fast = fast;
      const GeneratedTrajectory h = generateHandheldTrajectory(g, w, tp);
      EXPECT_EQ(h.summary.find("WARNING"), std::string::npos) << h.summary;
      const TrajectorySpec spec = loadTrajectorySpecFromString(h.yaml, "handheld");
      HandJitter none;
      none.translation_m = none.rotation_deg = 0.0;
      const HandheldTrajectory traj(spec.keyframes, none, 0);
      int frames = 0;
      rasm::RgbdFrame f;
      for (;; ++frames) {
        const double t = traj.startTime() + frames / 30.0;
        if (t > traj.endTime() + 1e-9) break;
        sensor.render(traj.smoothPose(t), 0, 0, f);
        const ViewStats v = viewStats(f, 4.0);
        EXPECT_GE(v.valid_fraction, tp.min_valid_handheld) << g.name << " t " << t;
        EXPECT_GE(v.object_fraction, tp.min_object_fraction_handheld)
            << g.name << (fast ? " fast" : "") << " t " << t;
        EXPECT_GE(v.normal_min_eig, tp.min_normal_eig_handheld)
            << g.name << (fast ? " fast" : "") << " t " << t;
      }
      EXPECT_GT(frames, 600);
    }
  }
}

TEST(TrajectoryGenerator, FastHandheldPeaksAt120To150DegPerSecondAboutEachAxis) {
  const GeneratedWorld g = generateWorld(params(4, RoomKind::Office));
  const World w = loadWorldFromString(g.yaml, g.name);
  TTrajectoryGenParams tp;
  tp.seed = 4;
  tp.fast = true;
  const GeneratedTrajectory h = generateHandheldTrajectory(g, w, tp);
  const TrajectorySpec spec = loadTrajectorySpecFromString(h.yaml, "fast");
  HandJitter none;
  none.translation_m = none.rotation_deg = 0.0;
  const HandheldTrajectory traj(spec.keyframes, none, 0);
  // Peak body rates from the spec as loaded (finite differences at 600 Hz).
  Eigen::Vector3d peak = Eigen::Vector3d::Zero();
  for (double t = traj.startTime(); t < traj.endTime(); t += 1.0 / 600.0) {
    const Eigen::AngleAxisd aa(traj.smoothPose(t).linear().transpose() *
                               traj.smoothPose(t + 1.0 / 600.0).linear());
    peak = peak.cwiseMax((aa.axis() * aa.angle() * 600.0 * 180.0 / M_PI).cwiseAbs());
  }
  for (int a = 0; a < 3; ++a) {
    EXPECT_GE(peak[a], 118.0) << "axis " << a << ": " << h.summary;
    EXPECT_LE(peak[a], 152.0) << "axis " << a << ": " << h.summary;
  }
  EXPECT_GE(traj.endTime() - traj.startTime(), 20.0);
}

TEST(TrajectoryGenerator, RobotLoopStartsFreeAndDrivesWithoutCollisionSeeingGeometry) {
  for (std::uint64_t seed : {1, 2, 3}) {
    for (bool fast : {false, true}) {
      const GeneratedWorld g = generateWorld(params(seed, RoomKind(seed % 3)));
      const World w = loadWorldFromString(g.yaml, g.name);
      TTrajectoryGenParams tp;
      tp.seed = seed;
      tp.fast = fast;
      const GeneratedTrajectory r = generateRobotTrajectory(g, w, tp);
      EXPECT_EQ(r.summary.find("WARNING"), std::string::npos) << r.summary;
      const TrajectorySpec spec = loadTrajectorySpecFromString(r.yaml, "robot");
      if (fast) {
        EXPECT_EQ(spec.controller.max_w_degps, 90.0);
        EXPECT_EQ(spec.robot_overrides.at("max_w_degps"), "90");
      }
      // The start pose is free.
      const RayScene scene(w);
      TRobotParams rp;
      applyParamOverrides(rp, "sim_robot", spec.robot_overrides, "robot");
      EXPECT_NO_THROW(SimulatedDiffDriveRobot(scene, rp, spec.start_pose, 1));
      // 300 frames (10 s) as the recorder renders them, at 160 x 120.
      SequenceOptions so;
      so.seed = seed;
      so.max_frames = 300;
      so.sensor_overrides = smallCamera();
      SimulatedSequence seq(w, spec, so);
      rasm::RgbdFrame f;
      double worst = 1.0;
      int frames = 0;
      while (seq.next(f)) {
        ++frames;
        EXPECT_FALSE(seq.robot()->collided()) << g.name << " frame " << frames;
        worst = std::min(worst, validFraction(f));
      }
      EXPECT_FALSE(seq.robotStuck());
      EXPECT_EQ(frames, 300);
      EXPECT_GE(worst, 0.35) << g.name << (fast ? " fast" : "");
    }
  }
}

// Not part of the suite: over many seeds, records every generated trajectory as the recorder
// would (160 x 120, full noise model) and prints, per world and trajectory, frames, collisions,
// the valid-depth fraction of the worst frame and, per frame, what the hand-held view check
// requires: the fraction of the valid pixels on objects and furniture (ViewStats) and the
// smallest eigenvalue of the normals' scatter (from an exact-depth render of the same pose, as
// noise scatters finite-difference normals). Run with --gtest_also_run_disabled_tests;
// RASM_GEN_SURVEY_SEEDS=N (default 20), RASM_GEN_SURVEY_FIRST=N (default 1).
TEST(TrajectoryGenerator, DISABLED_SurveyOverSeeds) {
  const char* env = std::getenv("RASM_GEN_SURVEY_SEEDS");
  const char* first_env = std::getenv("RASM_GEN_SURVEY_FIRST");
  const int first = first_env ? std::atoi(first_env) : 1;
  const int seeds = env ? std::atoi(env) : 20;
  const char* kind_names[4] = {"handheld", "robot", "handheld_fast", "robot_fast"};
  struct Worst {
    double valid4 = 1.0, object = 1.0, eig = 1.0;
    int frames_below_object = 0, frames = 0;
  } worst_of_kind[4];
  for (int seed = first; seed < first + seeds; ++seed) {
    const auto t0 = std::chrono::steady_clock::now();
    const GeneratedWorld g = generateWorld(params(std::uint64_t(seed), RoomKind(seed % 3)));
    const World w = loadWorldFromString(g.yaml, g.name);
    const RayScene scene(w);
    for (int kind = 0; kind < 4; ++kind) {
      TTrajectoryGenParams tp;
      tp.seed = std::uint64_t(seed);
      tp.fast = kind >= 2;
      const GeneratedTrajectory gt =
          kind % 2 == 0 ? generateHandheldTrajectory(g, w, tp) : generateRobotTrajectory(g, w, tp);
      const double gen_s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const TrajectorySpec spec = loadTrajectorySpecFromString(gt.yaml, "survey");
      SequenceOptions so;
      so.seed = std::uint64_t(seed);
      so.sensor_overrides = smallCamera();
      so.sensor_overrides["labels"] = "true";
      SimulatedSequence seq(w, spec, so);
      TSensorParams exact;
      exact.width = 160;
      exact.height = 120;
      exact.fx = exact.fy = 131.25;
      exact.cx = 79.5;
      exact.cy = 59.5;
      exact.noise = false;
      exact.labels = false;
      exact.max_depth_m = 4.0;
      RgbdSensor exact_sensor(scene, exact);
      rasm::RgbdFrame f, fe;
      int frames = 0, collided = 0, below50 = 0, below_object = 0, worst_frame = -1;
      double worst = 1.0, sum = 0.0, worst4 = 1.0, worst_object = 1.0, worst_eig = 1.0,
             worst_icp = 1.0;
      while (seq.next(f)) {
        ++frames;
        if (seq.robot() && seq.robot()->collided()) ++collided;
        const double v = validFraction(f), v4 = validFraction(f, 4.0f);
        worst = std::min(worst, v);
        worst4 = std::min(worst4, v4);
        sum += v;
        below50 += v4 < 0.5 ? 1 : 0;
        const ViewStats vs = viewStats(f, 4.0);
        exact_sensor.render(*f.gt_T_world_cam, 0, 0, fe);
        const ViewStats ve = viewStats(fe, 4.0);
        if (vs.object_fraction < worst_object) worst_frame = frames - 1;
        worst_object = std::min(worst_object, vs.object_fraction);
        worst_eig = std::min(worst_eig, ve.normal_min_eig);
        worst_icp = std::min(worst_icp, ve.icp_min_eig);
        below_object += vs.object_fraction < tp.min_object_fraction_handheld ||
                                ve.normal_min_eig < tp.min_normal_eig_handheld
                            ? 1
                            : 0;
      }
      Worst& wk = worst_of_kind[kind];
      wk.valid4 = std::min(wk.valid4, worst4);
      wk.object = std::min(wk.object, worst_object);
      wk.eig = std::min(wk.eig, worst_eig);
      wk.frames_below_object += below_object;
      wk.frames += frames;
      std::printf(
          "seed %2d %-28s %-14s frames %5d collided %d stuck %d valid depth: worst %.2f mean "
          "%.2f, within 4 m: worst %.2f, frames below 50%% %d; objects: worst %.2f (frame %d), "
          "normal spread: worst %.4f (6-DoF %.4f), frames below the hand-held rule %d (gen %.1f "
          "s) | %s\n",
          seed, g.name.c_str(), kind_names[kind], frames, collided, int(seq.robotStuck()), worst,
          sum / std::max(1, frames), worst4, below50, worst_object, worst_frame, worst_eig,
          worst_icp, below_object, gen_s, gt.summary.c_str());
      std::fflush(stdout);
      EXPECT_EQ(collided, 0);
      EXPECT_FALSE(seq.robotStuck());
    }
  }
  for (int kind = 0; kind < 4; ++kind)
    std::printf(
        "all seeds %-14s frames %6d: within 4 m worst %.2f; objects worst %.2f, normal spread "
        "worst %.4f, frames below the hand-held rule %d\n",
        kind_names[kind], worst_of_kind[kind].frames, worst_of_kind[kind].valid4,
        worst_of_kind[kind].object, worst_of_kind[kind].eig,
        worst_of_kind[kind].frames_below_object);
}

// ---- flats, plain walls, counters ---------------------------------------------------------------

namespace {

TWorldGenParams flatParams(std::uint64_t seed, int rooms, RoomKind kind = RoomKind::Mixed) {
  TWorldGenParams p = params(seed, kind);
  p.layout = WorldLayout::Flat;
  p.rooms = rooms;
  return p;
}

/// 64-bit FNV-1a of a text (the same on every platform).
std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : s) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

/// Where a disc robot's centre may be, on a lattice over the world: the disc clears the world's
/// geometry in the robot's height band (the collision raster of SimulatedDiffDriveRobot).
struct FreeLattice {
  double x0 = 0, y0 = 0, step = 0.05;
  int nx = 0, ny = 0;
  std::vector<std::uint8_t> free;
  FreeLattice(const World& w, double radius_m) {
    const OccupancyRaster raster(w, 0.03f, 0.6f, 0.02f);
    const Eigen::AlignedBox3f b = w.bounds();
    x0 = b.min().x();
    y0 = b.min().y();
    nx = int((b.max().x() - x0) / step) + 1;
    ny = int((b.max().y() - y0) / step) + 1;
    free.assign(std::size_t(nx) * ny, 0);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        free[std::size_t(j) * nx + i] =
            raster.collidesDisc(Eigen::Vector2f(float(x0 + i * step), float(y0 + j * step)),
                                float(radius_m))
                ? 0
                : 1;
  }
  int index(double x, double y) const {
    const int i = int(std::lround((x - x0) / step)), j = int(std::lround((y - y0) / step));
    return i < 0 || j < 0 || i >= nx || j >= ny ? -1 : j * nx + i;
  }
  bool freeAt(double x, double y) const {
    const int k = index(x, y);
    return k >= 0 && free[std::size_t(k)];
  }
  /// 4-connected flood fill from (x, y), never entering `blocked` (when given).
  std::vector<std::uint8_t> reach(double x, double y, const GenRect* blocked = nullptr) const {
    std::vector<std::uint8_t> seen(free.size(), 0);
    std::queue<int> q;
    const int s = index(x, y);
    if (s < 0 || !free[std::size_t(s)]) return seen;
    seen[std::size_t(s)] = 1;
    q.push(s);
    while (!q.empty()) {
      const int k = q.front();
      q.pop();
      const int i = k % nx, j = k / nx;
      const int nb[4][2] = {{i + 1, j}, {i - 1, j}, {i, j + 1}, {i, j - 1}};
      for (const auto& n : nb) {
        if (n[0] < 0 || n[1] < 0 || n[0] >= nx || n[1] >= ny) continue;
        const int m = n[1] * nx + n[0];
        if (seen[std::size_t(m)] || !free[std::size_t(m)]) continue;
        if (blocked && blocked->contains(x0 + n[0] * step, y0 + n[1] * step)) continue;
        seen[std::size_t(m)] = 1;
        q.push(m);
      }
    }
    return seen;
  }
};

GenRect centreOf(const GenRect& r) {
  const double x = 0.5 * (r.x0 + r.x1), y = 0.5 * (r.y0 + r.y1);
  return {x, y, x, y};
}

}  // namespace

// Recorded with the generator before flats, break rooms and plain walls existed: the room layout
// must keep giving these texts byte for byte (its trajectories were compared the same way).
TEST(WorldGenerator, RoomLayoutTextIsUnchanged) {
  struct Case {
    std::uint64_t seed;
    RoomKind kind;
    double w, d;
    std::uint64_t fnv;
  };
  const Case cases[] = {{1, RoomKind::Mixed, 0, 0, 0x237a495ffca37dabull},
                        {7, RoomKind::Mixed, 0, 0, 0x24484548ed484155ull},
                        {1001, RoomKind::Mixed, 0, 0, 0x3f417715ed940841ull},
                        {2, RoomKind::Office, 6, 5, 0xf9ca0360882e230aull},
                        {3, RoomKind::Lab, 0, 0, 0x0e2d2f42e4201ffcull},
                        {5, RoomKind::Mixed, 12, 9, 0x7272a0f077a1f652ull}};
  for (const Case& c : cases) {
    const GeneratedWorld g = generateWorld(params(c.seed, c.kind, c.w, c.d));
    EXPECT_EQ(fnv1a(g.yaml), c.fnv) << g.name;
    ASSERT_EQ(g.rooms.size(), 1u);
    EXPECT_EQ(g.rooms[0].free_area.x0, g.free_area.x0);
    EXPECT_TRUE(g.rooms[0].plain_sides.empty());
    EXPECT_EQ(g.rooms[0].counter_side, -1);
  }
}

TEST(WorldGenerator, FlatRoomsAreReachableFromTheHallwayThroughTheirDoorways) {
  for (int n = 2; n <= 5; ++n) {
    // A flat of break rooms (plain sides, counters) and a mixed one of each size.
    TWorldGenParams fp = flatParams(std::uint64_t(20 + n), n, RoomKind::BreakRoom);
    if (n % 2 == 0) fp.kind = RoomKind::Mixed;
    const GeneratedWorld g = generateWorld(fp);
    ASSERT_EQ(int(g.rooms.size()), n) << g.name;
    const World w = loadWorldFromString(g.yaml, g.name);
    EXPECT_GE(g.params.width_m, 8.0);
    EXPECT_LE(g.params.width_m, 14.0);
    const FreeLattice lat(w, g.params.robot_radius_m);
    // The free-space description is free.
    for (const GenRect& r : g.robot_free)
      for (double x = r.x0; x <= r.x1 + 1e-9; x += 0.1)
        for (double y = r.y0; y <= r.y1 + 1e-9; y += 0.1)
          EXPECT_TRUE(lat.freeAt(x, y)) << g.name << " (" << x << ", " << y << ")";
    const GenRect start = centreOf(g.free_area);
    ASSERT_TRUE(g.hallway.contains(start.x0, start.y0));
    const std::vector<std::uint8_t> all = lat.reach(start.x0, start.y0);
    for (const GeneratedWorld::Room& room : g.rooms) {
      EXPECT_GE(room.doorway.width(), 0.9 - 1e-9) << room.name;
      EXPECT_GE(room.interior.width(), 3.0) << g.name << " " << room.name;
      EXPECT_GE(room.interior.depth(), 3.0) << g.name << " " << room.name;
      const GenRect c = centreOf(room.free_area), d = centreOf(room.doorway);
      const int kc = lat.index(c.x0, c.y0), kd = lat.index(d.x0, d.y0);
      ASSERT_GE(kc, 0);
      ASSERT_GE(kd, 0);
      EXPECT_TRUE(all[std::size_t(kc)]) << g.name << ": " << room.name << " unreachable";
      EXPECT_TRUE(all[std::size_t(kd)]) << g.name << ": " << room.name << "'s doorway";
      // Through the doorway, not another way: with the doorway closed the room is cut off.
      const std::vector<std::uint8_t> closed = lat.reach(start.x0, start.y0, &room.doorway);
      EXPECT_FALSE(closed[std::size_t(kc)]) << g.name << ": " << room.name << " has another way";
    }
  }
}

TEST(WorldGenerator, FlatFootprintsKeepOffDoorwaysAndEachOther) {
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    TWorldGenParams fp = flatParams(seed, 2 + int(seed % 4));
    if (seed % 3 == 0) fp.plain_walls = 2;
    const GeneratedWorld g = generateWorld(fp);
    const World w = loadWorldFromString(g.yaml, g.name);
    std::vector<std::pair<std::string, GenRect>> feet;
    for (const auto& p : g.placements) {
      if (p.rest == GeneratedWorld::Rest::Structure) continue;
      const Eigen::AlignedBox3f b = objectOf(w, p.id).worldMesh().bounds();
      const GenRect r{b.min().x(), b.min().y(), b.max().x(), b.max().y()};
      // In one room (the flat's door: in the hallway).
      bool inside = g.hallway.contains(r.x0 + 1e-3, r.y0 + 1e-3) &&
                    g.hallway.contains(r.x1 - 1e-3, r.y1 - 1e-3);
      for (const auto& room : g.rooms)
        inside = inside || (room.interior.contains(r.x0 + 1e-3, r.y0 + 1e-3) &&
                            room.interior.contains(r.x1 - 1e-3, r.y1 - 1e-3));
      EXPECT_TRUE(inside) << g.name << ": " << p.id << " " << p.name;
      // Nothing within 0.6 m of a doorway, either side of the wall.
      for (const auto& room : g.rooms) {
        const GenRect door{room.doorway.x0, room.doorway.y0 - 0.6, room.doorway.x1,
                           room.doorway.y1 + 0.6};
        EXPECT_FALSE(door.overlaps(r))
            << g.name << ": " << p.id << " " << p.name << " in " << room.name << "'s doorway";
      }
      if (p.furniture) feet.emplace_back(std::to_string(p.id) + " " + p.name, r);
    }
    EXPECT_GE(feet.size(), 4u * g.rooms.size()) << g.name;
    for (std::size_t i = 0; i < feet.size(); ++i)
      for (std::size_t j = i + 1; j < feet.size(); ++j) {
        const GenRect &a = feet[i].second, &b = feet[j].second;
        const bool overlap =
            a.x0 < b.x1 - 1e-3 && b.x0 < a.x1 - 1e-3 && a.y0 < b.y1 - 1e-3 && b.y0 < a.y1 - 1e-3;
        EXPECT_FALSE(overlap) << g.name << ": " << feet[i].first << " and " << feet[j].first;
      }
  }
}

TEST(WorldGenerator, FlatFilesAreByteIdenticalAndTheRobotStartsInTheHallway) {
  TempDir t1("flat1"), t2("flat2");
  const TWorldGenParams p = flatParams(4, 3);
  const GenerateFilesResult r1 = generateWorldFiles(p, (t1.path / "flat.yaml").string());
  const GenerateFilesResult r2 = generateWorldFiles(p, (t2.path / "flat.yaml").string());
  EXPECT_EQ(readFile(r1.world_path), readFile(r2.world_path));
  for (const char* f : {"flat_handheld.yaml", "flat_robot.yaml"})
    EXPECT_EQ(readFile(t1.path / f), readFile(t2.path / f)) << f;
  EXPECT_NE(readFile(r1.world_path), generateWorld(flatParams(5, 3)).yaml);

  const GeneratedWorld g = generateWorld(p);
  const World w = loadWorldFromString(g.yaml, g.name);
  const RayScene scene(w);
  const TrajectorySpec robot = loadTrajectorySpec((t1.path / "flat_robot.yaml").string());
  EXPECT_TRUE(g.hallway.contains(robot.start_pose.x(), robot.start_pose.y()));
  TRobotParams rp;
  applyParamOverrides(rp, "sim_robot", robot.robot_overrides, "robot");
  EXPECT_NO_THROW(SimulatedDiffDriveRobot(scene, rp, robot.start_pose, 1));
  // The hand-held keyframes stand in one room, away from its walls.
  const TrajectorySpec hand = loadTrajectorySpec((t1.path / "flat_handheld.yaml").string());
  ASSERT_FALSE(hand.keyframes.empty());
  int room_of_first = -1;
  for (const auto& k : hand.keyframes) {
    const Eigen::Vector3d q = k.T_world_cam.translation();
    int in = -1;
    for (std::size_t i = 0; i < g.rooms.size(); ++i) {
      const GenRect& r = g.rooms[i].interior;
      if (q.x() > r.x0 + 0.3 && q.x() < r.x1 - 0.3 && q.y() > r.y0 + 0.3 && q.y() < r.y1 - 0.3)
        in = int(i);
    }
    EXPECT_GE(in, 0) << "keyframe at " << q.transpose();
    if (room_of_first < 0) room_of_first = in;
    EXPECT_EQ(in, room_of_first);
  }
}

TEST(WorldGenerator, PlainSidesStayBareAndBreakRoomsHaveTheirCounter) {
  struct Case {
    std::uint64_t seed;
    RoomKind kind;
    int plain;  ///< requested; -1: drawn (break rooms 1-2)
  };
  const Case cases[] = {{1, RoomKind::BreakRoom, -1}, {2, RoomKind::BreakRoom, -1},
                        {3, RoomKind::BreakRoom, 1},  {4, RoomKind::BreakRoom, 2},
                        {5, RoomKind::Office, 2},     {6, RoomKind::Mixed, 1}};
  for (const Case& c : cases) {
    TWorldGenParams p = params(c.seed, c.kind);
    p.plain_walls = c.plain;
    const GeneratedWorld g = generateWorld(p);
    EXPECT_EQ(g.yaml, generateWorld(p).yaml);
    const World w = loadWorldFromString(g.yaml, g.name);
    ASSERT_EQ(g.rooms.size(), 1u);
    const GeneratedWorld::Room& room = g.rooms[0];
    const std::size_t want = c.plain >= 0 ? std::size_t(c.plain) : room.plain_sides.size();
    EXPECT_EQ(room.plain_sides.size(), want) << g.name;
    EXPECT_GE(room.plain_sides.size(), c.kind == RoomKind::BreakRoom ? 1u : 0u) << g.name;
    // Plain sides are long sides, and nothing stands or hangs within 0.3 m of them.
    const bool along_x = room.interior.width() >= room.interior.depth();
    for (int s : room.plain_sides) {
      EXPECT_EQ(s % 2, along_x ? 0 : 1) << g.name << " side " << s;
      for (const auto& pl : g.placements) {
        if (pl.rest == GeneratedWorld::Rest::Structure) continue;
        const Eigen::AlignedBox3f b = objectOf(w, pl.id).worldMesh().bounds();
        const double gap = s == 0   ? b.min().y() - room.interior.y0
                           : s == 1 ? room.interior.x1 - b.max().x()
                           : s == 2 ? room.interior.y1 - b.max().y()
                                    : b.min().x() - room.interior.x0;
        EXPECT_GE(gap, 0.3 - 1e-3) << g.name << ": " << pl.name << " against plain side " << s;
      }
    }
    // Break rooms: one bare box of a uniform colour, 0.9 m high and 0.6 m deep, against a wall
    // that is not plain, 3-5 m long (or the wall's length less 0.2 m).
    int counters = 0;
    for (const auto& pl : g.placements) {
      if (pl.name.rfind("counter", 0) != 0) continue;
      ++counters;
      const WorldObject& o = objectOf(w, pl.id);
      const Eigen::AlignedBox3f b = o.worldMesh().bounds();
      EXPECT_NEAR(b.max().z(), 0.9, 1e-3);
      const bool along_wall_x = room.counter_side % 2 == 0;
      const double len = along_wall_x ? b.max().x() - b.min().x() : b.max().y() - b.min().y();
      const double depth = along_wall_x ? b.max().y() - b.min().y() : b.max().x() - b.min().x();
      const double wall = along_wall_x ? room.interior.width() : room.interior.depth();
      EXPECT_NEAR(depth, 0.6, 1e-3) << g.name;
      // Plain sides at its ends keep it kPlainKeep (0.3 m) shorter; it shrinks in 0.3 m steps.
      double usable = wall;
      for (int s : room.plain_sides) usable -= s % 2 != room.counter_side % 2 ? 0.3 : 0.0;
      EXPECT_GE(len, std::min(3.0, usable - 0.5) - 1e-3) << g.name;
      EXPECT_LE(len, 5.0 + 1e-3) << g.name;
      EXPECT_TRUE(o.material.pattern == Pattern::Solid) << g.name;
      for (const auto& other : g.placements)
        EXPECT_FALSE(other.rest == GeneratedWorld::Rest::Surface && other.support_id == pl.id)
            << g.name << ": " << other.name << " on the counter";
      EXPECT_EQ(std::count(room.plain_sides.begin(), room.plain_sides.end(), room.counter_side), 0);
    }
    EXPECT_EQ(counters, c.kind == RoomKind::BreakRoom ? 1 : 0) << g.name;
    EXPECT_EQ(room.counter_side >= 0, c.kind == RoomKind::BreakRoom) << g.name;
  }
  // In a flat, --plain-walls applies to every room.
  TWorldGenParams fp = flatParams(3, 4);
  fp.plain_walls = 2;
  for (const auto& room : generateWorld(fp).rooms) EXPECT_EQ(room.plain_sides.size(), 2u);
}

TEST(WorldGenerator, BadLayoutOptionsNameTheOption) {
  auto error = [](const TWorldGenParams& p) {
    try {
      generateWorld(p);
    } catch (const rasm::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  std::string e = error(flatParams(1, 1));
  EXPECT_NE(e.find("--rooms 1"), std::string::npos) << e;
  EXPECT_NE(e.find("expected 2 to 5 rooms"), std::string::npos) << e;
  EXPECT_NE(error(flatParams(1, 6)).find("--rooms 6"), std::string::npos);
  TWorldGenParams p = params(1);
  p.plain_walls = 3;
  e = error(p);
  EXPECT_NE(e.find("--plain-walls 3"), std::string::npos) << e;
  EXPECT_NE(e.find("expected 0, 1 or 2"), std::string::npos) << e;
  p = flatParams(1, 4);
  p.width_m = 5;
  p.depth_m = 5;
  e = error(p);
  EXPECT_NE(e.find("--size 5x5"), std::string::npos) << e;
  EXPECT_NE(e.find("too small for a flat of 4 rooms"), std::string::npos) << e;
  p.width_m = 25;
  p.depth_m = 10;
  EXPECT_NE(error(p).find("too large"), std::string::npos);
  try {
    worldLayoutFromName("house", "--layout");
    ADD_FAILURE();
  } catch (const rasm::InputError& ex) {
    EXPECT_NE(std::string(ex.what()).find("--layout house"), std::string::npos) << ex.what();
    EXPECT_NE(std::string(ex.what()).find("room or flat"), std::string::npos);
  }
  // A flat of the smallest size the message gives is generated.
  p.width_m = 6.5;
  p.depth_m = 8.4;
  EXPECT_NO_THROW(generateWorld(p));
}
