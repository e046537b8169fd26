// `rasm version` (also `rasm --version`): the version, the git commit the binary was built from
// and the build date (rasm/pipeline/BuildInfo.h; report.json carries the same).
#include <iostream>

#include "Command.h"
#include "rasm/core/Error.h"
#include "rasm/pipeline/BuildInfo.h"

namespace {

const rasm::app::CommandDecl kDecl{
    "version",
    "version, git commit and build date (also --version)",
    {},
    {},
    "Prints the version, the git commit the binary was built from (\"-dirty\": with uncommitted\n"
    "changes; \"unknown\": not built from a git checkout) and the build date (UTC).\n"
    "rasm --version prints the same.\n"};

int versionMain(const rasm::app::ParsedArgs&) {
  const rasm::pipeline::BuildInfo& b = rasm::pipeline::buildInfo();
  std::cout << "rasm " << b.version << "\ncommit " << b.commit << "\nbuilt " << b.date << "\n";
  return 0;
}

const rasm::app::Registrar reg{kDecl, &versionMain};

}  // namespace
