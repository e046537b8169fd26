#include "rasm/classification/TObjectParams.h"

#include <mrpt/config/CConfigFileBase.h>

#include "rasm/core/Params.h"

namespace rasm::classification {

void TObjectParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                       const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(link_min_probability, double, c, s);
  MRPT_LOAD_CONFIG_VAR(link_max_gap_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(link_min_codetection_fraction, double, c, s);
  MRPT_LOAD_CONFIG_VAR(link_min_box_containment, double, c, s);
  MRPT_LOAD_CONFIG_VAR(piece_min_inside_fraction, double, c, s);
  MRPT_LOAD_CONFIG_VAR(min_view_pixels, int, c, s);
  MRPT_LOAD_CONFIG_VAR(min_existence_probability, double, c, s);
  requireInRange(link_min_probability, 0.5, 1.0, s, "link_min_probability");
  requireInRange(link_max_gap_m, 0.0, 10.0, s, "link_max_gap_m");
  requireInRange(link_min_codetection_fraction, 0.0, 1.0, s, "link_min_codetection_fraction");
  requireInRange(link_min_box_containment, 0.0, 1.0, s, "link_min_box_containment");
  requireInRange(piece_min_inside_fraction, 0.0, 1.0, s, "piece_min_inside_fraction");
  requireInRange(min_view_pixels, 1, 100000000, s, "min_view_pixels");
  requireInRange(min_existence_probability, 0.0, 1.0, s, "min_existence_probability");
}

void TObjectParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  c.write(s, "link_min_probability", link_min_probability, -1, -1,
          "segments of one class join one object when each has this probability");
  c.write(s, "link_max_gap_m", link_max_gap_m, -1, -1,
          "... and their boxes are at most this far apart on every axis");
  c.write(s, "link_min_codetection_fraction", link_min_codetection_fraction, -1, -1,
          "... and this fraction of the detections of the less detected held both (0: contact)");
  c.write(s, "link_min_box_containment", link_min_box_containment, -1, -1,
          "... or the smaller one's box lies this fraction inside the other's (0: off)");
  c.write(s, "piece_min_inside_fraction", piece_min_inside_fraction, -1, -1,
          "a segment is in a detection's box when this fraction of its pixels is");
  c.write(s, "min_view_pixels", min_view_pixels, -1, -1,
          "pixels of a detected frame's L^p that make it a view of a segment");
  c.write(s, "min_existence_probability", min_existence_probability, -1, -1,
          "objects.json: (views detected + 1) / (views + 2) needed to report an object");
}

}  // namespace rasm::classification
