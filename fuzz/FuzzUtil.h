#pragma once
// Shared by the libFuzzer targets (fuzz/README in docs/io.md "Bad input and fuzzing"): expected
// errors (rasm::InputError, MRPT's std::exceptions) are what bad input must produce; anything
// else (a crash, a sanitizer report, a hang, an allocation beyond libFuzzer's -malloc_limit_mb,
// std::bad_alloc or std::length_error from a size field taken on trust) is a finding.

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <new>
#include <stdexcept>
#include <string>

namespace rasm::fuzz {

/// A per-process scratch file name (fuzzers may run as parallel jobs).
inline std::string scratchPath(const std::string& name) {
  const char* dir = std::getenv("TMPDIR");
  return std::string(dir && *dir ? dir : "/tmp") + "/rasm_fuzz_" + std::to_string(::getpid()) +
         "_" + name;
}

inline void writeFile(const std::string& path, const std::uint8_t* data, std::size_t size) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(reinterpret_cast<const char*>(data), std::streamsize(size));
}

/// Runs `body`; expected errors are swallowed, unbounded allocations abort (a finding).
template <typename F>
void expectOnlyInputErrors(F&& body) {
  try {
    body();
  } catch (const std::bad_alloc& e) {
    std::fprintf(stderr, "rasm fuzz: std::bad_alloc (unbounded allocation?): %s\n", e.what());
    std::abort();
  } catch (const std::length_error& e) {
    std::fprintf(stderr, "rasm fuzz: std::length_error (size taken on trust?): %s\n", e.what());
    std::abort();
  } catch (const std::exception&) {
    // rasm::InputError or an MRPT exception: the reader rejected the input, as it should.
  }
}

}  // namespace rasm::fuzz
