#pragma once
// Internal: rasm::Image <-> cv::Mat without copies where possible, and image file reading with
// InputErrors that name the file.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "rasm/compute/Types.h"
#include "rasm/core/Image.h"

namespace rasm::io::detail {

/// cv::Mat headers over an Image's pitched buffer (no copy).
cv::Mat cvView(Image<Bgr8>& img);
cv::Mat cvView(const Image<Bgr8>& img);  ///< do not write through it
cv::Mat cvView(Image<float>& img);
cv::Mat cvView(Image<std::uint16_t>& img);

/// Copies an 8-bit image (BGR, BGRA or grey, which is replicated) into `out`.
void colourFromMat(const cv::Mat& m, Image<Bgr8>& out, const std::string& what);

/// depth_m = raw * metres_per_unit for raw not in `invalid_values` (0 always invalid).
void depthFromU16(const cv::Mat& raw, double metres_per_unit, Image<float>& out,
                  std::uint16_t also_invalid = 0);

/// The largest image rasm decodes (either side, and pixels in all): a frame never takes more
/// than 4096 x 4096 x 3 bytes, whatever its file's header claims.
constexpr int kMaxImageSide = 16384;
constexpr long long kMaxImagePixels = 4096LL * 4096LL;
/// The largest image file rasm reads into memory.
constexpr long long kMaxImageFileBytes = 256LL << 20;

/// What a PNG (IHDR) or JPEG (SOF) header says, read without decoding; `format` is empty for
/// other formats or an unreadable header.
struct ImageHeader {
  std::string format;  ///< "PNG", "JPEG" or ""
  int width = 0, height = 0;
  int bit_depth = 0;  ///< bits per sample
  int channels = 0;   ///< samples per pixel (a palette PNG: 1)
};
ImageHeader readImageHeader(const std::vector<unsigned char>& bytes);

/// cv::imread that throws InputError "<what> <path>: missing / unreadable / not 16-bit...".
/// A truncated JPEG or PNG (no end-of-image marker / IEND chunk) is an error, not the partly grey
/// image libjpeg returns with only a warning on stderr. The header is checked before decoding:
/// a size above kMaxImagePixels, or other than `expected` (when not empty), or (depth) a PNG
/// that is not 16-bit grey is refused in microseconds, not after gigabytes of decoding.
cv::Mat readColourImage(const std::string& path, const std::string& what,
                        cv::Size expected = cv::Size());
cv::Mat readDepthU16(const std::string& path, const std::string& what,
                     cv::Size expected = cv::Size());

/// "" for a complete JPEG / PNG (or another format, not checked), else what is missing.
std::string truncationProblem(const std::vector<unsigned char>& bytes);

/// Flips rows in place (negative-fy cameras).
template <typename T>
void flipRows(Image<T>& img) {
  for (int y = 0, y2 = img.height() - 1; y < y2; ++y, --y2)
    for (int x = 0; x < img.width(); ++x) std::swap(img(x, y), img(x, y2));
}

}  // namespace rasm::io::detail
