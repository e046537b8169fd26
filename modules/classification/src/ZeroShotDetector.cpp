// The zero-shot classifier at runtime (paper IV-A): Edge Boxes proposals, 16 x 16 HOG, cosine
// similarity against the template bank. Choices and formulas: ZeroShotDetector.h.
#include "rasm/classification/ZeroShotDetector.h"

#include <mrpt/config/CConfigFileBase.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/edgeboxes.hpp>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/core/Timing.h"

namespace rasm::classification {

void TZeroShotParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                         const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(enabled, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(bank, string, c, s);
  MRPT_LOAD_CONFIG_VAR(models, string, c, s);
  MRPT_LOAD_CONFIG_VAR(similarity_threshold, double, c, s);
  MRPT_LOAD_CONFIG_VAR(score_at_threshold, double, c, s);
  MRPT_LOAD_CONFIG_VAR(score_at_one, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_proposals, int, c, s);
  MRPT_LOAD_CONFIG_VAR(proposal_scale, double, c, s);
  MRPT_LOAD_CONFIG_VAR(edge_smoothing_sigma_px, double, c, s);
  MRPT_LOAD_CONFIG_VAR(edge_contrast, double, c, s);
  MRPT_LOAD_CONFIG_VAR(edge_nms_min_gradient, double, c, s);
  MRPT_LOAD_CONFIG_VAR(edge_boxes_alpha, double, c, s);
  MRPT_LOAD_CONFIG_VAR(edge_boxes_beta, double, c, s);
  MRPT_LOAD_CONFIG_VAR(edge_boxes_min_score, double, c, s);
  MRPT_LOAD_CONFIG_VAR(edge_boxes_max_aspect_ratio, double, c, s);
  MRPT_LOAD_CONFIG_VAR(min_box_px, int, c, s);
  MRPT_LOAD_CONFIG_VAR(max_aspect_mismatch, double, c, s);
  MRPT_LOAD_CONFIG_VAR(nms_iou, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_detections, int, c, s);
  requireInRange(similarity_threshold, 0.0, 1.0, s, "similarity_threshold");
  requireInRange(score_at_threshold, 0.0, 1.0, s, "score_at_threshold");
  requireInRange(score_at_one, score_at_threshold, 1.0, s, "score_at_one");
  requireInRange(max_proposals, 1, 100000, s, "max_proposals");
  requireInRange(proposal_scale, 0.1, 1.0, s, "proposal_scale");
  requireInRange(edge_smoothing_sigma_px, 0.0, 10.0, s, "edge_smoothing_sigma_px");
  requireInRange(edge_contrast, 1.0, 2000.0, s, "edge_contrast");
  requireInRange(edge_nms_min_gradient, 0.0, 1000.0, s, "edge_nms_min_gradient");
  requireInRange(edge_boxes_alpha, 0.05, 0.99, s, "edge_boxes_alpha");
  requireInRange(edge_boxes_beta, 0.05, 1.0, s, "edge_boxes_beta");
  requireInRange(edge_boxes_min_score, 0.0, 1.0, s, "edge_boxes_min_score");
  requireInRange(edge_boxes_max_aspect_ratio, 1.0, 20.0, s, "edge_boxes_max_aspect_ratio");
  requireInRange(min_box_px, 4, 10000, s, "min_box_px");
  requireInRange(max_aspect_mismatch, 1.0, 1e6, s, "max_aspect_mismatch");
  requireInRange(nms_iou, 0.0, 1.0, s, "nms_iou");
  requireInRange(max_detections, 1, 100000, s, "max_detections");
  if (enabled && bank.empty() && models.empty())
    throwInputError("[" + s + "] bank", "empty and [" + s + "] models is empty; set one of them");
}

void TZeroShotParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                       const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(enabled, c, s);
  MRPT_SAVE_CONFIG_VAR(bank, c, s);
  MRPT_SAVE_CONFIG_VAR(models, c, s);
  MRPT_SAVE_CONFIG_VAR(similarity_threshold, c, s);
  MRPT_SAVE_CONFIG_VAR(score_at_threshold, c, s);
  MRPT_SAVE_CONFIG_VAR(score_at_one, c, s);
  MRPT_SAVE_CONFIG_VAR(max_proposals, c, s);
  MRPT_SAVE_CONFIG_VAR(proposal_scale, c, s);
  MRPT_SAVE_CONFIG_VAR(edge_smoothing_sigma_px, c, s);
  MRPT_SAVE_CONFIG_VAR(edge_contrast, c, s);
  MRPT_SAVE_CONFIG_VAR(edge_nms_min_gradient, c, s);
  MRPT_SAVE_CONFIG_VAR(edge_boxes_alpha, c, s);
  MRPT_SAVE_CONFIG_VAR(edge_boxes_beta, c, s);
  MRPT_SAVE_CONFIG_VAR(edge_boxes_min_score, c, s);
  MRPT_SAVE_CONFIG_VAR(edge_boxes_max_aspect_ratio, c, s);
  MRPT_SAVE_CONFIG_VAR(min_box_px, c, s);
  MRPT_SAVE_CONFIG_VAR(max_aspect_mismatch, c, s);
  MRPT_SAVE_CONFIG_VAR(nms_iou, c, s);
  MRPT_SAVE_CONFIG_VAR(max_detections, c, s);
}

std::string resolveModelsPath(const std::string& models, const std::string& section) {
  namespace fs = std::filesystem;
  if (fs::is_regular_file(models)) return models;
  const fs::path shipped = fs::path(shippedModelsDir()) / (models + ".yaml");
  if (models.find('/') == std::string::npos && fs::is_regular_file(shipped))
    return shipped.string();
  throwInputError("[" + section + "] models",
                  "file '" + models + "' not found (nor shipped as " + shipped.string() + ")");
}

ZeroShotDetector::ZeroShotDetector(TemplateBank bank, const TZeroShotParams& params,
                                   std::string name)
    : m_bank(std::move(bank)), m_params(params), m_name(std::move(name)) {
  if (m_bank.size() == 0 || m_bank.descriptors.rows != int(m_bank.size()))
    throwInputError("zero-shot detector '" + m_name + "'", "empty template bank");
  for (int m = 0; m < int(m_bank.model_sources.size()); ++m)
    m_azimuth_period_deg.push_back(modelAzimuthPeriodDeg(m_bank, m));
}

std::unique_ptr<ZeroShotDetector> ZeroShotDetector::fromParams(const TZeroShotParams& params,
                                                               const std::string& name) {
  if (!params.bank.empty() && std::filesystem::exists(params.bank))
    return std::make_unique<ZeroShotDetector>(loadTemplateBank(params.bank), params, name);
  if (params.models.empty())
    throwInputError("[" + name + "] bank",
                    params.bank.empty() ? "empty and [" + name + "] models is empty"
                                        : "file '" + params.bank + "' not found and [" + name +
                                              "] models is empty (train it: rasm zsc train)");
  TemplateBank bank = trainTemplateBank(loadModelsSpec(resolveModelsPath(params.models, name)));
  if (!params.bank.empty()) saveTemplateBank(bank, params.bank);
  return std::make_unique<ZeroShotDetector>(std::move(bank), params, name);
}

void ZeroShotDetector::edgeMaps(const cv::Mat& bgr, cv::Mat& edges, cv::Mat& orientation) const {
  CV_Assert(bgr.type() == CV_8UC3);
  const double scale = m_params.proposal_scale;
  cv::Mat image = bgr;
  if (scale < 1.0) cv::resize(bgr, image, {}, scale, scale, cv::INTER_AREA);
  const double sigma = m_params.edge_smoothing_sigma_px * scale;
  if (sigma > 0.05) cv::GaussianBlur(image, image, {0, 0}, sigma);
  cv::Mat dx, dy, thin;
  cv::Sobel(image, dx, CV_16S, 1, 0, 3);
  cv::Sobel(image, dy, CV_16S, 0, 1, 3);
  // Canny on the given derivatives: its non-maximum suppression thins the edges; equal thresholds
  // switch hysteresis off (Edge Boxes wants every ridge with its strength, not a binary contour).
  const double t = m_params.edge_nms_min_gradient;
  cv::Canny(dx, dy, thin, t, t, true);
  edges.create(image.size(), CV_32F);
  orientation.create(image.size(), CV_32F);
  const float inv_contrast = float(1.0 / m_params.edge_contrast);
  for (int y = 0; y < image.rows; ++y) {
    const cv::Vec3s* gx = dx.ptr<cv::Vec3s>(y);
    const cv::Vec3s* gy = dy.ptr<cv::Vec3s>(y);
    const std::uint8_t* keep = thin.ptr<std::uint8_t>(y);
    float* e = edges.ptr<float>(y);
    float* o = orientation.ptr<float>(y);
    for (int x = 0; x < image.cols; ++x) {
      int best = 0, best_m2 = -1;  // the channel of largest gradient, as HOG and Canny use
      for (int ch = 0; ch < 3; ++ch) {
        const int m2 = int(gx[x][ch]) * gx[x][ch] + int(gy[x][ch]) * gy[x][ch];
        if (m2 > best_m2) best_m2 = m2, best = ch;
      }
      const float mag = std::sqrt(float(best_m2));
      e[x] = keep[x] ? 1.f - std::exp(-mag * inv_contrast) : 0.f;
      float a = std::atan2(float(gy[x][best]), float(gx[x][best]));  // gradient = edge normal
      if (a < 0.f) a += float(M_PI);
      o[x] = a >= float(M_PI) ? 0.f : a;
    }
  }
}

std::vector<cv::Rect> ZeroShotDetector::proposals(const cv::Mat& bgr, int max_boxes) const {
  cv::Mat edges, orientation;
  edgeMaps(bgr, edges, orientation);
  const double scale = m_params.proposal_scale;
  const double min_side = m_params.min_box_px * scale;
  auto eb = cv::ximgproc::createEdgeBoxes(
      float(m_params.edge_boxes_alpha), float(m_params.edge_boxes_beta), 1.f,
      float(m_params.edge_boxes_min_score), max_boxes > 0 ? max_boxes : m_params.max_proposals,
      0.1f, 0.5f, 0.5f, float(m_params.edge_boxes_max_aspect_ratio), float(min_side * min_side),
      2.f, 1.5f);
  std::vector<cv::Rect> boxes;
  eb->getBoundingBoxes(edges, orientation, boxes);
  const cv::Rect image(0, 0, bgr.cols, bgr.rows);
  for (cv::Rect& b : boxes) {
    b = cv::Rect(
            cv::Point(int(std::lround(b.x / scale)), int(std::lround(b.y / scale))),
            cv::Point(int(std::lround(b.br().x / scale)), int(std::lround(b.br().y / scale)))) &
        image;
  }
  return boxes;
}

namespace {

/// Image pyramid (halving) so that every proposal is cropped from the level where its square is
/// 32..64 px: the area-averaging down to 16 px then reads at most 64 x 64 pixels per proposal.
std::vector<cv::Mat> cropPyramid(const cv::Mat& bgr) {
  std::vector<cv::Mat> levels{bgr};
  while (std::min(levels.back().cols, levels.back().rows) >= 4 * kTemplatePx) {
    cv::Mat next;
    cv::pyrDown(levels.back(), next);
    levels.push_back(next);
  }
  return levels;
}

cv::Mat proposalPatch(const std::vector<cv::Mat>& levels, const cv::Rect& box) {
  const double side = std::max(box.width, box.height) * double(kTemplatePx) / kTemplateObjectPx;
  int level = 0;
  while (level + 1 < int(levels.size()) && side / double(2 << level) >= 2.0 * kTemplatePx) ++level;
  const double f = 1.0 / double(1 << level);
  const cv::Rect scaled(
      cv::Point(int(std::lround(box.x * f)), int(std::lround(box.y * f))),
      cv::Point(int(std::lround(box.br().x * f)), int(std::lround(box.br().y * f))));
  return squareCropWithMargin(levels[level], scaled);
}

/// IV-A matching: cosine similarity (dot product of L2-normalised descriptors) of one proposal
/// with every template, keeping the best template per class. Templates whose outline's aspect
/// (width / height) differs from the box's by more than the factor `max_aspect_mismatch` are
/// skipped. A plain loop the compiler vectorises (omp simd reduction over the descriptor).
void bestPerClass(const float* descriptor, const TemplateBank& bank, float max_aspect_mismatch,
                  ProposalMatch& m) {
  const int dim = bank.descriptors.cols;
  const float box_aspect = float(m.box.width) / float(std::max(1, m.box.height));
  for (int t = 0; t < bank.descriptors.rows; ++t) {
    const float r = box_aspect / bank.templates[t].aspect;
    if (r > max_aspect_mismatch || r * max_aspect_mismatch < 1.f) continue;
    const float* tmpl = bank.descriptors.ptr<float>(t);
    float s = 0.f;
#pragma omp simd reduction(+ : s)
    for (int k = 0; k < dim; ++k) s += descriptor[k] * tmpl[k];
    const int c = bank.templates[t].class_index;
    if (s > m.best_similarity[c]) m.best_similarity[c] = s, m.best_template[c] = t;
  }
}

}  // namespace

std::vector<ProposalMatch> ZeroShotDetector::match(const cv::Mat& bgr,
                                                   const std::vector<cv::Rect>& boxes) const {
  const std::vector<cv::Mat> levels = cropPyramid(bgr);
  std::vector<float> descriptor(descriptorLength());
  const int n_classes = int(m_bank.class_names.size());
  std::vector<ProposalMatch> out(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    ProposalMatch& m = out[i];
    m.box = boxes[i];
    m.best_similarity.assign(n_classes, -1.f);
    m.best_template.assign(n_classes, -1);
    describePatch(proposalPatch(levels, boxes[i]), descriptor.data());
    bestPerClass(descriptor.data(), m_bank, float(m_params.max_aspect_mismatch), m);
  }
  return out;
}

std::vector<Detection> ZeroShotDetector::detectionsFrom(
    const std::vector<ProposalMatch>& matches) const {
  const float threshold = float(m_params.similarity_threshold);
  const float lo = float(m_params.score_at_threshold), hi = float(m_params.score_at_one);
  std::vector<Detection> detections;
  for (const ProposalMatch& m : matches) {
    Detection d;
    d.box = cv::Rect2f(m.box);
    for (int c = 0; c < int(m.best_similarity.size()); ++c) {
      const float s = m.best_similarity[c];
      if (s < threshold) continue;  // IV-A: forwarded only when the match passes the threshold
      const float f = threshold < 1.f ? (s - threshold) / (1.f - threshold) : 1.f;
      d.scores.push_back({c, lo + (hi - lo) * std::min(1.f, f)});
    }
    if (d.scores.empty()) continue;
    std::stable_sort(d.scores.begin(), d.scores.end(),
                     [](const ClassScore& a, const ClassScore& b) { return a.score > b.score; });
    const int t = m.best_template[d.bestIndex()];
    const TemplateInfo& info = m_bank.templates[t];
    const int model = info.model_index;
    d.pose = {true, info.azimuth_deg, info.elevation_deg, t,
              model >= 0 && model < int(m_azimuth_period_deg.size())
                  ? m_azimuth_period_deg[std::size_t(model)]
                  : 360.f};
    detections.push_back(std::move(d));
  }
  detections = suppressPerClass(std::move(detections), 0.f, float(m_params.nms_iou));
  if (int(detections.size()) > m_params.max_detections) detections.resize(m_params.max_detections);
  return detections;
}

std::vector<Detection> ZeroShotDetector::detect(const DetectorInput& input) {
  if (input.bgr.type() != CV_8UC3 || input.bgr.empty())
    throwInputError(
        "zero-shot detector '" + m_name + "'",
        "expects an 8-bit BGR image (CV_8UC3), got type " + std::to_string(input.bgr.type()));
  const Clock::time_point t0 = Clock::now();
  std::vector<cv::Rect> boxes = proposals(input.bgr);
  const int min_px = m_params.min_box_px;
  boxes.erase(
      std::remove_if(boxes.begin(), boxes.end(),
                     [&](const cv::Rect& b) { return b.width < min_px || b.height < min_px; }),
      boxes.end());
  m_proposal_ms = msSince(t0);
  const Clock::time_point t1 = Clock::now();
  std::vector<Detection> detections = detectionsFrom(match(input.bgr, boxes));
  m_match_ms = msSince(t1);
  return detections;
}

}  // namespace rasm::classification
