#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <tuple>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/pipeline/stages/ExplorationStage.h"
#include "rasm/pipeline/stages/FusionStages.h"
#include "rasm/run/MappingRun.h"
#include "rasm/run/RunConfig.h"

using namespace rasm;
using namespace rasm::pipeline;
using namespace rasm::autonomy;
using namespace rasm::run;

namespace {
std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(RunConfig, EmbeddedDefaultLoadsStrictly) {
  const RunConfig cfg = RunConfig::embeddedDefault();
  MappingRun run(cfg);
  EXPECT_EQ(run.sourceParams().type, "sim");
  EXPECT_NEAR(run.mapper().stage<FusionStage>().params().confidence_sigma, 0.6f, 1e-7);
  EXPECT_EQ(run.mapper().mapperParams().pyramid_levels, 3);
}

TEST(RunConfig, UnknownSectionKeyAndBadValueAreNamed) {
  const std::string e1 =
      errorOf([] { MappingRun(RunConfig::fromString("[trackin]\nx=1\n", "my.ini")); });
  EXPECT_NE(e1.find("my.ini"), std::string::npos) << e1;
  EXPECT_NE(e1.find("[trackin]"), std::string::npos) << e1;

  const std::string e2 =
      errorOf([] { MappingRun(RunConfig::fromString("[mapper]\npyramid_levle = 2\n", "my.ini")); });
  EXPECT_NE(e2.find("pyramid_levle"), std::string::npos) << e2;
  EXPECT_NE(e2.find("[mapper]"), std::string::npos) << e2;

  const std::string e3 =
      errorOf([] { MappingRun(RunConfig::fromString("[mapper]\nmax_depth_m = far\n", "my.ini")); });
  EXPECT_NE(e3.find("max_depth_m"), std::string::npos) << e3;

  const std::string e4 = errorOf([] { RunConfig::fromString("[mapper]\njust words\n", "my.ini"); });
  EXPECT_NE(e4.find("my.ini:2"), std::string::npos) << e4;

  const std::string e5 = errorOf([] { RunConfig::fromFile("/nonexistent/x.ini"); });
  EXPECT_NE(e5.find("/nonexistent/x.ini"), std::string::npos) << e5;
}

TEST(RunConfig, OverridesReplaceKeys) {
  RunConfig cfg = RunConfig::embeddedDefault();
  cfg.applyOverride("mapper.max_depth_m=3.5");
  cfg.applyOverride("source.type=rawlog");
  cfg.applyOverride("source.path=/usr/share/mrpt/datasets/tests_rgbd.rawlog");
  MappingRun run(cfg);
  EXPECT_DOUBLE_EQ(run.mapper().mapperParams().max_depth_m, 3.5);
  EXPECT_EQ(run.sourceParams().type, "rawlog");
  EXPECT_THROW(cfg.applyOverride("nodot=1"), InputError);
  EXPECT_THROW(cfg.applyOverride("a.b"), InputError);
  EXPECT_NE(cfg.text().find("mapper.max_depth_m=3.5"), std::string::npos);
}

/// `--set` errors are blamed on the command line, INI errors on file:line (an unknown
/// `--set bogus.key=1` was blamed on the embedded default INI).
TEST(RunConfig, ErrorsNameTheCommandLineOrTheFileLine) {
  std::string e = errorOf([] {
    RunConfig cfg = RunConfig::embeddedDefault();
    cfg.applyOverride("bogus.key=1");
    MappingRun run(cfg);
  });
  EXPECT_NE(e.find("command line (bogus.key=1) [bogus]: unknown section"), std::string::npos) << e;
  EXPECT_EQ(e.find("embedded default"), std::string::npos) << e;

  e = errorOf([] {
    RunConfig cfg = RunConfig::embeddedDefault();
    cfg.applyOverride("mapper.bogus=1");
    MappingRun run(cfg);
  });
  EXPECT_NE(e.find("command line (mapper.bogus=1) [mapper] bogus: unknown key"), std::string::npos)
      << e;

  e = errorOf([] {
    RunConfig cfg = RunConfig::embeddedDefault();
    cfg.applyOverride("mapper.pyramid_levels=three");
    MappingRun run(cfg);
  });
  EXPECT_NE(e.find("command line (mapper.pyramid_levels=three)"), std::string::npos) << e;
  EXPECT_NE(e.find("'three' is not an integer"), std::string::npos) << e;

  e = errorOf([] {
    RunConfig cfg = RunConfig::embeddedDefault();
    cfg.applyOverride("source.max_frames=99999999999999999999");
    MappingRun run(cfg);
  });
  EXPECT_NE(e.find("command line (source.max_frames=99999999999999999999)"), std::string::npos)
      << e;
  EXPECT_NE(e.find("too large"), std::string::npos) << e;

  e = errorOf([] {
    RunConfig cfg = RunConfig::embeddedDefault();
    cfg.applyOverride("mapper.pyramid_levels=9");
    MappingRun run(cfg);
  });
  EXPECT_NE(e.find("command line (mapper.pyramid_levels=9)"), std::string::npos) << e;
  EXPECT_NE(e.find("value 9 out of range"), std::string::npos) << e;

  e = errorOf(
      [] { MappingRun(RunConfig::fromString("; x\n[mapper]\n\nmax_depth_m = nan\n", "my.ini")); });
  EXPECT_NE(e.find("my.ini:4 [mapper] max_depth_m: 'nan' is not a finite number"),
            std::string::npos)
      << e;
  e = errorOf([] { MappingRun(RunConfig::fromString("[mapper]\n[trackin]\nx=1\n", "my.ini")); });
  EXPECT_NE(e.find("my.ini:2 [trackin]"), std::string::npos) << e;

  e = errorOf([] { RunConfig::fromFile("/tmp"); });
  EXPECT_NE(e.find("is a folder"), std::string::npos) << e;
}

// [explore] was merged into [exploration]: an INI or override of the old section is refused with
// what to write instead, and the planner's keys and the loop's share the one section without a
// name in common (the loop's would shadow the planner's).
TEST(RunConfig, TheOldExploreSectionIsRefusedWithItsNewName) {
  std::string e = errorOf([] {
    MappingRun(RunConfig::fromString("[mapper]\n[explore]\nenabled = true\n", "old.ini"));
  });
  EXPECT_NE(e.find("old.ini:2 [explore]: was merged into [exploration]"), std::string::npos) << e;
  e = errorOf([] {
    RunConfig cfg = RunConfig::embeddedDefault();
    cfg.applyOverride("explore.time_budget_s=60");
    MappingRun run(cfg);
  });
  EXPECT_NE(e.find("command line (explore.time_budget_s=60) [explore]"), std::string::npos) << e;
  EXPECT_NE(e.find("--set exploration.KEY=value"), std::string::npos) << e;

  RunConfig cfg = RunConfig::embeddedDefault();
  cfg.applyOverride("exploration.time_budget_s=60");
  cfg.applyOverride("exploration.planner=frontier");
  MappingRun run(cfg);  // both halves of the section load
  const auto& stage = run.mapper().stage<ExplorationStage>();
  EXPECT_DOUBLE_EQ(stage.loopParams().time_budget_s, 60.0);
  EXPECT_EQ(stage.params().planner, "frontier");

  const auto planner_keys = knownKeys(exploration::TExplorationParams(), "exploration");
  const auto loop_keys = knownKeys(TExplorationLoopParams(), "exploration");
  EXPECT_GT(planner_keys.size(), 30u);
  EXPECT_GT(loop_keys.size(), 10u);
  for (const std::string& k : loop_keys) EXPECT_EQ(planner_keys.count(k), 0u) << k;
}

/// [camera] fx = nan / 0 / -517 were accepted (and silently replaced by the preset).
TEST(RunConfig, CameraIntrinsicsAreCheckedAtTheBoundary) {
  const auto camErr = [](const std::string& camera) {
    return errorOf([&] {
      MappingRun(RunConfig::fromString("[camera]\npreset = tum_fr1\n" + camera, "cam.ini"));
    });
  };
  std::string e = camErr("fx = nan\n");
  EXPECT_NE(e.find("camera.fx = nan in cam.ini:3: expected a finite focal length > 0 (pixels)"),
            std::string::npos)
      << e;
  e = camErr("fx = -517\nfy = 516\ncx = 318\ncy = 255\n");
  EXPECT_NE(e.find("camera.fx = -517 in cam.ini:3"), std::string::npos) << e;
  e = camErr("fx = 0\nfy = 516\ncx = 318\ncy = 255\n");
  EXPECT_NE(e.find("camera.fx = 0 in cam.ini:3"), std::string::npos) << e;
  e = camErr("fx = 517\nfy = -516\ncx = 318\ncy = 255\n");
  EXPECT_NE(e.find("camera.fy = -516"), std::string::npos) << e;
  e = camErr("fx = 517\nfy = 516\ncx = 900\ncy = 255\n");
  EXPECT_NE(e.find("camera.cx = 900 in cam.ini:5"), std::string::npos) << e;
  EXPECT_NE(e.find("inside the image"), std::string::npos) << e;
  e = camErr("fx = 517\nfy = 516\ncx = 318\ncy = inf\n");
  EXPECT_NE(e.find("camera.cy = inf"), std::string::npos) << e;
  e = camErr("fx = 517\n");
  EXPECT_NE(e.find("camera.cx"), std::string::npos) << e;
  EXPECT_NE(e.find("missing"), std::string::npos) << e;
  e = errorOf([] {
    MappingRun(RunConfig::fromString("[camera]\nfx = 517\ncx = 318\ncy = 255\n", "cam.ini"));
  });
  EXPECT_NE(e.find("width"), std::string::npos) << e;
  e = errorOf([] {
    RunConfig cfg = RunConfig::embeddedDefault();
    cfg.applyOverride("camera.fx=nan");
    MappingRun run(cfg);
  });
  EXPECT_NE(e.find("camera.fx = nan in command line (camera.fx=nan)"), std::string::npos) << e;
  EXPECT_EQ(camErr("fx = 517.3\nfy = 516.5\ncx = 318.6\ncy = 255.3\n"), "");
  // All zero (what config.ini writes for "not set"): the preset's intrinsics.
  EXPECT_EQ(camErr("fx = 0\nfy = 0\ncx = 0\ncy = 0\nwidth = 0\nheight = 0\n"), "");
}

/// The embedded default sets no camera: a TUM or 7-Scenes folder run without an INI uses the
/// dataset's own intrinsics (it got Kinect v1's before: redkitchen ATE 2.5 mm instead of 1.1 mm).
TEST(RunConfig, DatasetFolderWithoutIniUsesItsOwnIntrinsics) {
  for (const auto& [type, folder, fx] :
       {std::tuple<std::string, std::string, double>{"tum", "/tum/fr1_xyz_first37", 517.3},
        {"7scenes", "/7scenes/redkitchen_first300", 585.0}}) {
    const std::string path = std::string(RASM_SHARED_DATA) + folder;
    if (!std::filesystem::is_directory(path)) {
      std::printf("skipped %s: %s absent (shared data)\n", type.c_str(), path.c_str());
      continue;
    }
    RunConfig cfg = RunConfig::embeddedDefault();
    cfg.applyOverride("source.type=" + type);
    cfg.applyOverride("source.path=" + path);
    MappingRun run(cfg);
    auto src = run.openSource();
    const auto f = src->next();
    ASSERT_TRUE(f.has_value());
    EXPECT_DOUBLE_EQ(f->intrinsics.fx, fx) << type;
  }
}
