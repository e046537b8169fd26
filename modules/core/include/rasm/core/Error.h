#pragma once
// One exception type for bad input: its message names the thing (file, section/key, frame)
// and what was expected. Applications print what() and exit non-zero.

#include <stdexcept>
#include <string>

namespace rasm {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Throws InputError("<what>: <problem>").
[[noreturn]] inline void throwInputError(const std::string& what, const std::string& problem) {
  throw InputError(what + ": " + problem);
}

}  // namespace rasm
