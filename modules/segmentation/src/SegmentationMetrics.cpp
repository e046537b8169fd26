#include "rasm/segmentation/SegmentationMetrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <unordered_map>
#include <utility>

namespace rasm::segmentation {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Overlap {
  std::uint32_t id;  ///< the other side (segment for an instance's list, instance for a segment's)
  std::size_t count;
};

using CountById = std::unordered_map<std::uint32_t, std::size_t>;
using OverlapLists = std::map<std::uint32_t, std::vector<Overlap>>;

std::size_t countOf(const CountById& c, std::uint32_t id) {
  const auto it = c.find(id);
  return it == c.end() ? 0 : it->second;
}

/// The largest overlap of `v` whose id is not `exclude` (ties: the first, the lower id).
Overlap argmax(const std::vector<Overlap>& v, std::uint32_t exclude) {
  Overlap best{0, 0};
  for (const Overlap& o : v)
    if (o.id != exclude && o.count > best.count) best = o;
  return best;
}

void checkInputs(const std::vector<std::uint32_t>& segment,
                 const std::vector<std::uint32_t>& instance,
                 const std::vector<std::uint8_t>& stable, const std::vector<GtObject>& objects,
                 const SegmentationMetricsParams& params) {
  if (segment.size() != instance.size())
    throw std::invalid_argument("computeSegmentationMetrics: " + std::to_string(segment.size()) +
                                " segment ids but " + std::to_string(instance.size()) +
                                " instance ids (one of each per surfel expected)");
  if (!stable.empty() && stable.size() != segment.size())
    throw std::invalid_argument("computeSegmentationMetrics: " + std::to_string(stable.size()) +
                                " stable flags for " + std::to_string(segment.size()) +
                                " surfels (none or one per surfel expected)");
  if (params.stable_only && stable.empty())
    throw std::invalid_argument("computeSegmentationMetrics: stable_only needs the stable flags");
  if (!(params.iou_threshold >= 0.5 && params.iou_threshold < 1.0))
    throw std::invalid_argument(
        "computeSegmentationMetrics: iou_threshold in [0.5, 1) expected (unique matches)");
  if (!(params.min_object_size_m >= 0.0) || !(params.undersegment_ratio > 0.0) ||
      !(params.undersegment_min_share > 0.0 && params.undersegment_min_share <= 1.0))
    throw std::invalid_argument(
        "computeSegmentationMetrics: min_object_size_m >= 0, undersegment_ratio > 0 and "
        "undersegment_min_share in (0, 1] expected");
  std::unordered_map<std::uint32_t, bool> listed;
  for (const GtObject& o : objects) {
    if (o.instance_id == 0)
      throw std::invalid_argument("computeSegmentationMetrics: object instance id 0 (void)");
    if (!listed.emplace(o.instance_id, true).second)
      throw std::invalid_argument("computeSegmentationMetrics: object instance " +
                                  std::to_string(o.instance_id) + " listed twice");
  }
}

/// Surfel counts over the surfels used: per instance, per segment, per instance unsegmented, and
/// per (segment, instance) pair as overlap lists sorted by id (ties of the arg-max rules go to
/// the lower id).
struct SurfelCounts {
  CountById per_instance, per_segment, unsegmented;
  OverlapLists by_segment, by_instance;
};

SurfelCounts countSurfels(const std::vector<std::uint32_t>& segment,
                          const std::vector<std::uint32_t>& instance,
                          const std::vector<std::uint8_t>& stable,
                          const SegmentationMetricsParams& params, SegmentationMetrics& m) {
  SurfelCounts c;
  std::unordered_map<std::uint64_t, std::size_t> inter;  // (s << 32 | g), s > 0, g > 0
  std::unordered_map<std::uint32_t, bool> seen_segment;
  for (std::size_t i = 0; i < segment.size(); ++i) {
    if (params.stable_only && !stable[i]) continue;
    ++m.surfels;
    const std::uint32_t s = segment[i], g = instance[i];
    if (s > 0) {
      ++m.segmented_surfels;
      seen_segment[s] = true;
    }
    if (g == 0) {
      ++m.void_surfels;
      continue;
    }
    ++c.per_instance[g];
    if (s == 0) {
      ++c.unsegmented[g];
      continue;
    }
    ++c.per_segment[s];
    ++inter[(std::uint64_t(s) << 32) | g];
  }
  if (m.surfels == 0)
    throw std::invalid_argument(params.stable_only ? "computeSegmentationMetrics: no stable surfels"
                                                   : "computeSegmentationMetrics: no surfels");
  m.segments = seen_segment.size();
  std::vector<std::pair<std::uint64_t, std::size_t>> pairs(inter.begin(), inter.end());
  std::sort(pairs.begin(), pairs.end());
  for (const auto& [key, n] : pairs) {
    const auto s = std::uint32_t(key >> 32), g = std::uint32_t(key & 0xffffffffu);
    c.by_segment[s].push_back({g, n});
    c.by_instance[g].push_back({s, n});
  }
  return c;
}

/// An object's best segment by IoU, its dominant segment and whether it is under-segmented
/// (a segment holding a large enough share of it holds as much of another object).
void matchObject(ObjectResult& r, const std::vector<Overlap>& overlaps, const SurfelCounts& c,
                 const SegmentationMetricsParams& params) {
  const std::uint32_t g = r.object.instance_id;
  for (const Overlap& o : overlaps) {
    const double iou = double(o.count) / double(countOf(c.per_segment, o.id) + r.surfels - o.count);
    if (iou > r.iou) {
      r.iou = iou;
      r.best_segment = o.id;
    }
  }
  r.dominant_segment = argmax(overlaps, 0).id;
  // Under-segmentation: the segments holding a large enough share of g, largest first.
  std::vector<Overlap> shares;
  for (const Overlap& o : overlaps)
    if (double(o.count) >= params.undersegment_min_share * double(r.surfels)) shares.push_back(o);
  std::stable_sort(shares.begin(), shares.end(),
                   [](const Overlap& a, const Overlap& b) { return a.count > b.count; });
  for (const Overlap& o : shares) {
    const Overlap other = argmax(c.by_segment.at(o.id), g);
    if (other.count > 0 && double(other.count) >= params.undersegment_ratio * double(o.count)) {
      r.undersegmented = true;
      r.merged_with = other.id;
      break;
    }
  }
}

/// The panoptic scores and per-object summaries once every row is matched.
void finishScores(SegmentationMetrics& m, double iou_sum) {
  m.tp = m.recovered;
  m.fn = m.objects_evaluated - m.recovered;
  if (m.objects_evaluated == 0) {
    m.objects_recovered_fraction = m.sq = m.rq = m.pq = kNaN;
    m.segments_per_object = m.undersegmented_fraction = kNaN;
    return;
  }
  const double n = double(m.objects_evaluated);
  m.objects_recovered_fraction = double(m.recovered) / n;
  m.sq = m.tp > 0 ? iou_sum / double(m.tp) : 0.0;
  m.rq = double(m.tp) / (double(m.tp) + 0.5 * double(m.fp) + 0.5 * double(m.fn));
  m.pq = m.sq * m.rq;
  m.undersegmented_fraction = double(m.undersegmented_objects) / n;
  std::size_t owners = 0, owned = 0;
  for (const ObjectResult& r : m.per_object) {
    if (!r.evaluated) continue;
    if (r.owned_segments > 0) {
      ++owners;
      owned += r.owned_segments;
    } else {
      ++m.objects_without_segment;
    }
  }
  m.segments_per_object = owners > 0 ? double(owned) / double(owners) : kNaN;
}

}  // namespace

SegmentationMetrics computeSegmentationMetrics(const std::vector<std::uint32_t>& segment,
                                               const std::vector<std::uint32_t>& instance,
                                               const std::vector<std::uint8_t>& stable,
                                               const std::vector<GtObject>& objects,
                                               const SegmentationMetricsParams& params) {
  checkInputs(segment, instance, stable, objects, params);
  SegmentationMetrics m;
  m.objects_listed = objects.size();
  const SurfelCounts c = countSurfels(segment, instance, stable, params, m);

  // Rows and the evaluated set.
  std::unordered_map<std::uint32_t, std::size_t> row_of;  // instance -> index into per_object
  for (const GtObject& o : objects) {
    if (!(o.size_m > params.min_object_size_m)) continue;
    ++m.objects_over_size;
    ObjectResult r;
    r.object = o;
    r.surfels = countOf(c.per_instance, o.instance_id);
    r.unsegmented = countOf(c.unsegmented, o.instance_id);
    r.evaluated = r.surfels > 0 && r.surfels >= params.min_object_surfels;
    if (r.evaluated)
      ++m.objects_evaluated;
    else
      ++m.objects_unseen;
    row_of[o.instance_id] = m.per_object.size();
    m.per_object.push_back(std::move(r));
  }

  // Best segment by IoU, matches, dominant segment and under-segmentation per object.
  std::unordered_map<std::uint32_t, bool> matched_segment;
  double iou_sum = 0.0;
  for (ObjectResult& r : m.per_object) {
    const auto it = c.by_instance.find(r.object.instance_id);
    if (it == c.by_instance.end()) continue;
    matchObject(r, it->second, c, params);
    if (!r.evaluated) continue;
    if (r.iou > params.iou_threshold) {
      r.recovered = true;
      ++m.recovered;
      iou_sum += r.iou;
      matched_segment[r.best_segment] = true;
    }
    if (r.undersegmented) ++m.undersegmented_objects;
  }

  // Segment side: owners (majority instance) and false positives.
  for (const auto& [s, list] : c.by_segment) {
    const Overlap major = argmax(list, 0);
    const auto row = row_of.find(major.id);
    if (row == row_of.end()) continue;
    ObjectResult& r = m.per_object[row->second];
    // Owned by a non-evaluated instance: still counted in that row, never a false positive.
    ++r.owned_segments;
    if (r.evaluated && !matched_segment.count(s)) ++m.fp;
  }
  finishScores(m, iou_sum);
  return m;
}

double labelChangesPerStableSurfel(std::uint64_t label_changes_stable,
                                   std::uint64_t stable_surfels) {
  if (stable_surfels == 0) return kNaN;
  return double(label_changes_stable) / double(stable_surfels);
}

}  // namespace rasm::segmentation
