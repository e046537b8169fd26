// The stage seam (issue 13, 1): a stage from outside the Mapper plugs in with one call, gets its
// INI section, timer, frames.csv column and report field from the list, and what it writes into
// the frame context (here a label map L^p) reaches fusion.
#include <gtest/gtest.h>

#include <algorithm>

#include <mrpt/config/CConfigFileMemory.h>

#include "rasm/core/Error.h"
#include "rasm/io/FrameSource.h"
#include "rasm/pipeline/Mapper.h"
#include "rasm/pipeline/stages/FusionStages.h"

using namespace rasm;
using namespace rasm::pipeline;

namespace {

struct TConstantLabelParams : mrpt::config::CLoadableOptions {
  int label = 7;
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override {
    MRPT_LOAD_CONFIG_VAR(label, int, c, s);
  }
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override {
    MRPT_SAVE_CONFIG_VAR(label, c, s);
  }
};

/// Writes one label over every pixel (a stand-in for label propagation, III) and checks that it
/// sees the index map of the frame's pose.
class ConstantLabelStage : public MapperStage {
 public:
  ConstantLabelStage() : MapperStage("constant_label") {}
  std::vector<ParamsSection> sections() override { return {{"constant_label", &params}}; }
  void process(FrameContext& ctx, maps::CSurfelMap& /*map*/) override {
    if (!ctx.result.fusable()) return;
    index_map_seen += ctx.index_map.valid();
    ctx.labels.resize(ctx.frame->intrinsics.width, ctx.frame->intrinsics.height);
    ctx.labels.setTo(std::uint32_t(params.label));
    ++frames;
  }
  void csvColumns(std::vector<std::string>& c) const override {
    c.push_back("constant_label_frames");
  }
  void csvValues(const FrameContext&, CsvRow& row) const override { row.add(frames); }
  void report(nlohmann::json& rep) const override { rep["constant_label_frames"] = frames; }

  TConstantLabelParams params;
  int frames = 0, index_map_seen = 0;
};

}  // namespace

TEST(MapperStage, AStagePlugsInWithOneCallAndItsLabelsReachTheMap) {
  std::unique_ptr<io::FrameSource> src =
      io::openFrameSource(std::string(RASM_MRPT_TEST_RAWLOG), io::FrameSourceOptions());
  Mapper mapper;
  auto stage = std::make_unique<ConstantLabelStage>();
  ConstantLabelStage& s = *stage;
  s.params.label = 9;
  mapper.addStage(std::move(stage), "fuse");  // after the index map, before fusion: as III

  const auto names = mapper.sectionNames();
  EXPECT_NE(std::find(names.begin(), names.end(), "constant_label"), names.end());
  const auto& timers = mapper.timerNames();
  const auto at = std::find(timers.begin(), timers.end(), "constant_label");
  ASSERT_NE(at, timers.end());
  EXPECT_LT(std::find(timers.begin(), timers.end(), "index_map"), at);
  EXPECT_EQ(*(at + 1), "fuse");
  EXPECT_NE(mapper.csvHeader().find("constant_label_frames"), std::string::npos);
  mrpt::config::CConfigFileMemory saved;
  mapper.saveParams(saved);
  EXPECT_EQ(saved.read_int("constant_label", "label", -1), 9);

  int fused = 0;
  while (auto f = src->next()) {
    const FrameResult r = mapper.processFrame(*f);
    ASSERT_EQ(r.ms.size(), timers.size());
    // frames.csv: every stage writes as many values as it names columns.
    const std::string header = mapper.csvHeader(), row = mapper.csvRow();
    ASSERT_EQ(std::count(row.begin(), row.end(), ','),
              std::count(header.begin(), header.end(), ','))
        << header << "\n"
        << row;
    fused += r.fused;
    if (fused >= 3) break;
  }
  ASSERT_GE(fused, 1) << "the test rawlog gave no fused frame";
  EXPECT_EQ(s.frames, fused);
  EXPECT_EQ(s.index_map_seen, fused) << "the index map at T_t is in the context before fusion";
  // Every surfel fusion created or updated took L^p = 9 (III: a new surfel takes its pixel's
  // label).
  const maps::SurfelStore& store = mapper.map().store();
  ASSERT_GT(store.size(), 1000);
  const maps::SurfelArrays a = store.arrays();
  int labelled = 0;
  for (int i = 0; i < store.size(); ++i) labelled += a.segment[i] == 9u;
  EXPECT_EQ(labelled, store.size());
  nlohmann::json rep;
  mapper.report(rep);
  EXPECT_EQ(rep["constant_label_frames"], fused);
  EXPECT_THROW(mapper.addStage(std::make_unique<ConstantLabelStage>()), std::logic_error);
}

TEST(MapperStage, ConfigLoadsEveryStageSectionStrictly) {
  mrpt::config::CConfigFileMemory ini;
  ini.write("fusion", "confidence_sigma", 0.5);
  ini.write("tracking", "no_such_key", 1);
  EXPECT_THROW(Mapper(ini, "test.ini"), InputError);
  mrpt::config::CConfigFileMemory ok;
  ok.write("fusion", "confidence_sigma", 0.5);
  const Mapper m(ok, "test.ini");
  EXPECT_FLOAT_EQ(m.stage<FusionStage>().params().confidence_sigma, 0.5f);
  EXPECT_FLOAT_EQ(m.stage<FusionStage>().fusion().params().confidence_sigma, 0.5f)
      << "configure() applied it";
}
