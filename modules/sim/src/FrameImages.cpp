#include "rasm/sim/FrameImages.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "rasm/core/AtomicFile.h"
#include "rasm/core/Error.h"
#include "rasm/sim/kernels/CounterRng.h"

namespace rasm::sim {

namespace {

cv::Vec3b idColour(std::uint16_t id) {
  if (id == 0) return {0, 0, 0};
  const std::uint64_t h = splitMix64(id);
  return {std::uint8_t(64 + (h & 191)), std::uint8_t(64 + ((h >> 8) & 191)),
          std::uint8_t(64 + ((h >> 16) & 191))};
}

void write(const std::string& path, const cv::Mat& m) {
  try {
    writeThroughTemporary(
        path,
        [&](const std::string& temp) {
          return cv::imwrite(temp, m, {cv::IMWRITE_PNG_COMPRESSION, 3});
        },
        ".part.png");
  } catch (const std::exception& e) {
    throwInputError(path, std::string("cannot write PNG: ") + e.what());
  }
}

cv::Mat colourised(const Image<std::uint16_t>& ids) {
  cv::Mat m(ids.height(), ids.width(), CV_8UC3);
  for (int y = 0; y < ids.height(); ++y)
    for (int x = 0; x < ids.width(); ++x) m.at<cv::Vec3b>(y, x) = idColour(ids(x, y));
  return m;
}

}  // namespace

void saveLabelPng(const Image<std::uint16_t>& labels, const std::string& path) {
  cv::Mat m(labels.height(), labels.width(), CV_16UC1, const_cast<std::uint16_t*>(labels.data()),
            labels.pitchBytes());
  write(path, m);
}

Image<std::uint16_t> loadLabelPng(const std::string& path) {
  const cv::Mat m = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (m.empty()) throwInputError(path, "cannot read PNG");
  if (m.type() != CV_16UC1) throwInputError(path, "expected a 16-bit single-channel label PNG");
  Image<std::uint16_t> out(m.cols, m.rows);
  for (int y = 0; y < m.rows; ++y)
    for (int x = 0; x < m.cols; ++x) out(x, y) = m.at<std::uint16_t>(y, x);
  return out;
}

void savePreviewImages(const RgbdFrame& f, const std::string& prefix, double max_depth_m) {
  const cv::Mat colour(f.colour.height(), f.colour.width(), CV_8UC3,
                       const_cast<Bgr8*>(f.colour.data()), f.colour.pitchBytes());
  write(prefix + "_colour.png", colour);
  cv::Mat d8(f.depth_m.height(), f.depth_m.width(), CV_8UC1);
  for (int y = 0; y < d8.rows; ++y)
    for (int x = 0; x < d8.cols; ++x) {
      const float z = f.depth_m(x, y);
      d8.at<std::uint8_t>(y, x) =
          z <= 0.f ? 0 : std::uint8_t(std::clamp(255.0 * (1.0 - z / max_depth_m), 1.0, 255.0));
    }
  cv::Mat dc;
  cv::applyColorMap(d8, dc, cv::COLORMAP_JET);
  dc.setTo(cv::Scalar(0, 0, 0), d8 == 0);
  write(prefix + "_depth.png", dc);
  if (!f.gt_instance.empty()) write(prefix + "_instance.png", colourised(f.gt_instance));
  if (!f.gt_class.empty()) write(prefix + "_class.png", colourised(f.gt_class));
}

}  // namespace rasm::sim
