#include "rasm/classification/ClassFusion.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <unordered_map>

#include "rasm/surfel_map/ClassEvidence.h"

namespace rasm::classification {

namespace {

struct PixelBox {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< [x0, x1) x [y0, y1)
  int area() const { return std::max(0, x1 - x0) * std::max(0, y1 - y0); }
};

PixelBox clipBox(const cv::Rect2f& b, int width, int height) {
  PixelBox p;
  p.x0 = std::clamp(int(std::lround(b.x)), 0, width);
  p.y0 = std::clamp(int(std::lround(b.y)), 0, height);
  p.x1 = std::clamp(int(std::lround(b.x + b.width)), 0, width);
  p.y1 = std::clamp(int(std::lround(b.y + b.height)), 0, height);
  return p;
}

}  // namespace

std::vector<Association> associateDetections(const Image<std::uint32_t>& labels,
                                             const std::vector<Detection>& detections,
                                             float min_iou, float piece_min_inside_fraction) {
  std::vector<Association> out(detections.size());
  if (labels.empty() || detections.empty()) return out;
  const int w = labels.width(), h = labels.height();
  std::unordered_map<std::uint32_t, int> segment_pixels;  // |l|
  for (int y = 0; y < h; ++y) {
    const std::uint32_t* row = labels.row(y);
    for (int x = 0; x < w; ++x)
      if (row[x] != 0) ++segment_pixels[row[x]];
  }
  for (std::size_t d = 0; d < detections.size(); ++d) {
    const PixelBox box = clipBox(detections[d].box, w, h);
    if (box.area() == 0) continue;
    std::unordered_map<std::uint32_t, int> inter;  // I(l, d)
    for (int y = box.y0; y < box.y1; ++y) {
      const std::uint32_t* row = labels.row(y);
      for (int x = box.x0; x < box.x1; ++x)
        if (row[x] != 0) ++inter[row[x]];
    }
    Association best;
    for (const auto& [l, i] : inter) {
      const int u = segment_pixels[l] + box.area() - i;  // U(l, d)
      const float iou = float(i) / float(u);
      if (iou > best.iou || (iou == best.iou && l < best.segment)) best = Association{l, iou, i, u};
    }
    if (best.iou < min_iou) continue;
    out[d] = best;
    if (piece_min_inside_fraction > 0.f && piece_min_inside_fraction <= 1.f)
      for (const auto& [l, i] : inter)
        if (l != best.segment && float(i) >= piece_min_inside_fraction * float(segment_pixels[l]))
          out[d].pieces.push_back(l);
    std::sort(out[d].pieces.begin(), out[d].pieces.end());
  }
  return out;
}

float detectionProbability(float score, ScoreModel model, float max_p, float s0) {
  if (!(score == score)) return 0.5f;
  score = std::clamp(score, 0.f, 1.f);
  s0 = std::clamp(s0, 0.f, 0.99f);
  const float p =
      model == ScoreModel::Vote ? 0.5f + 0.5f * std::max(0.f, score - s0) / (1.f - s0) : score;
  const float hi = std::clamp(max_p, 0.5f, 1.f);
  return std::clamp(p, 1.f - hi, hi);
}

int evidenceLogitUnits(const SegmentEvidence& e) {
  return maps::quantizeClassLogit(e.weight * maps::probabilityLogit(e.p_detection));
}

FusionCounts fuseSegmentEvidence(const maps::SurfelArrays& a,
                                 const std::vector<SegmentEvidence>& evidence) {
  FusionCounts counts;
  if (evidence.empty() || a.n_classes == 0 || a.size == 0) return counts;
  // Evidence items grouped by segment: first[l] .. first[l + 1] in `items`.
  std::uint32_t top = 0;
  for (const SegmentEvidence& e : evidence) top = std::max(top, e.segment);
  std::vector<SegmentEvidence> items(evidence);
  std::stable_sort(items.begin(), items.end(),
                   [](const auto& x, const auto& y) { return x.segment < y.segment; });
  std::vector<int> first(std::size_t(top) + 2, 0);
  for (const SegmentEvidence& e : items) ++first[e.segment + 1];
  for (std::size_t l = 1; l < first.size(); ++l) first[l] += first[l - 1];
  std::vector<int> units(items.size());
  for (std::size_t k = 0; k < items.size(); ++k) units[k] = evidenceLogitUnits(items[k]);

  long long updated = 0, dropped = 0;
#pragma omp parallel for schedule(static) reduction(+ : updated, dropped)
  for (int i = 0; i < a.size; ++i) {
    const std::uint32_t l = a.segment[i];
    if (l == 0 || l > top || !a.alive(i)) continue;
    for (int k = first[l]; k < first[l + 1]; ++k) {
      if (items[k].class_id <= 0 || items[k].class_id > a.n_classes) continue;
      const auto r = maps::classEvidenceAdd(a.class_ev[i], items[k].class_id, units[k]);
      ++updated;
      dropped += r == maps::kClassDropped;
    }
  }
  counts.surfels = std::size_t(updated);
  counts.dropped = std::size_t(dropped);
  return counts;
}

FusionCounts fuseSurfelListEvidence(const maps::SurfelArrays& a,
                                    const std::vector<std::int32_t>& indices,
                                    const std::vector<SegmentEvidence>& evidence) {
  FusionCounts counts;
  if (evidence.empty() || a.n_classes == 0) return counts;
  for (const std::int32_t i : indices) {
    if (i < 0 || i >= a.size || !a.alive(i)) continue;
    for (const SegmentEvidence& e : evidence) {
      if (e.class_id <= 0 || e.class_id > a.n_classes) continue;
      const auto r = maps::classEvidenceAdd(a.class_ev[i], e.class_id, evidenceLogitUnits(e));
      ++counts.surfels;
      counts.dropped += r == maps::kClassDropped;
    }
  }
  return counts;
}

std::vector<SegmentClass> segmentClasses(const maps::SurfelArrays& a) {
  // Per segment: surfel count and, per class with evidence, the sum of (p - 0.5) over the
  // surfels that hold it; the mean posterior is 0.5 + sum / count.
  std::map<std::uint32_t, std::pair<int, std::map<int, double>>> acc;
  for (int i = 0; i < a.size; ++i) {
    if (!a.alive(i) || a.segment[i] == 0) continue;
    auto& [count, sums] = acc[a.segment[i]];
    ++count;
    if (a.n_classes == 0) continue;
    const maps::ClassEvidence& e = a.class_ev[i];
    for (int k = 0; k < maps::kClassSlots; ++k)
      if (e.id[k] != 0)
        sums[e.id[k]] +=
            double(maps::logitProbability(maps::dequantizeClassLogit(e.logit[k]))) - 0.5;
  }
  std::vector<SegmentClass> out;
  out.reserve(acc.size());
  for (const auto& [segment, cs] : acc) {
    SegmentClass c;
    c.segment = segment;
    c.surfels = cs.first;
    for (const auto& [id, sum] : cs.second) {
      const float p = float(0.5 + sum / cs.first);
      if (p <= 0.5f) continue;
      if (p > c.best_p || (p == c.best_p && id < c.best_id)) {
        c.runner_up_id = c.best_id;
        c.runner_up_p = c.best_p;
        c.best_id = id;
        c.best_p = p;
      } else if (p > c.runner_up_p || (p == c.runner_up_p && id < c.runner_up_id)) {
        c.runner_up_id = id;
        c.runner_up_p = p;
      }
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace rasm::classification
