#pragma once
// Writing the files of a run's output folder: complete or not at all under the final name.

#include <string>

namespace rasm::pipeline {

/// Writes `text` to `path` through "<path>.part" + rename. InputError naming the file when it
/// cannot be created or written.
void writeFileAtomically(const std::string& path, const std::string& text);

}  // namespace rasm::pipeline
