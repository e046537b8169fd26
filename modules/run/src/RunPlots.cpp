#include "rasm/run/RunPlots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "rasm/io/TimestampAssociation.h"
#include "rasm/run/LinePlot.h"

namespace rasm::run {

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
constexpr int kRunningMean = 10;

double finiteMean(const std::vector<double>& v) {
  double sum = 0.0;
  int n = 0;
  for (double t : v)
    if (std::isfinite(t)) sum += t, ++n;
  return n > 0 ? sum / n : 0.0;
}

/// A timer's curve: the running mean over kRunningMean frames (a frame's own time jumps with the
/// load of the machine); its legend gives the timer's mean.
PlotSeries timerSeries(const std::string& name, double mean, const std::vector<double>& x,
                       const std::vector<double>& ms, const cv::Scalar& colour, int thickness) {
  char label[96];
  std::snprintf(label, sizeof label, "%s %.1f", name.c_str(), mean);
  PlotSeries s{label, x, {}, colour, thickness};
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < ms.size(); ++i) {
    if (std::isfinite(ms[i])) sum += ms[i], ++n;
    if (i >= std::size_t(kRunningMean) && std::isfinite(ms[i - kRunningMean]))
      sum -= ms[i - kRunningMean], --n;
    s.y.push_back(n > 0 ? sum / n : std::nan(""));
  }
  return s;
}
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
  PlotSeries gt{"ground truth", {}, {}, cv::Scalar(120, 220, 120), 4};  // wide, under the estimate
  for (const io::StampedPose& p : groundtruth) {
    gt.x.push_back(p.T_world_cam.translation().x());
    gt.y.push_back(p.T_world_cam.translation().y());
  }
  PlotSeries est{"estimate", {}, {}, cv::Scalar(200, 60, 0), 1};
  PlotSeries lost{"tracking lost", {}, {}, cv::Scalar(0, 0, 220), 2, true};
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

namespace {
/// The frames.csv column `name`, NaN per row when it is missing.
std::vector<double> column(const CsvColumns& frames, const std::string& name) {
  const auto c = frames.values.find(name);
  return c != frames.values.end() ? c->second : std::vector<double>(frames.rows, std::nan(""));
}

/// The plots' x axis: frames.csv's `index` per row, the row number where it has none.
std::vector<double> frameAxis(const CsvColumns& frames) {
  const std::vector<double> index = column(frames, "index");
  std::vector<double> x;
  for (std::size_t i = 0; i < frames.rows; ++i)
    x.push_back(std::isfinite(index[i]) ? index[i] : double(i));
  return x;
}

/// A band from y_lo to y_hi over the frames tracking lost (light red), each lost frame half a
/// frame either side of its x (a single one shows), NaN between the runs.
PlotSeries lostBand(const std::vector<double>& x, const std::vector<double>& tracked, double y_lo,
                    double y_hi, bool with_label) {
  PlotSeries s{with_label ? "tracking lost" : "", {}, {}, cv::Scalar(150, 150, 255), 1};
  for (std::size_t i = 0; i < x.size(); ++i) {
    const bool lost = i < tracked.size() && tracked[i] == 0;
    for (const double dx : {-0.5, 0.5}) {
      s.x.push_back(x[i] + dx);
      s.y.push_back(lost ? y_hi : std::nan(""));
      s.fill_base.push_back(lost ? y_lo : std::nan(""));
    }
  }
  return s;
}
}  // namespace

cv::Mat trackingPlot(const CsvColumns& frames, const io::Trajectory& estimate,
                     const io::Trajectory& groundtruth) {
  if (frames.rows == 0) return {};
  const std::vector<double> x = frameAxis(frames), tracked = column(frames, "tracked");
  // World-frame error per estimated pose, placed at its frame by order (trajectory.txt holds one
  // pose per processed frame, as frames.csv one row).
  std::vector<double> err_cm(frames.rows, std::nan(""));
  std::vector<double> te, tg;
  for (const io::StampedPose& p : estimate) te.push_back(p.timestamp_s);
  for (const io::StampedPose& p : groundtruth) tg.push_back(p.timestamp_s);
  bool have_error = false;
  if (estimate.size() == frames.rows)
    for (const auto& [i, j] : io::associateTimestamps(te, tg)) {
      err_cm[i] =
          100.0 *
          (estimate[i].T_world_cam.translation() - groundtruth[j].T_world_cam.translation()).norm();
      have_error = true;
    }
  const int panels = have_error ? 3 : 2, h = 240;
  cv::Mat img(panels * h, 900, CV_8UC3, cv::Scalar(255, 255, 255));
  const auto max_finite = [](const std::vector<double>& v, double floor) {
    double m = floor;
    for (double t : v)
      if (std::isfinite(t)) m = std::max(m, t);
    return m;
  };
  PlotAxes a1;
  a1.title = "tracking quality per frame (frames.csv); red: frames tracking lost";
  a1.y_label = "fraction", a1.y_min = 0.0, a1.y_max = 1.05;
  a1.x_min = x.front(), a1.x_max = x.back();
  drawLinePlot(img, cv::Rect(0, 0, 900, h), a1,
               {lostBand(x, tracked, 0.0, 1.05, true),
                {"ICP inlier fraction", x, column(frames, "inlier_fraction"), {200, 80, 0}, 1},
                {"pose check agreement", x, column(frames, "check_agreement"), {0, 150, 0}, 1}});
  std::vector<double> rms_mm = column(frames, "rms_m");
  for (double& v : rms_mm) v *= 1000.0;
  PlotAxes a2 = a1;
  a2.title.clear(), a2.y_label = "mm", a2.y_max = 1.05 * max_finite(rms_mm, 1.0);
  a2.x_label = have_error ? "" : "frame";
  drawLinePlot(img, cv::Rect(0, h, 900, h), a2,
               {lostBand(x, tracked, 0.0, a2.y_max, false),
                {"ICP residual (rms)", x, rms_mm, {0, 0, 200}, 1}});
  if (have_error) {
    PlotAxes a3 = a2;
    a3.y_label = "cm", a3.x_label = "frame", a3.y_max = 1.05 * max_finite(err_cm, 1.0);
    drawLinePlot(img, cv::Rect(0, 2 * h, 900, h), a3,
                 {lostBand(x, tracked, 0.0, a3.y_max, false),
                  {"world-frame position error (no alignment)", x, err_cm, {120, 0, 120}, 1}});
  }
  return img;
}

cv::Mat objectsPlot(const CsvColumns& frames) {
  if (frames.rows == 0 || !frames.values.count("objects")) return {};
  const std::vector<double> x = frameAxis(frames), objects = column(frames, "objects");
  const std::vector<double> fused = column(frames, "cls_fused");
  std::vector<double> fused_so_far;
  double sum = 0.0, most = 1.0;
  for (std::size_t i = 0; i < frames.rows; ++i) {
    if (std::isfinite(fused[i])) sum += fused[i];
    fused_so_far.push_back(sum);
    if (std::isfinite(objects[i])) most = std::max(most, objects[i]);
  }
  // With a simulated world: the objects named right where they were measured (sparse rows).
  const std::vector<double> correct = column(frames, "objects_correct"),
                            detectable = column(frames, "objects_detectable");
  PlotSeries right{"", {}, {}, {0, 140, 220}, 1};
  for (std::size_t i = 0; i < frames.rows; ++i)
    if (std::isfinite(correct[i]) && std::isfinite(detectable[i])) {
      right.x.push_back(x[i]), right.y.push_back(correct[i]);
      right.label = "objects of the world named right (ground truth; of " +
                    std::to_string(int(detectable[i])) + " detectable)";
      most = std::max(most, detectable[i]);
    }
  const int h = 240;
  cv::Mat img(2 * h, 900, CV_8UC3, cv::Scalar(255, 255, 255));
  PlotAxes a1;
  a1.title = "the object list as it grows (frames.csv)";
  a1.y_label = "objects", a1.y_min = 0.0, a1.y_max = 1.1 * most;
  a1.x_min = x.front(), a1.x_max = std::max(x.back(), x.front() + 1.0);
  std::vector<PlotSeries> top = {
      {"objects listed (objects.json's rule)", x, objects, {160, 60, 0}, 2}};
  if (!right.x.empty()) {
    PlotSeries dots = right;
    dots.label.clear(), dots.dots = true;
    top.push_back(right);
    top.push_back(dots);
  }
  drawLinePlot(img, cv::Rect(0, 0, 900, h), a1, top);
  PlotAxes a2 = a1;
  a2.title.clear(), a2.y_label = "detections", a2.x_label = "frame";
  a2.y_max = 1.05 * std::max(1.0, sum);
  drawLinePlot(img, cv::Rect(0, h, 900, h), a2,
               {{"detections fused so far", x, fused_so_far, {0, 120, 0}, 1}});
  return img;
}

cv::Mat timingPlot(const CsvColumns& frames, const std::vector<std::string>& stages) {
  const auto total = frames.values.find("ms_total");
  if (frames.rows == 0 || total == frames.values.end()) return {};
  const std::vector<double> x = frameAxis(frames);
  // Stacked layers: each stage's running mean on top of the ones before it (a stage's own
  // timer holds its parts, so only stages stack), then the rest of the frame up to the total.
  std::vector<PlotSeries> series;
  std::vector<double> base(frames.rows, 0.0), stacked(frames.rows, 0.0);
  int k = 0;
  const auto layer = [&](const std::string& name, const std::vector<double>& ms,
                         const cv::Scalar& colour) {
    PlotSeries s = timerSeries(name, finiteMean(ms), x, ms, colour, 1);
    for (std::size_t i = 0; i < frames.rows; ++i) {
      const double v = std::isfinite(s.y[i]) ? s.y[i] : 0.0;
      stacked[i] = base[i] + v;
    }
    s.y = stacked;
    s.fill_base = base;
    base = stacked;
    series.push_back(s);
  };
  std::vector<double> rest = total->second;
  for (const std::string& name : stages) {
    const auto col = frames.values.find("ms_" + name);
    if (col == frames.values.end()) continue;
    for (std::size_t i = 0; i < frames.rows; ++i)
      if (std::isfinite(col->second[i]) && std::isfinite(rest[i])) rest[i] -= col->second[i];
    layer(name, col->second, kStageColours[k++ % 9]);
  }
  for (double& r : rest) r = std::max(0.0, r);  // the stages' own rounding
  layer("rest of the frame", rest, cv::Scalar(190, 190, 190));
  const double total_mean = finiteMean(total->second);
  series.push_back(timerSeries("total", total_mean, x, total->second, cv::Scalar(0, 0, 0), 2));
  std::vector<double> sorted;
  for (double t : series.back().y)
    if (std::isfinite(t)) sorted.push_back(t);
  PlotAxes axes;
  axes.title = "ms per frame by stage, stacked (frames.csv ms_*, " + std::to_string(kRunningMean) +
               "-frame running means; legend: mean)";
  axes.x_label = "frame";
  axes.x_min = x.front();
  axes.x_max = x.back();
  axes.y_label = "ms";
  axes.y_min = 0.0;
  if (!sorted.empty()) {
    std::sort(sorted.begin(), sorted.end());
    axes.y_max =
        1.1 * std::max(1e-3, sorted[std::min(sorted.size() - 1, sorted.size() * 99 / 100)]);
  }
  return linePlot(axes, series, 900, 420);
}

cv::Mat explorationPlot(const std::vector<autonomy::ExplorationMetricsRow>& metrics) {
  if (metrics.size() < 2) return {};
  PlotSeries coverage{"coverage", {}, {}, cv::Scalar(200, 80, 0), 2};
  PlotSeries objects{"objects correct", {}, {}, cv::Scalar(0, 0, 200), 2};
  for (const autonomy::ExplorationMetricsRow& r : metrics) {
    coverage.x.push_back(r.t);
    coverage.y.push_back(r.coverage);
    objects.x.push_back(r.t);
    objects.y.push_back(r.objects_correct);
  }
  PlotAxes axes;
  axes.title = "exploration: fractions of the world's surface and objects";
  axes.x_label = "simulated time (s)";
  axes.x_min = 0.0;
  axes.x_max = std::max(1.0, metrics.back().t);
  axes.y_min = 0.0;
  axes.y_max = 1.0;
  axes.y_guides = {0.25, 0.5, 0.75};
  return linePlot(axes, {coverage, objects});
}

}  // namespace rasm::run
