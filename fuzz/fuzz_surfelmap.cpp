// libFuzzer target: the surfel map deserializer (rasm::maps::CSurfelMap::serializeFrom through
// MRPT's archive, as `rasm run --map` reads a map.surfelmap; versions 0-3, keyframes, classes).
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdint>

#include "FuzzUtil.h"
#include "rasm/surfel_map/CSurfelMap.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  rasm::fuzz::expectOnlyInputErrors([&] {
    mrpt::io::CMemoryStream buf;
    buf.assignMemoryNotOwn(data, size);
    auto in = mrpt::serialization::archiveFrom(buf);
    rasm::maps::CSurfelMap map;
    in >> map;
    std::string why;
    if (!map.store().checkConsistency(&why)) {
      std::fprintf(stderr, "rasm fuzz: inconsistent map after loading: %s\n", why.c_str());
      std::abort();
    }
  });
  return 0;
}
