#pragma once
// classes_legend.png, the key to map_classes.ply / .3Dscene and preview_classes.png, which the
// classification stage writes with its other files: one row per class (a swatch of its colour at
// probability 1, its name, the surfels whose best class it is), with a grey "none" row and a note
// that colours fade to that grey as the probability falls to the 0.5 prior. Drawn as the floor
// plan draws its legend (run/FloorPlan.h), with the same fonts and colours.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace rasm::pipeline {

struct ClassLegendEntry {
  int class_id = 0;
  std::string name;
  long long surfels = 0;
};

/// The legend image (BGR); rows in the order given.
cv::Mat classLegendImage(const std::vector<ClassLegendEntry>& entries);

}  // namespace rasm::pipeline
