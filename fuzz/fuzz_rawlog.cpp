// libFuzzer target: the rawlog frame reader (rasm::io::RawlogFrameSource: MRPT's two rawlog
// formats, gzip or plain, CObservation3DRangeScan -> RgbdFrame with validation) and the image
// decoding of the dataset readers (truncation checks, OpenCV decoders). The first byte selects
// the reader: even = rawlog, odd = an image file (colour, then 16-bit depth).
#include <cstdint>

#include "../modules/io/src/ImageCv.h"
#include "FuzzUtil.h"
#include "rasm/io/RawlogFrameSource.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const bool image = data[0] & 1;
  const std::string path = rasm::fuzz::scratchPath(image ? "image" : "input.rawlog");
  rasm::fuzz::writeFile(path, data + 1, size - 1);
  rasm::fuzz::expectOnlyInputErrors([&] {
    if (image) {
      rasm::Image<rasm::Bgr8> colour;
      rasm::io::detail::colourFromMat(rasm::io::detail::readColourImage(path, "fuzz colour"),
                                      colour, "fuzz colour");
      rasm::io::detail::readDepthU16(path, "fuzz depth");
      return;
    }
    rasm::io::RawlogFrameSource src(path);
    for (int i = 0; i < 64 && src.next(); ++i) {
    }
  });
  return 0;
}
