#include "rasm/run/LinePlot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <opencv2/imgproc.hpp>

namespace rasm::run {

namespace {
const cv::Scalar kBlack(0, 0, 0), kGuide(200, 200, 200), kGrid(236, 236, 236);
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kTextScale = 0.42;

std::string number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", std::abs(v) < 1e-12 ? 0.0 : v);
  return b;
}

int textWidth(const std::string& s) {
  int base = 0;
  return cv::getTextSize(s, kFont, kTextScale, 1, &base).width;
}

/// [lo, hi] of the finite values of one coordinate of every series, where the axes leave it open.
void dataRange(const std::vector<PlotSeries>& series, bool x, double& lo, double& hi) {
  const bool lo_open = std::isnan(lo), hi_open = std::isnan(hi);
  double dlo = INFINITY, dhi = -INFINITY;
  for (const PlotSeries& s : series)
    for (double v : x ? s.x : s.y)
      if (std::isfinite(v)) dlo = std::min(dlo, v), dhi = std::max(dhi, v);
  if (!std::isfinite(dlo)) dlo = 0.0, dhi = 1.0;
  if (lo_open) lo = dlo;
  if (hi_open) hi = dhi;
  if (!(hi > lo)) {  // one value (or none): a unit range around it
    const double pad = std::max(0.5, 0.05 * std::abs(lo));
    if (lo_open) lo -= pad;
    if (hi_open || !(hi > lo)) hi = lo + 2 * pad;
  } else {  // a margin of 3% where the data sets the bound, so no curve runs along the frame
    const double pad = 0.03 * (hi - lo);
    if (lo_open) lo -= pad;
    if (hi_open) hi += pad;
  }
}

/// Rows of legend entries that fit `width` pixels.
std::vector<std::vector<const PlotSeries*>> legendRows(const std::vector<PlotSeries>& series,
                                                       int width) {
  std::vector<std::vector<const PlotSeries*>> rows(1);
  int used = 0;
  for (const PlotSeries& s : series) {
    if (s.label.empty()) continue;
    const int w = textWidth(s.label) + 34;
    if (used + w > width && !rows.back().empty()) rows.emplace_back(), used = 0;
    rows.back().push_back(&s);
    used += w;
  }
  if (rows.back().empty()) rows.pop_back();
  return rows;
}
/// The band between s.fill_base and s.y, one polygon per run of finite points.
void fillBand(cv::Mat& clip, const PlotSeries& s,
              const std::function<cv::Point(double, double)>& px, const cv::Point& o) {
  const cv::Scalar light = 0.5 * (s.colour + cv::Scalar(255, 255, 255));
  const std::size_t n = std::min({s.x.size(), s.y.size(), s.fill_base.size()});
  std::size_t i = 0;
  while (i < n) {
    std::vector<cv::Point> top, bottom;
    for (; i < n && std::isfinite(s.x[i]) && std::isfinite(s.y[i]) && std::isfinite(s.fill_base[i]);
         ++i) {
      top.push_back(px(s.x[i], s.y[i]) - o);
      bottom.push_back(px(s.x[i], s.fill_base[i]) - o);
    }
    if (top.size() > 1) {
      top.insert(top.end(), bottom.rbegin(), bottom.rend());
      cv::fillPoly(clip, std::vector<std::vector<cv::Point>>{top}, light);
    }
    ++i;
  }
}
}  // namespace

std::vector<double> niceTicks(double lo, double hi, int max_ticks) {
  std::vector<double> ticks;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi) || max_ticks < 1) return ticks;
  double step = std::pow(10.0, std::floor(std::log10((hi - lo) / max_ticks)));
  for (int k = 0; k < 4 && std::floor(hi / step) - std::ceil(lo / step) + 1 > max_ticks; ++k)
    step *= (k % 3 == 1) ? 2.5 : 2.0;  // 1, 2, 5, 10, 20, ...
  for (double t = std::ceil(lo / step - 1e-9) * step; t <= hi + 1e-9 * step; t += step)
    ticks.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
  return ticks;
}

void drawLinePlot(cv::Mat& img, const cv::Rect& panel, const PlotAxes& axes,
                  const std::vector<PlotSeries>& series) {
  const int L = 56, R = 16, B = 38;
  const auto rows = legendRows(series, panel.width - L - R);
  const int T = (axes.title.empty() ? 8 : 26) + 17 * int(rows.size()) + 4;
  const cv::Rect area(panel.x + L, panel.y + T, std::max(10, panel.width - L - R),
                      std::max(10, panel.height - T - B));
  double x0 = axes.x_min, x1 = axes.x_max, y0 = axes.y_min, y1 = axes.y_max;
  dataRange(series, true, x0, x1);
  dataRange(series, false, y0, y1);
  if (axes.equal_aspect) {  // widen the range that is short for its side
    const double s = std::max((x1 - x0) / area.width, (y1 - y0) / area.height);
    const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    x0 = cx - 0.5 * s * area.width, x1 = cx + 0.5 * s * area.width;
    y0 = cy - 0.5 * s * area.height, y1 = cy + 0.5 * s * area.height;
  }
  auto px = [&](double x, double y) {
    return cv::Point(area.x + int(std::lround(area.width * (x - x0) / (x1 - x0))),
                     area.y + area.height - int(std::lround(area.height * (y - y0) / (y1 - y0))));
  };
  // The grid at the ticks, under everything; the tick marks outside the frame.
  const std::vector<double> xt = niceTicks(x0, x1, std::max(2, area.width / 90)),
                            yt = niceTicks(y0, y1, std::max(2, area.height / 45));
  for (double t : xt) cv::line(img, px(t, y0), px(t, y1), kGrid);
  for (double t : yt) cv::line(img, px(x0, t), px(x1, t), kGrid);
  for (double g : axes.y_guides)
    if (g > y0 && g < y1) cv::line(img, px(x0, g), px(x1, g), kGuide);
  for (double g : axes.x_guides)
    if (g > x0 && g < x1) cv::line(img, px(g, y0), px(g, y1), kGuide);
  cv::rectangle(img, area, kBlack);
  for (double t : xt) cv::line(img, px(t, y0), px(t, y0) + cv::Point(0, 5), kBlack);
  for (double t : yt) cv::line(img, px(x0, t), px(x0, t) - cv::Point(5, 0), kBlack);
  if (!axes.title.empty())
    cv::putText(img, axes.title, cv::Point(panel.x + L, panel.y + 18), kFont, 0.48, kBlack);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    int x = panel.x + L;
    const int y = panel.y + T - 8 - 17 * int(rows.size() - 1 - r);
    for (const PlotSeries* s : rows[r]) {
      cv::line(img, cv::Point(x, y - 4), cv::Point(x + 22, y - 4), s->colour, 2);
      cv::putText(img, s->label, cv::Point(x + 27, y), kFont, kTextScale, s->colour);
      x += textWidth(s->label) + 34;
    }
  }
  // The ticks' values (centred under x ticks, kept inside the panel), the guides', the names.
  const int by = area.y + area.height;
  for (double t : xt) {
    const std::string v = number(t);
    const int x = std::clamp(px(t, y0).x - textWidth(v) / 2, panel.x + 2,
                             panel.x + panel.width - 2 - textWidth(v));
    cv::putText(img, v, cv::Point(x, by + 18), kFont, kTextScale, kBlack);
  }
  auto yLabel = [&](double v) {  // the top one below the frame's edge, clear of the axis name
    const std::string t = number(v);
    const int y = std::max(px(x0, v).y + 5, area.y + 12);
    cv::putText(img, t, cv::Point(area.x - 7 - textWidth(t), y), kFont, kTextScale, kBlack);
  };
  for (double t : yt) yLabel(t);
  for (double g : axes.y_guides)
    if (g > y0 && g < y1) yLabel(g);
  if (!axes.x_label.empty())
    cv::putText(img, axes.x_label,
                cv::Point(area.x + (area.width - textWidth(axes.x_label)) / 2, by + 30), kFont,
                kTextScale, kBlack);
  if (!axes.y_label.empty())
    cv::putText(img, axes.y_label, cv::Point(panel.x + 4, area.y - 3), kFont, kTextScale, kBlack);
  cv::Mat clip = img(area);  // curves stay inside the frame
  const cv::Point o(area.x, area.y);
  for (const PlotSeries& s : series)
    if (!s.fill_base.empty()) fillBand(clip, s, px, o);
  for (const PlotSeries& s : series) {
    const std::size_t n = std::min(s.x.size(), s.y.size());
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      const cv::Point p = px(s.x[i], s.y[i]) - o;
      if (s.dots) {
        cv::circle(clip, p, s.thickness + 1, s.colour, cv::FILLED);
      } else if (i > 0 && std::isfinite(s.x[i - 1]) && std::isfinite(s.y[i - 1])) {
        cv::Point a = px(s.x[i - 1], s.y[i - 1]) - o, b = p;
        if (cv::clipLine(cv::Rect(0, 0, area.width, area.height), a, b))
          cv::line(clip, a, b, s.colour, s.thickness, cv::LINE_AA);
      }
    }
  }
}

cv::Mat linePlot(const PlotAxes& axes, const std::vector<PlotSeries>& series, int width,
                 int height) {
  cv::Mat img(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  drawLinePlot(img, cv::Rect(0, 0, width, height), axes, series);
  return img;
}

}  // namespace rasm::run
