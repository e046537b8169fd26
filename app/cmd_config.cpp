// rasm config [file.ini] [--set section.key=value ...]: prints the effective configuration (every
// section and key with its value, defaults included) without running anything. Also validates
// the file: unknown sections, keys and bad values are reported as `rasm run` would.
#include <iostream>

#include "Command.h"
#include "rasm/core/Error.h"
#include "rasm/pipeline/MappingRun.h"

namespace {

const char* kUsage =
    "usage: rasm config [file.ini] [--set section.key=value ...]\n"
    "Prints the effective configuration (every section and key, defaults included) without\n"
    "running anything; unknown sections or keys and bad values stop it as they stop rasm run.\n";

int configMain(const std::vector<std::string>& args) {
  using namespace rasm::pipeline;
  std::string ini_path;
  std::vector<std::string> overrides;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--set" && i + 1 < args.size())
      overrides.push_back(args[++i]);
    else if (!args[i].empty() && args[i][0] == '-')
      rasm::throwInputError("option '" + args[i] + "'", "unknown");
    else
      ini_path = args[i];
  }
  RunConfig cfg = ini_path.empty() ? RunConfig::embeddedDefault() : RunConfig::fromFile(ini_path);
  for (const auto& o : overrides) cfg.applyOverride(o);
  const MappingRun run(cfg);
  std::cout << run.effectiveConfig();
  return 0;
}

const rasm::app::Registrar reg(
    "config", "print the effective configuration: rasm config [file.ini] [--set s.k=v]", configMain,
    kUsage);

}  // namespace
