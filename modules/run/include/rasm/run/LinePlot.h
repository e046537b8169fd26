#pragma once
// The one PNG line plotter of rasm's outputs (exploration.png, plot_trajectory.png,
// plot_timing.png, `rasm eval memory --plot`, `rasm eval exploration --plot`): a white panel with a
// frame, tick marks and a light grid at round values (1, 2 or 5 times a power of ten) on both
// axes, guide lines, a legend, and each series as a polyline, dots or a filled band. OpenCV
// only, so every module and app/ can draw with it.

#include <limits>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace rasm::run {

struct PlotSeries {
  std::string label;  ///< legend entry; empty = none
  std::vector<double> x, y;
  cv::Scalar colour{0, 0, 0};  ///< BGR
  int thickness = 1;
  bool dots = false;  ///< small filled circles instead of a polyline
  /// When set (one value per x): the band between it and y is filled in the colour lightened
  /// halfway to white, y drawn over it (stacked areas: each layer's base is the one below).
  std::vector<double> fill_base{};
};

struct PlotAxes {
  std::string title, x_label, y_label;
  /// Ranges; a NaN bound is taken from the data.
  double x_min = std::numeric_limits<double>::quiet_NaN();
  double x_max = std::numeric_limits<double>::quiet_NaN();
  double y_min = std::numeric_limits<double>::quiet_NaN();
  double y_max = std::numeric_limits<double>::quiet_NaN();
  /// One data unit is as long on both axes (a top view in metres); the ranges are widened.
  bool equal_aspect = false;
  std::vector<double> y_guides;  ///< horizontal guide lines (light grey), their values printed
  std::vector<double> x_guides;  ///< vertical guide lines (light grey)
};

/// The tick values in [lo, hi]: the multiples of the smallest step of 1, 2 or 5 x 10^k that gives
/// at most max_ticks of them.
std::vector<double> niceTicks(double lo, double hi, int max_ticks);

/// Draws the plot into `panel` of `img` (CV_8UC3); points outside the ranges are clipped.
void drawLinePlot(cv::Mat& img, const cv::Rect& panel, const PlotAxes& axes,
                  const std::vector<PlotSeries>& series);
/// A new width x height image holding one plot.
cv::Mat linePlot(const PlotAxes& axes, const std::vector<PlotSeries>& series, int width = 640,
                 int height = 360);

}  // namespace rasm::run
