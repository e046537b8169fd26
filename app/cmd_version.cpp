// `rasm version` (also `rasm --version`): the version, the git commit the binary was built from
// and the build date (rasm/pipeline/BuildInfo.h; report.json carries the same).
#include <iostream>

#include "Command.h"
#include "rasm/core/Error.h"
#include "rasm/pipeline/BuildInfo.h"

namespace {

const char* kUsage =
    "usage: rasm version   (or rasm --version)\n"
    "Prints the version, the git commit the binary was built from (\"-dirty\": with uncommitted\n"
    "changes; \"unknown\": not built from a git checkout) and the build date (UTC).\n";

int versionMain(const std::vector<std::string>& args) {
  if (!args.empty())
    rasm::throwInputError("argument '" + args[0] + "'", "unexpected: rasm version takes none");
  const rasm::pipeline::BuildInfo& b = rasm::pipeline::buildInfo();
  std::cout << "rasm " << b.version << "\ncommit " << b.commit << "\nbuilt " << b.date << "\n";
  return 0;
}

const rasm::app::Registrar reg("version", "version, git commit and build date (also --version)",
                               versionMain, kUsage);

}  // namespace
