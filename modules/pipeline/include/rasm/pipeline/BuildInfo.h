#pragma once
// What a run's outputs and `rasm --version` say about the binary: the version (CMake project), the
// git commit it was built from and the build date. Generated at build time by
// cmake/BuildInfo.cmake (the commit of the last build, not of the last configure).

#include <string>

namespace rasm::pipeline {

struct BuildInfo {
  std::string version;  ///< "0.1.0" (project(rasm VERSION ...))
  std::string commit;   ///< full SHA-1, "<sha>-dirty" with uncommitted changes, or "unknown"
  std::string date;     ///< build date, UTC, "YYYY-MM-DD"
};

const BuildInfo& buildInfo();

}  // namespace rasm::pipeline
