#pragma once
// The project's shared data folder (detectors, models, real sequences; README of ../shared/data)
// from any working directory. Compiled-in defaults name it "../shared/data/...", relative to the
// repository root; run from elsewhere they are looked up in the shared data folders instead.

#include <string>
#include <vector>

namespace rasm {

/// Candidate shared data folders, in order: $RASM_SHARED_DATA, the one compiled in (CMake's
/// RASM_SHARED_DATA), and next to the source tree of the running binary
/// (<source>/build/rasm -> <source>/../shared/data).
std::vector<std::string> sharedDataFolders();

/// A path starting with "../shared/data/" that does not exist relative to the working directory,
/// found in the first shared data folder holding it; any other path unchanged.
std::string resolveSharedData(const std::string& path);

}  // namespace rasm
