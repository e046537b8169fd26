#include "rasm/pipeline/RunPlots.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "rasm/pipeline/LinePlot.h"

namespace rasm::pipeline {

namespace {
std::vector<std::string> splitRow(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream s(line);
  std::string cell;
  while (std::getline(s, cell, ',')) cells.push_back(cell);
  return cells;
}

double toNumber(const std::string& cell) {
  char* end = nullptr;
  const double v = std::strtod(cell.c_str(), &end);
  return end != cell.c_str() && *end == '\0' ? v : std::nan("");
}

const cv::Scalar kStageColours[] = {{200, 80, 0},  {0, 0, 200},   {0, 150, 0},
                                    {150, 0, 150}, {0, 140, 255}, {140, 140, 0},
                                    {90, 60, 200}, {0, 90, 140},  {120, 120, 120}};
}  // namespace

CsvColumns parseCsvColumns(const std::string& text) {
  CsvColumns c;
  std::stringstream s(text);
  std::string line;
  if (!std::getline(s, line)) return c;
  c.names = splitRow(line);
  for (const std::string& n : c.names) c.values[n];
  while (std::getline(s, line)) {
    if (line.empty()) continue;
    const std::vector<std::string> cells = splitRow(line);
    for (std::size_t k = 0; k < c.names.size(); ++k)
      c.values[c.names[k]].push_back(k < cells.size() ? toNumber(cells[k]) : std::nan(""));
    ++c.rows;
  }
  return c;
}

cv::Mat trajectoryPlot(const io::Trajectory& estimate, const io::Trajectory& groundtruth,
                       const CsvColumns& frames) {
  PlotSeries gt{"ground truth", {}, {}, cv::Scalar(0, 150, 0), 2};
  for (const io::StampedPose& p : groundtruth) {
    gt.x.push_back(p.T_world_cam.translation().x());
    gt.y.push_back(p.T_world_cam.translation().y());
  }
  PlotSeries est{"estimate", {}, {}, cv::Scalar(200, 80, 0), 1};
  PlotSeries lost{"tracking lost", {}, {}, cv::Scalar(0, 0, 220), 1, true};
  const auto tracked = frames.values.find("tracked");
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    const Eigen::Vector3d t = estimate[i].T_world_cam.translation();
    est.x.push_back(t.x());
    est.y.push_back(t.y());
    if (tracked != frames.values.end() && i < tracked->second.size() && tracked->second[i] == 0)
      lost.x.push_back(t.x()), lost.y.push_back(t.y());
  }
  PlotAxes axes;
  axes.title = "camera path, top view (world x, y)";
  axes.x_label = "x (m)";
  axes.y_label = "y (m)";
  axes.equal_aspect = true;
  std::vector<PlotSeries> series;
  if (!gt.x.empty()) series.push_back(gt);
  series.push_back(est);
  if (!lost.x.empty()) series.push_back(lost);
  return linePlot(axes, series, 560, 560);
}

cv::Mat timingPlot(const CsvColumns& frames) {
  std::vector<PlotSeries> series;
  const auto index = frames.values.find("index");
  std::vector<double> x;
  for (std::size_t i = 0; i < frames.rows; ++i)
    x.push_back(index != frames.values.end() ? index->second[i] : double(i));
  double top = 0.0;
  int k = 0;
  for (const std::string& name : frames.names) {
    if (name.rfind("ms_", 0) != 0) continue;
    const std::vector<double>& v = frames.values.at(name);
    PlotSeries s{name.substr(3), x, v, kStageColours[k++ % 9], 1};
    if (name == "ms_total") {
      s.colour = cv::Scalar(0, 0, 0);
      s.thickness = 2;
      std::vector<double> sorted;
      for (double t : v)
        if (std::isfinite(t)) sorted.push_back(t);
      if (!sorted.empty()) {
        std::sort(sorted.begin(), sorted.end());
        top = sorted[std::min(sorted.size() - 1, sorted.size() * 99 / 100)];
      }
    }
    series.push_back(std::move(s));
  }
  if (series.empty() || frames.rows == 0) return {};
  PlotAxes axes;
  axes.title = "time per frame of each stage (frames.csv ms_*)";
  axes.x_label = "frame";
  axes.y_label = "ms";
  axes.y_min = 0.0;
  if (top > 0) axes.y_max = 1.1 * top;
  return linePlot(axes, series, 900, 420);
}

}  // namespace rasm::pipeline
