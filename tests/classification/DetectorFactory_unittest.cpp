// makeDetectors: the detectors [classification] detectors lists, in that order, the built-in ones
// and the kinds added from outside (DetectorKind: how pipeline adds the simulator's detector).
#include <gtest/gtest.h>

#include <mrpt/config/CLoadableOptions.h>

#include <mrpt/config/CConfigFileMemory.h>

#include "rasm/classification/DetectorFactory.h"
#include "rasm/classification/TClassificationParams.h"
#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

using namespace rasm::classification;

namespace {

/// The section of a detector kind added in the test.
struct TNamedParams : mrpt::config::CLoadableOptions {
  std::string label = "default";
  void loadFromConfigFile(const mrpt::config::CConfigFileBase&, const std::string&) override {}
  void saveToConfigFile(mrpt::config::CConfigFileBase&, const std::string&) const override {}
};

/// A detector that finds nothing, named after its kind.
class NamedDetector : public Detector {
 public:
  explicit NamedDetector(std::string name) : m_name(std::move(name)) {}
  std::string name() const override { return m_name; }
  const std::vector<std::string>& classNames() const override { return m_names; }
  std::vector<Detection> detect(const DetectorInput&) override { return {}; }

 private:
  std::string m_name;
  std::vector<std::string> m_names = {"tv"};
};

DetectorKind kind(const std::string& name, TNamedParams& params, int& seed_seen) {
  return {name, &params, [name, &params, &seed_seen](const TClassificationParams& p) {
            seed_seen = p.seed;
            return std::make_unique<NamedDetector>(name + ":" + params.label);
          }};
}

}  // namespace

TEST(DetectorFactory, AddedKindsAreBuiltByNameInTheListedOrder) {
  TNamedParams first_params, second_params;
  second_params.label = "loaded";
  int seed_first = -1, seed_second = -1;
  DetectorSections sections;
  sections.added.push_back(kind("first", first_params, seed_first));
  sections.added.push_back(kind("second", second_params, seed_second));

  std::vector<std::string> names;
  for (const auto& [name, params] : sections.list()) names.push_back(name);
  EXPECT_EQ(names, (std::vector<std::string>{"first", "second", "dnn_detector", "zero_shot"}));
  EXPECT_EQ(sections.list()[1].second, &second_params);

  TClassificationParams params;
  params.detectors = "second, zero_shot, first, no_such_detector";
  params.seed = 7;
  const DetectorBuild built = makeDetectors(params, sections);
  ASSERT_EQ(built.detectors.size(), 2u);
  EXPECT_EQ(built.detectors[0]->name(), "second:loaded");
  EXPECT_EQ(built.detectors[1]->name(), "first:default");
  EXPECT_EQ(seed_first, 7);
  EXPECT_EQ(seed_second, 7);
  // zero_shot is disabled by default and no_such_detector is neither added nor built in.
  ASSERT_EQ(built.warnings.size(), 2u);
  EXPECT_NE(built.warnings[0].find("zero_shot"), std::string::npos);
  EXPECT_NE(built.warnings[1].find("no_such_detector"), std::string::npos);
}

namespace {
TClassificationParams loadClassification(const std::string& ini) {
  mrpt::config::CConfigFileMemory cfg;
  cfg.setContent(ini);
  TClassificationParams p;
  rasm::loadParamsStrict(cfg, "classification", p, "test.ini");
  return p;
}
}  // namespace

// detectors = auto and threaded = auto (the defaults): the simulator's detector on the mapping
// thread for the simulator's frames, the DNN detector on a worker for any other source; what an
// INI states stays; config.ini's form reloads to the same.
TEST(ClassificationParams, AutoDetectorsAndThreadingFollowTheSource) {
  TClassificationParams sim = loadClassification("[classification]\n");
  EXPECT_EQ(sim.detectors, "auto");
  EXPECT_TRUE(sim.threaded_auto);
  TClassificationParams real = sim;
  sim.resolveAuto(true);
  real.resolveAuto(false);
  EXPECT_EQ(sim.detectors, "sim_detector");
  EXPECT_FALSE(sim.threaded);
  EXPECT_EQ(real.detectors, "dnn_detector");
  EXPECT_TRUE(real.threaded);
  EXPECT_FALSE(real.threaded_auto);

  TClassificationParams stated =
      loadClassification("[classification]\ndetectors = zero_shot\nthreaded = 0\n");
  stated.resolveAuto(false);
  EXPECT_EQ(stated.detectors, "zero_shot");
  EXPECT_FALSE(stated.threaded);
  EXPECT_TRUE(loadClassification("[classification]\nthreaded = Yes\n").threaded);

  mrpt::config::CConfigFileMemory saved;
  real.saveToConfigFile(saved, "classification");
  TClassificationParams reloaded;
  reloaded.loadFromConfigFile(saved, "classification");
  EXPECT_EQ(reloaded.detectors, "dnn_detector");
  EXPECT_TRUE(reloaded.threaded);
  EXPECT_FALSE(reloaded.threaded_auto);

  try {
    loadClassification("[classification]\nthreaded = sometimes\n");
    ADD_FAILURE() << "threaded = sometimes was accepted";
  } catch (const rasm::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[classification] threaded"), std::string::npos)
        << e.what();
  }
}
