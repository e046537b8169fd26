// rasm config [file.ini] [--set section.key=value ...]: prints the effective configuration (every
// section and key with its value, defaults included) without running anything. Also validates
// the file: unknown sections, keys and bad values are reported as `rasm run` would.
#include <iostream>

#include "Command.h"
#include "rasm/core/Error.h"
#include "rasm/run/MappingRun.h"

namespace {

const rasm::app::CommandDecl kDecl{
    "config",
    "print the effective configuration: rasm config [file.ini] [--set s.k=v]",
    {{"file.ini", "the configuration (default: the embedded default, ini/default.ini)", false}},
    {{"set", "section.key=value", "set one key of the configuration", "", true}},
    "Prints the effective configuration (every section and key, defaults included) without\n"
    "running anything; unknown sections or keys and bad values stop it as they stop rasm run.\n"};

int configMain(const rasm::app::ParsedArgs& args) {
  using namespace rasm::pipeline;
  using namespace rasm::run;
  const std::string ini_path = args.positional("file.ini");
  RunConfig cfg = ini_path.empty() ? RunConfig::embeddedDefault() : RunConfig::fromFile(ini_path);
  for (const auto& o : args.values("set")) cfg.applyOverride(o);
  const MappingRun run(cfg);
  std::cout << run.effectiveConfig();
  return 0;
}

const rasm::app::Registrar reg{kDecl, &configMain};

}  // namespace
