// Bounds the strings MRPT's deserializers read from rawlogs and maps (found by
// fuzz_rawlog): MRPT 2.5's `operator>>(CArchive&, std::string&)` resizes the string to the
// 32-bit length it reads before reading the bytes, so one corrupt length in a
// CObservation3DRangeScan's TCamera (or any sensor label) allocates up to 4 GB. This definition
// of the same exported function interposes MRPT's for the whole process (rasm_io is loaded before
// libmrpt-serialization, and MRPT's own libraries call it through the PLT): same wire format
// (uint32 length, then the bytes), but a length over kMaxArchiveStringBytes is an error, and the
// string grows only as bytes arrive. tests/io/RawlogFrameSource_unittest.cpp checks both.
#include <mrpt/core/exceptions.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cstdint>
#include <string>

namespace rasm::io {
/// Longest string read from an MRPT archive: labels, names and comments are far shorter.
constexpr std::uint32_t kMaxArchiveStringBytes = 64u << 20;
}  // namespace rasm::io

namespace mrpt::serialization {

CArchive& operator>>(CArchive& in, std::string& str) {
  std::uint32_t n = 0;
  in >> n;
  if (n > rasm::io::kMaxArchiveStringBytes)
    THROW_EXCEPTION_FMT(
        "serialized string of %u bytes (corrupt file?); rasm reads at most %u bytes per string",
        unsigned(n), unsigned(rasm::io::kMaxArchiveStringBytes));
  str.clear();
  constexpr std::uint32_t kChunk = 1u << 20;
  for (std::uint32_t done = 0; done < n;) {
    const std::uint32_t m = std::min(kChunk, n - done);
    str.resize(std::size_t(done) + m);
    in.ReadBuffer(&str[done], m);
    done += m;
  }
  return in;
}

}  // namespace mrpt::serialization
