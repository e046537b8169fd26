#include "ImageCv.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "rasm/core/Error.h"

namespace rasm::io::detail {

cv::Mat cvView(Image<Bgr8>& img) {
  return cv::Mat(img.height(), img.width(), CV_8UC3, img.data(), img.pitchBytes());
}
cv::Mat cvView(const Image<Bgr8>& img) {
  return cv::Mat(img.height(), img.width(), CV_8UC3, const_cast<Bgr8*>(img.data()),
                 img.pitchBytes());
}
cv::Mat cvView(Image<float>& img) {
  return cv::Mat(img.height(), img.width(), CV_32FC1, img.data(), img.pitchBytes());
}
cv::Mat cvView(Image<std::uint16_t>& img) {
  return cv::Mat(img.height(), img.width(), CV_16UC1, img.data(), img.pitchBytes());
}

void colourFromMat(const cv::Mat& m, Image<Bgr8>& out, const std::string& what) {
  if (m.depth() != CV_8U)
    throwInputError(what, "colour image must be 8-bit per channel, got OpenCV depth " +
                              std::to_string(m.depth()));
  out.resize(m.cols, m.rows);
  cv::Mat dst = cvView(out);
  switch (m.channels()) {
    case 3:
      m.copyTo(dst);
      break;
    case 1:
      cv::cvtColor(m, dst, cv::COLOR_GRAY2BGR);
      break;
    case 4:
      cv::cvtColor(m, dst, cv::COLOR_BGRA2BGR);
      break;
    default:
      throwInputError(what, "colour image has " + std::to_string(m.channels()) +
                                " channels, expected 1, 3 or 4");
  }
}

void depthFromU16(const cv::Mat& raw, double metres_per_unit, Image<float>& out,
                  std::uint16_t also_invalid) {
  out.resize(raw.cols, raw.rows);
  const float k = float(metres_per_unit);
  for (int y = 0; y < raw.rows; ++y) {
    const auto* src = raw.ptr<std::uint16_t>(y);
    float* dst = out.row(y);
    for (int x = 0; x < raw.cols; ++x) {
      const std::uint16_t v = src[x];
      dst[x] = (v == 0 || (also_invalid != 0 && v == also_invalid)) ? 0.0f : float(v) * k;
    }
  }
}

std::string truncationProblem(const std::vector<unsigned char>& b) {
  const std::size_t n = b.size();
  if (n >= 2 && b[0] == 0xFF && b[1] == 0xD8) {
    // JPEG: the stream ends with the end-of-image marker FF D9 (padding after it is tolerated).
    std::size_t e = n;
    while (e > 2 && (b[e - 1] == 0x00 || b[e - 1] == 0x0A || b[e - 1] == 0x0D || b[e - 1] == 0x20))
      --e;
    if (e < 4 || b[e - 2] != 0xFF || b[e - 1] != 0xD9)
      return "truncated JPEG: no end-of-image marker (FF D9) after " + std::to_string(n) +
             " bytes (libjpeg would only warn \"Premature end of JPEG file\" and fill the rest "
             "grey)";
    return "";
  }
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  if (n >= 8 && std::equal(kPng, kPng + 8, b.begin())) {
    // PNG: the last chunk is IEND (length 0, type "IEND", CRC).
    if (n < 8 + 12 || !std::equal(b.end() - 8, b.end() - 4, "IEND"))
      return "truncated PNG: the file does not end with the IEND chunk (" + std::to_string(n) +
             " bytes)";
  }
  return "";
}

ImageHeader readImageHeader(const std::vector<unsigned char>& b) {
  ImageHeader h;
  const std::size_t n = b.size();
  const auto be16 = [&](std::size_t i) { return int(b[i]) << 8 | int(b[i + 1]); };
  const auto be32 = [&](std::size_t i) {
    return (long long)b[i] << 24 | (long long)b[i + 1] << 16 | (long long)b[i + 2] << 8 |
           (long long)b[i + 3];
  };
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  if (n >= 33 && std::equal(kPng, kPng + 8, b.begin()) &&
      std::equal(b.begin() + 12, b.begin() + 16, "IHDR")) {
    // IHDR: width, height (big-endian uint32), bit depth, colour type (0 grey, 2 RGB, 3 palette,
    // 4 grey + alpha, 6 RGBA).
    const long long w = be32(16), hh = be32(20);
    h.width = int(std::min<long long>(w, 1LL << 30));
    h.height = int(std::min<long long>(hh, 1LL << 30));
    h.bit_depth = b[24];
    static const int kChannels[7] = {1, 0, 3, 1, 2, 0, 4};
    h.channels = b[25] <= 6 ? kChannels[b[25]] : 0;
    h.format = "PNG";
    return h;
  }
  if (n >= 4 && b[0] == 0xFF && b[1] == 0xD8) {
    // JPEG: markers up to the first start-of-frame (SOF0-15 but DHT C4, JPG C8, DAC CC): sample
    // precision, height, width, components.
    std::size_t i = 2;
    while (i + 4 <= n && b[i] == 0xFF) {
      const int marker = b[i + 1];
      if (marker == 0xFF) {
        ++i;
        continue;
      }
      if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD9)) {
        i += 2;
        continue;
      }
      const int len = be16(i + 2);
      if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) {
        if (i + 10 > n) break;
        h.bit_depth = b[i + 4];
        h.height = be16(i + 5);
        h.width = be16(i + 7);
        h.channels = b[i + 9];
        h.format = "JPEG";
        return h;
      }
      i += 2 + std::size_t(len);
    }
  }
  return h;
}

namespace {
/// The bytes of an image file, checked for truncation and by their header (size, bit depth),
/// decoded by OpenCV.
cv::Mat decodeFile(const std::string& path, const std::string& what, int flags, cv::Size expected,
                   bool depth_u16) {
  if (std::filesystem::is_directory(path))
    throwInputError(what + " " + path, "is a folder, expected an image file");
  if (!std::filesystem::is_regular_file(path)) throwInputError(what + " " + path, "file not found");
  std::error_code ec;
  const auto file_bytes = std::filesystem::file_size(path, ec);
  if (!ec && (long long)file_bytes > kMaxImageFileBytes)
    throwInputError(what + " " + path, "holds " + std::to_string(file_bytes) +
                                           " bytes: larger than any image rasm reads (at most " +
                                           std::to_string(kMaxImageFileBytes >> 20) + " MiB)");
  std::ifstream f(path, std::ios::binary);
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(f)),
                                   std::istreambuf_iterator<char>());
  if (!f.eof() && f.fail()) throwInputError(what + " " + path, "cannot read the file");
  if (bytes.empty()) throwInputError(what + " " + path, "empty file, expected an image");
  const ImageHeader h = readImageHeader(bytes);
  if (!h.format.empty()) {
    const std::string says = "its " + h.format + " header says " + std::to_string(h.width) + "x" +
                             std::to_string(h.height);
    if (h.width <= 0 || h.height <= 0 || h.width > kMaxImageSide || h.height > kMaxImageSide ||
        (long long)h.width * h.height > kMaxImagePixels)
      throwInputError(what + " " + path,
                      says +
                          (expected.area() > 0 ? ", expected " + std::to_string(expected.width) +
                                                     "x" + std::to_string(expected.height)
                                               : std::string()) +
                          " (rasm reads images of at most 4096x4096 pixels)");
    if (expected.area() > 0 && (h.width != expected.width || h.height != expected.height))
      throwInputError(what + " " + path, says + ", expected " + std::to_string(expected.width) +
                                             "x" + std::to_string(expected.height) +
                                             " (the size of the sequence's first depth image)");
    if (depth_u16 && h.format == "PNG" && (h.bit_depth != 16 || h.channels != 1))
      throwInputError(what + " " + path, "expected a 16-bit single-channel depth PNG, " + says +
                                             " with " + std::to_string(h.channels) +
                                             " channel(s) of " + std::to_string(h.bit_depth) +
                                             " bits");
  }
  const std::string truncated = truncationProblem(bytes);
  if (!truncated.empty()) throwInputError(what + " " + path, truncated);
  cv::Mat m;
  try {
    m = cv::imdecode(bytes, flags);
  } catch (const cv::Exception& e) {
    throwInputError(what + " " + path, std::string("cannot decode the image: ") + e.what());
  }
  if (m.empty()) throwInputError(what + " " + path, "cannot decode the image");
  return m;
}
}  // namespace

cv::Mat readColourImage(const std::string& path, const std::string& what, cv::Size expected) {
  // IMREAD_COLOR decodes to 8-bit BGR, the order of rasm::Bgr8 (grey files are expanded).
  return decodeFile(path, what, cv::IMREAD_COLOR, expected, false);
}

cv::Mat readDepthU16(const std::string& path, const std::string& what, cv::Size expected) {
  cv::Mat m = decodeFile(path, what, cv::IMREAD_UNCHANGED, expected, true);
  if (m.type() != CV_16UC1)
    throwInputError(
        what + " " + path,
        "expected a 16-bit single-channel depth PNG, got OpenCV type " + std::to_string(m.type()));
  return m;
}

}  // namespace rasm::io::detail
