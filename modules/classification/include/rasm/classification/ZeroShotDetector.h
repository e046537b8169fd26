#pragma once
// The zero-shot classifier at runtime (paper IV-A): "Edge Boxes are calculated on the RGB image to
// generate a list of object proposals. After scaling down to 16 x 16 images, HOG descriptors are
// calculated for each object proposal, and matched with the templates using the cosine similarity
// distance to generate a match score." The paper forwards a proposal "if the minimum score is
// below a threshold" (a distance); with the similarity used here that is similarity >= threshold.
//
// Edge map without a downloaded model: OpenCV's Edge Boxes (ximgproc) expects a structured-edge
// probability map and its orientation. Here the edge strength is the colour gradient (Sobel on the
// Gaussian-smoothed image, the channel of largest magnitude per pixel, as HOG does), mapped to
// [0, 1) by 1 - exp(-|g| / edge_contrast); edges are thinned by Canny's non-maximum suppression
// (cv::Canny with both thresholds at edge_nms_min_gradient, i.e. no hysteresis); the orientation is
// the gradient direction modulo pi, which is what StructuredEdgeDetection::computeOrientation
// gives (Edge Boxes compares it with the direction normal to the line joining edge groups).
//
// Addition to the paper: a proposal is compared only with templates whose outline aspect (width /
// height) is within max_aspect_mismatch of the box's (docs/classification-zero-shot.md: higher
// precision and recall in the simulated office); 1e6 restores the paper's matching.
//
// Scores: a detection's score for a class is the best cosine similarity s over that class's
// templates, mapped linearly from [similarity_threshold, 1] to [score_at_threshold, score_at_one]
// (defaults 0.55 .. 0.9: a proposal just at the threshold is weak evidence, and even a perfect
// template match stays below 1 because the paper expects many false positives, VII-A).

#include <mrpt/config/CLoadableOptions.h>

#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "rasm/classification/Detector.h"
#include "rasm/classification/TemplateBank.h"

namespace rasm::classification {

/// INI section [zero_shot] (keys as the member names).
struct TZeroShotParams : public mrpt::config::CLoadableOptions {
  bool enabled = false;
  /// Template bank file (`rasm zsc train`). When it does not exist and `models` is set, the bank
  /// is trained at startup from `models` and saved here (when not empty) for the next run.
  std::string bank;
  /// Models file (TemplateBank.h). A bare name (`office_zero_shot`) is looked up in the shipped
  /// modules/classification/models/<name>.yaml.
  std::string models;
  double similarity_threshold = 0.8;     ///< cosine similarity a match needs (IV-A threshold)
  double score_at_threshold = 0.55;      ///< class score of a match at the threshold
  double score_at_one = 0.9;             ///< class score of a perfect match
  int max_proposals = 500;               ///< Edge Boxes proposals matched per image
  double proposal_scale = 0.5;           ///< image scale the edge map and Edge Boxes run at
  double edge_smoothing_sigma_px = 1.0;  ///< Gaussian before the gradient (full-resolution px)
  double edge_contrast = 60.0;           ///< gradient magnitude (Sobel, 8 bit) mapped to 1 - 1/e
  double edge_nms_min_gradient = 20.0;   ///< weakest gradient kept by the edge thinning
  double edge_boxes_alpha = 0.65;        ///< Edge Boxes sliding-window step (IoU of neighbours)
  double edge_boxes_beta = 0.75;         ///< Edge Boxes NMS IoU among proposals
  double edge_boxes_min_score = 0.01;
  double edge_boxes_max_aspect_ratio = 3.0;
  int min_box_px = 20;  ///< proposals with a shorter side (full resolution) are dropped
  /// A proposal is compared only with templates whose outline aspect (width / height) is within
  /// this factor of the box's (1e6: all templates, as in the paper; 1.6 measured in the office).
  double max_aspect_mismatch = 1.6;
  double nms_iou = 0.3;     ///< per-class NMS of the detections
  int max_detections = 20;  ///< best detections kept per image

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                        const std::string& section) const override;
};

/// Folder of the shipped models files: modules/classification/models, compiled in.
std::string shippedModelsDir();

/// `models` resolved: an existing path as is, a bare name to the shipped models file
/// (<shippedModelsDir>/<name>.yaml). Throws InputError naming [section] models when neither exists.
std::string resolveModelsPath(const std::string& models, const std::string& section = "zero_shot");

/// One proposal's best match per class (similarity; template index or -1).
struct ProposalMatch {
  cv::Rect box;
  std::vector<float> best_similarity;  ///< per class of the bank
  std::vector<int> best_template;
};

class ZeroShotDetector : public Detector {
 public:
  /// Uses `bank` (must not be empty).
  ZeroShotDetector(TemplateBank bank, const TZeroShotParams& params,
                   std::string name = "zero_shot");
  /// Loads or trains the bank as params.bank / params.models say (InputError naming the
  /// [zero_shot] key or the file).
  static std::unique_ptr<ZeroShotDetector> fromParams(const TZeroShotParams& params,
                                                      const std::string& name = "zero_shot");

  std::string name() const override { return m_name; }
  const std::vector<std::string>& classNames() const override { return m_bank.class_names; }
  std::vector<Detection> detect(const DetectorInput& input) override;

  const TemplateBank& bank() const { return m_bank; }
  const TZeroShotParams& params() const { return m_params; }

  /// The stages of detect(), public for tests and the benchmark.
  /// Edge strength in [0, 1) (thinned) and orientation in [0, pi) of a BGR image.
  void edgeMaps(const cv::Mat& bgr, cv::Mat& edges, cv::Mat& orientation) const;
  /// Edge Boxes proposals in full-resolution pixels, best first, at most max_boxes (<= 0: the
  /// params' max_proposals), without the min_box_px filter.
  std::vector<cv::Rect> proposals(const cv::Mat& bgr, int max_boxes = 0) const;
  /// Best template per class for each box (cosine similarity of the HOG descriptors).
  std::vector<ProposalMatch> match(const cv::Mat& bgr, const std::vector<cv::Rect>& boxes) const;
  /// Detections from matches: threshold, scores, pose hint, per-class NMS.
  std::vector<Detection> detectionsFrom(const std::vector<ProposalMatch>& matches) const;

  /// Milliseconds of the stages of the last detect() (edges + proposals, HOG + matching).
  double lastProposalMs() const { return m_proposal_ms; }
  double lastMatchMs() const { return m_match_ms; }

 private:
  TemplateBank m_bank;
  std::vector<float> m_azimuth_period_deg;  ///< per model of the bank (modelAzimuthPeriodDeg)
  TZeroShotParams m_params;
  std::string m_name;
  double m_proposal_ms = 0, m_match_ms = 0;
};

}  // namespace rasm::classification
