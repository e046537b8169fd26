#include <gtest/gtest.h>

#include "rasm/core/Error.h"
#include "rasm/pipeline/MappingRun.h"
#include "rasm/pipeline/RunConfig.h"
#include "rasm/pipeline/stages/FusionStages.h"

using namespace rasm;
using namespace rasm::pipeline;

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
