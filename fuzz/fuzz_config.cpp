// libFuzzer target: the run configuration (rasm::run::RunConfig: INI text, then `--set`
// overrides, the section and [camera] checks) and strict loading of the run's own params structs
// (rasm::loadParamsStrict: unknown keys, value text, ranges, the round trip). Input: INI text;
// lines "--set section.key=value" after a line "--set" are command-line overrides.
#include <cstdint>
#include <sstream>

#include "FuzzUtil.h"
#include "rasm/core/Params.h"
#include "rasm/pipeline/RunParams.h"
#include "rasm/run/RunConfig.h"
#include "rasm/tracking/TRobotParams.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::string ini = text, overrides;
  if (const auto cut = text.find("\n--set\n"); cut != std::string::npos) {
    ini = text.substr(0, cut);
    overrides = text.substr(cut + 7);
  }
  rasm::fuzz::expectOnlyInputErrors([&] {
    auto cfg = rasm::run::RunConfig::fromString(ini, "fuzz.ini");
    std::istringstream in(overrides);
    for (std::string line; std::getline(in, line);) cfg.applyOverride(line);
    cfg.checkSections({"source", "camera", "mapper", "robot", "output", "sim"});
    rasm::pipeline::TSourceParams source;
    rasm::pipeline::TMapperParams mapper;
    rasm::tracking::TRobotParams robot;
    rasm::pipeline::TOutputParams output;
    rasm::loadParamsStrict(cfg.ini(), "source", source, cfg.source());
    rasm::loadParamsStrict(cfg.ini(), "mapper", mapper, cfg.source());
    rasm::loadParamsStrict(cfg.ini(), "robot", robot, cfg.source());
    rasm::loadParamsStrict(cfg.ini(), "output", output, cfg.source());
    (void)source.dropped(3);
    (void)source.blanked(7);
    (void)robot.T_base_cam();
    (void)cfg.text();
  });
  return 0;
}
