#include "rasm/pipeline/ClassLegend.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "rasm/surfel_map/MapExport.h"

namespace rasm::pipeline {

namespace {

constexpr int kPad = 12;
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
const cv::Scalar kWhite(255, 255, 255), kBlack(0, 0, 0);

double fontScale(double height_px) {
  return height_px / 22.0;
}
cv::Size textSize(const std::string& s, double height_px) {
  int base = 0;
  return cv::getTextSize(s, kFont, fontScale(height_px), 1, &base);
}

cv::Scalar classScalar(int class_id) {
  const Bgr8 c = maps::labelColour(class_id);
  return {double(c.b), double(c.g), double(c.r)};
}

cv::Point pixel(const cv::Point2d& q) {
  return {int(std::lround(q.x)), int(std::lround(q.y))};
}

/// A swatch (filled or outlined rectangle) or a text line (with a white halo), drawn in order
/// once the image's size is known.
struct Mark {
  bool is_text = false;
  cv::Point2d a, b;  ///< rectangle corners; text: a = baseline left
  cv::Scalar colour = kBlack;
  bool filled = false;
  std::string text;
  double height_px = 0.0;
};

void draw(cv::Mat& img, const Mark& m) {
  if (!m.is_text) {
    cv::rectangle(img, pixel(m.a), pixel(m.b), m.colour, m.filled ? cv::FILLED : 1);
    return;
  }
  cv::putText(img, m.text, pixel(m.a), kFont, fontScale(m.height_px), kWhite, 3, cv::LINE_AA);
  cv::putText(img, m.text, pixel(m.a), kFont, fontScale(m.height_px), m.colour, 1, cv::LINE_AA);
}

}  // namespace

cv::Mat classLegendImage(const std::vector<ClassLegendEntry>& entries) {
  std::vector<Mark> marks;
  const auto rect = [&](const cv::Point2d& a, const cv::Point2d& b, const cv::Scalar& c,
                        bool filled) {
    marks.push_back({false, a, b, c, filled, {}, 0.0});
  };
  const auto text = [&](const cv::Point2d& at, const std::string& s, double height_px) {
    marks.push_back({true, at, {}, kBlack, false, s, height_px});
  };
  double y = 26.0, width = 0.0;
  const auto row = [&](const cv::Scalar& colour, const std::string& label) {
    rect({kPad, y - 11}, {kPad + 22.0, y + 5}, colour, true);
    rect({kPad, y - 11}, {kPad + 22.0, y + 5}, kBlack, false);
    text({kPad + 32.0, y + 2}, label, 13);
    width = std::max(width, kPad + 32.0 + textSize(label, 13).width);
    y += 24;
  };
  const std::string title = "Classes (map_classes.ply, preview_classes.png)";
  text({double(kPad), y - 6}, title, 13);
  width = std::max(width, kPad + double(textSize(title, 13).width));
  y += 18;
  for (const ClassLegendEntry& e : entries)
    row(classScalar(e.class_id), e.name + " (" + std::to_string(e.surfels) + " surfels)");
  row(classScalar(0), "none: no class above the 0.5 prior");
  const std::string note = "colours fade to this grey as the probability falls to 0.5";
  text({double(kPad), y + 4}, note, 12);
  width = std::max(width, kPad + double(textSize(note, 12).width));
  cv::Mat img(int(y) + 18, int(width) + 2 * kPad, CV_8UC3, kWhite);
  for (const Mark& m : marks) draw(img, m);
  return img;
}

}  // namespace rasm::pipeline
