#include "rasm/classification/TClassificationParams.h"

#include <mrpt/config/CConfigFileBase.h>

#include <cctype>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

namespace rasm::classification {

std::vector<std::string> TClassificationParams::detectorList() const {
  return splitList(detectors);
}

void TClassificationParams::resolveAuto(bool simulated_source) {
  if (detectors == "auto") detectors = simulated_source ? "sim_detector" : "dnn_detector";
  if (threaded_auto) threaded = !simulated_source;
  threaded_auto = false;
}

ScoreModel TClassificationParams::scoreModel() const {
  return score_model == "vote" ? ScoreModel::Vote : ScoreModel::Probability;
}

void TClassificationParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                               const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(enabled, bool, c, s);
  detectors = c.read_string(s, "detectors", detectors);
  MRPT_LOAD_CONFIG_VAR(every_n_frames, int, c, s);
  {  // a bool as MRPT reads one (true / 1 / yes, false / 0 / no), or auto
    std::string given =
        c.read_string(s, "threaded", threaded_auto ? "auto" : (threaded ? "true" : "false"));
    for (char& ch : given) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    requireOneOf(given, {"true", "1", "yes", "false", "0", "no", "auto"}, s, "threaded");
    threaded_auto = given == "auto";
    if (!threaded_auto) threaded = given == "true" || given == "1" || given == "yes";
  }
  MRPT_LOAD_CONFIG_VAR(min_iou, double, c, s);
  score_model = c.read_string(s, "score_model", score_model);
  MRPT_LOAD_CONFIG_VAR(vote_neutral_score, double, c, s);
  MRPT_LOAD_CONFIG_VAR(iou_weighted_evidence, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(max_detection_probability, double, c, s);
  MRPT_LOAD_CONFIG_VAR(min_object_probability, double, c, s);
  MRPT_LOAD_CONFIG_VAR(min_object_surfels, int, c, s);
  MRPT_LOAD_CONFIG_VAR(min_object_size_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(structure_min_extent_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(structure_max_thickness_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(structure_max_thickness_fraction, double, c, s);
  MRPT_LOAD_CONFIG_VAR(structure_piece_min_extent_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(structure_piece_max_offset_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(pose_consensus, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(pose_agreement_deg, double, c, s);
  MRPT_LOAD_CONFIG_VAR(pose_min_view_change_deg, double, c, s);
  MRPT_LOAD_CONFIG_VAR(pose_max_fraction_of_view_change, double, c, s);
  MRPT_LOAD_CONFIG_VAR(seed, int, c, s);
  requireInRange(pose_agreement_deg, 0.0, 180.0, s, "pose_agreement_deg");
  requireInRange(pose_min_view_change_deg, 0.0, 180.0, s, "pose_min_view_change_deg");
  requireInRange(pose_max_fraction_of_view_change, 0.0, 10.0, s,
                 "pose_max_fraction_of_view_change");
  requireInRange(every_n_frames, 1, 100000, s, "every_n_frames");
  requireInRange(min_iou, 0.0, 1.0, s, "min_iou");
  requireInRange(max_detection_probability, 0.5, 1.0, s, "max_detection_probability");
  requireInRange(vote_neutral_score, 0.0, 0.95, s, "vote_neutral_score");
  requireInRange(min_object_probability, 0.5, 1.0, s, "min_object_probability");
  requireInRange(min_object_surfels, 0, 100000000, s, "min_object_surfels");
  requireInRange(min_object_size_m, 0.0, 100.0, s, "min_object_size_m");
  requireInRange(structure_min_extent_m, 0.0, 1000.0, s, "structure_min_extent_m");
  requireInRange(structure_max_thickness_m, 0.0, 1000.0, s, "structure_max_thickness_m");
  requireInRange(structure_max_thickness_fraction, 0.0, 1.0, s, "structure_max_thickness_fraction");
  requireInRange(structure_piece_min_extent_m, 0.0, 1000.0, s, "structure_piece_min_extent_m");
  requireInRange(structure_piece_max_offset_m, 0.0, 10.0, s, "structure_piece_max_offset_m");
  if (score_model != "probability" && score_model != "vote")
    throwInputError("[" + s + "] score_model = " + score_model, "expected 'probability' or 'vote'");
  for (const std::string& d : detectorList())
    if (detectors != "auto" && d != "sim_detector" && d != "dnn_detector" && d != "zero_shot")
      throwInputError("[" + s + "] detectors = " + detectors,
                      "unknown detector '" + d +
                          "'; expected auto or a list of sim_detector, dnn_detector, zero_shot");
}

void TClassificationParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                             const std::string& s) const {
  c.write(s, "enabled", enabled, -1, -1, "false: no classification stage work");
  c.write(s, "detectors", detectors, -1, -1,
          "auto | comma list of detector sections: sim_detector, dnn_detector, zero_shot");
  c.write(s, "every_n_frames", every_n_frames, -1, -1, "offer every n-th fused frame");
  c.write(s, "threaded",
          threaded_auto ? std::string("auto") : std::string(threaded ? "true" : "false"), -1, -1,
          "detectors on worker threads (false: deterministic; auto: false on the simulator)");
  c.write(s, "min_iou", min_iou, -1, -1, "box / L^p segment IoU needed to fuse a detection");
  c.write(s, "score_model", score_model, -1, -1, "p_d from a score: probability | vote");
  c.write(s, "vote_neutral_score", vote_neutral_score, -1, -1,
          "vote model: scores at or below it carry no evidence");
  c.write(s, "iou_weighted_evidence", iou_weighted_evidence, -1, -1,
          "scale a detection's log-odds by its IoU with the segment");
  c.write(s, "max_detection_probability", max_detection_probability, -1, -1,
          "p_d clamped to [1 - max, max]");
  c.write(s, "min_object_probability", min_object_probability, -1, -1,
          "a segment's class needs this mean posterior");
  c.write(s, "min_object_surfels", min_object_surfels, -1, -1,
          "objects.json: fewer surfels make a fragment, not an object");
  c.write(s, "min_object_size_m", min_object_size_m, -1, -1,
          "objects.json: a smaller largest extent makes a fragment");
  c.write(s, "structure_min_extent_m", structure_min_extent_m, -1, -1,
          "objects.json: a thin plane larger than this both ways is structure");
  c.write(s, "structure_max_thickness_m", structure_max_thickness_m, -1, -1,
          "objects.json: the thickness below which a large plane is structure");
  c.write(s, "structure_max_thickness_fraction", structure_max_thickness_fraction, -1, -1,
          "objects.json: ... or below this fraction of its middle extent");
  c.write(s, "structure_piece_min_extent_m", structure_piece_min_extent_m, -1, -1,
          "objects.json: a thin plane this large both ways in a structure's plane is part of it");
  c.write(s, "structure_piece_max_offset_m", structure_piece_max_offset_m, -1, -1,
          "objects.json: ... within this distance of that plane");
  c.write(s, "pose_consensus", pose_consensus, -1, -1,
          "fuse template-pose detections only when views agree on the object's orientation");
  c.write(s, "pose_agreement_deg", pose_agreement_deg, -1, -1,
          "pose consensus: orientations this close agree (deg)");
  c.write(s, "pose_min_view_change_deg", pose_min_view_change_deg, -1, -1,
          "pose consensus: views at least this far apart (deg) count");
  c.write(s, "pose_max_fraction_of_view_change", pose_max_fraction_of_view_change, -1, -1,
          "pose consensus: orientations at most this fraction of the view change apart agree");
  c.write(s, "seed", seed, -1, -1, "seed of the simulated detector's noise");
}

}  // namespace rasm::classification
