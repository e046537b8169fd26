#pragma once
// The plots of a run folder, drawn with LinePlot.h:
//   plot_trajectory.png  top view (x, y in m, equal scales) of the estimated camera path against
//                        the ground truth; frames tracking lost (frames.csv tracked = 0) in red
//   plot_timing.png      milliseconds per frame of the Mapper's stages (frames.csv ms_<stage>)
//                        stacked in their order, then the rest of the frame (total minus the
//                        stages, grey), so the layers add up to the total (black line); 10-frame
//                        running means over the frame index (legend: each layer's mean); the
//                        parts of a stage (ms_icp within ms_tracking) are not stacked again; the
//                        y range ends at the 99th percentile of the total
//   plot_tracking.png    tracking quality per frame: the ICP inlier fraction and the pose check's
//                        agreement (top), the ICP residual in mm (middle) and, with ground truth,
//                        the camera's world-frame position error in cm (bottom; no alignment:
//                        the map starts at the first true pose); frames tracking lost (frames.csv
//                        tracked = 0) shaded red in every panel
//   plot_objects.png     the object list as it grows: objects the object layer would list at
//                        each frame (frames.csv objects, top) and the detections fused so far
//                        (cumulative cls_fused, bottom), for every run that classifies; with a
//                        simulated world also the objects named right against its truth where
//                        frames.csv measured them (objects_correct, of objects_detectable)
//   exploration.png      an exploring run with the simulator's truth: the fractions of the
//                        world's surface seen and of its objects carrying their right class
//                        against simulated time (ExplorationLoop's metrics rows)

#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "rasm/autonomy/ExplorationMetrics.h"
#include "rasm/io/Trajectory.h"

namespace rasm::run {

/// A CSV text with a header row (frames.csv): columns by name, every value as a number (NaN
/// where a cell is not one).
struct CsvColumns {
  std::vector<std::string> names;  ///< in file order
  std::map<std::string, std::vector<double>> values;
  std::size_t rows = 0;
};
CsvColumns parseCsvColumns(const std::string& text);

/// plot_trajectory.png. `frames` = frames.csv (for the tracked column; may be empty).
cv::Mat trajectoryPlot(const io::Trajectory& estimate, const io::Trajectory& groundtruth,
                       const CsvColumns& frames);
/// plot_objects.png; an empty image when frames.csv has no row or no `objects` column.
cv::Mat objectsPlot(const CsvColumns& frames);
/// plot_tracking.png; an empty image when frames.csv has no row.
cv::Mat trackingPlot(const CsvColumns& frames, const io::Trajectory& estimate,
                     const io::Trajectory& groundtruth);
/// plot_timing.png; `stages`: the Mapper's stage timers in order (Mapper::stageTimerNames). An
/// empty image when frames.csv has no ms_total column or no row.
cv::Mat timingPlot(const CsvColumns& frames, const std::vector<std::string>& stages);
/// exploration.png: coverage (blue) and objects correct (red) against simulated time; an empty
/// image with fewer than two rows.
cv::Mat explorationPlot(const std::vector<autonomy::ExplorationMetricsRow>& metrics);

}  // namespace rasm::run
