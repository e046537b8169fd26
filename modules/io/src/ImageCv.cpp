#include "ImageCv.h"

#include <filesystem>
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

static void requireFile(const std::string& path, const std::string& what) {
  if (!std::filesystem::is_regular_file(path)) throwInputError(what + " " + path, "file not found");
}

cv::Mat readColourImage(const std::string& path, const std::string& what) {
  requireFile(path, what);
  // IMREAD_COLOR decodes to 8-bit BGR, the order of rasm::Bgr8 (grey files are expanded).
  cv::Mat m = cv::imread(path, cv::IMREAD_COLOR);
  if (m.empty()) throwInputError(what + " " + path, "cannot decode the image");
  return m;
}

cv::Mat readDepthU16(const std::string& path, const std::string& what) {
  requireFile(path, what);
  cv::Mat m = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (m.empty()) throwInputError(what + " " + path, "cannot decode the image");
  if (m.type() != CV_16UC1)
    throwInputError(
        what + " " + path,
        "expected a 16-bit single-channel depth PNG, got OpenCV type " + std::to_string(m.type()));
  return m;
}

}  // namespace rasm::io::detail
