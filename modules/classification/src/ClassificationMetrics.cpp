#include "rasm/classification/ClassificationMetrics.h"

#include <cmath>
#include <set>
#include <stdexcept>
#include <unordered_map>

namespace rasm::classification {

double ClassStats::recall() const {
  return objects > 0 ? double(objects_correct) / double(objects) : std::nan("");
}
double ClassStats::precision() const {
  return segments_predicted > 0 ? double(segments_true) / double(segments_predicted) : std::nan("");
}

namespace {

using Counts = std::unordered_map<std::uint32_t, std::size_t>;

/// The key with the largest count (ties to the lower key); 0 when empty.
std::uint32_t argmax(const Counts& c, std::size_t* best_count = nullptr) {
  std::uint32_t best = 0;
  std::size_t n = 0;
  for (const auto& [k, v] : c)
    if (v > n || (v == n && k < best)) {
      best = k;
      n = v;
    }
  if (best_count) *best_count = n;
  return best;
}

/// An evaluated object (header): not structure, larger than min_object_size_m, with at least
/// min_object_surfels surfels in the map.
bool isEvaluated(const GtClassObject& o, std::size_t surfels,
                 const ClassificationMetricsParams& p) {
  return !o.is_structure && o.size_m > p.min_object_size_m && surfels >= p.min_object_surfels;
}

/// Whether `o`'s class is one the detectors can name (every class when the set is empty).
bool isDetectable(const GtClassObject& o, const ClassificationMetricsParams& p) {
  return p.detectable_classes.empty() || p.detectable_classes.count(o.class_name) != 0;
}

}  // namespace

ClassificationMetrics computeClassificationMetrics(
    const std::vector<std::uint32_t>& segment, const std::vector<std::uint32_t>& instance,
    const std::map<std::uint32_t, std::string>& segment_class,
    const std::vector<GtClassObject>& objects, const ClassificationMetricsParams& params,
    const std::map<std::uint32_t, int>& segment_detections) {
  if (segment.size() != instance.size())
    throw std::invalid_argument("computeClassificationMetrics: segment and instance sizes differ");
  std::unordered_map<std::uint32_t, Counts> by_segment, by_instance;  // s -> g -> n, g -> s -> n
  std::unordered_map<std::uint32_t, std::size_t> segment_size;
  for (std::size_t i = 0; i < segment.size(); ++i) {
    if (instance[i] != 0) ++by_instance[instance[i]][segment[i]];
    if (segment[i] != 0 && instance[i] != 0) {
      ++by_segment[segment[i]][instance[i]];
      ++segment_size[segment[i]];
    }
  }
  std::unordered_map<std::uint32_t, const GtClassObject*> object_of;
  for (const GtClassObject& o : objects) object_of[o.instance_id] = &o;
  const auto classOf = [&](std::uint32_t s) {
    const auto it = segment_class.find(s);
    return it == segment_class.end() || it->second.empty() ? std::string("none") : it->second;
  };

  ClassificationMetrics m;
  m.by_views = {{0, 0}, {1, 2}, {3, 5}, {6, 10}, {11, -1}};
  for (const GtClassObject& o : objects) {
    if (o.is_structure || !(o.size_m > params.min_object_size_m)) continue;
    ObjectClassResult r;
    r.object = o;
    Counts segs = by_instance.count(o.instance_id) ? by_instance[o.instance_id] : Counts{};
    for (const auto& [s, n] : segs) r.surfels += n;
    r.evaluated = isEvaluated(o, r.surfels, params);
    segs.erase(0);
    std::size_t n_dom = 0;
    r.segment = argmax(segs, &n_dom);
    r.segment_share = r.surfels > 0 ? double(n_dom) / double(r.surfels) : 0.0;
    if (r.segment != 0) {
      r.predicted = classOf(r.segment);
      r.segmented = argmax(by_segment[r.segment]) == o.instance_id &&
                    r.segment_share >= params.min_segment_share;
    }
    r.correct = r.segment != 0 && r.predicted == o.class_name;
    const auto views = segment_detections.find(r.segment);
    r.views = r.segment != 0 && views != segment_detections.end() ? views->second : 0;
    r.detectable = isDetectable(o, params);
    if (r.evaluated) {
      ++m.evaluated;
      m.correct += r.correct;
      ClassStats& cs = m.per_class[o.class_name];
      ++cs.objects;
      cs.objects_correct += r.correct;
      ++m.confusion[o.class_name][r.predicted];
      for (ViewBin& b : m.by_views)
        if (r.views >= b.min_views && (b.max_views < 0 || r.views <= b.max_views)) {
          ++b.objects;
          b.correct += r.correct;
        }
      if (r.segmented && r.detectable) {
        ++m.segmented_detectable;
        m.segmented_detectable_correct += r.correct;
      }
    }
    m.per_object.push_back(std::move(r));
  }
  // Precision: every segment of a useful size that carries a class.
  for (const auto& [s, n] : segment_size) {
    const std::string predicted = classOf(s);
    if (predicted == "none" || n < params.min_object_surfels) continue;
    ClassStats& cs = m.per_class[predicted];
    ++cs.segments_predicted;
    const auto it = object_of.find(argmax(by_segment[s]));
    cs.segments_true += it != object_of.end() && it->second->class_name == predicted;
  }
  m.object_accuracy = m.evaluated > 0 ? double(m.correct) / double(m.evaluated) : std::nan("");
  m.segmented_accuracy = m.segmented_detectable > 0 ? double(m.segmented_detectable_correct) /
                                                          double(m.segmented_detectable)
                                                    : std::nan("");
  return m;
}

namespace {

/// The object's name, else "<class>#<instance id>" (world objects need no name).
std::string displayName(const GtClassObject& o) {
  return o.name.empty() ? o.class_name + "#" + std::to_string(o.instance_id) : o.name;
}

}  // namespace

ObjectLevelMetrics computeObjectLevelMetrics(const std::vector<std::uint32_t>& segment,
                                             const std::vector<std::uint32_t>& instance,
                                             const std::vector<ReportedObject>& reported,
                                             const std::vector<GtClassObject>& objects,
                                             const ClassificationMetricsParams& params) {
  if (segment.size() != instance.size())
    throw std::invalid_argument("computeObjectLevelMetrics: segment and instance sizes differ");
  std::unordered_map<std::uint32_t, std::size_t> object_of_segment;  // segment -> reported index
  for (std::size_t r = 0; r < reported.size(); ++r)
    for (const std::uint32_t s : reported[r].segments)
      if (!object_of_segment.emplace(s, r).second)
        throw std::invalid_argument("computeObjectLevelMetrics: segment " + std::to_string(s) +
                                    " is in two reported objects");
  std::vector<std::size_t> reported_size(reported.size(), 0);
  std::vector<Counts> overlap(reported.size());  // reported -> instance -> |R ∩ G|
  Counts instance_size;
  for (std::size_t i = 0; i < segment.size(); ++i) {
    if (instance[i] != 0) ++instance_size[instance[i]];
    const auto it = object_of_segment.find(segment[i]);
    if (segment[i] == 0 || it == object_of_segment.end()) continue;
    ++reported_size[it->second];
    if (instance[i] != 0) ++overlap[it->second][instance[i]];
  }
  std::unordered_map<std::uint32_t, const GtClassObject*> object_of;
  for (const GtClassObject& o : objects) object_of[o.instance_id] = &o;

  ObjectLevelMetrics m;
  std::set<std::uint32_t> found;
  for (std::size_t r = 0; r < reported.size(); ++r) {
    ReportedObjectResult res;
    res.object = reported[r];
    res.surfels = reported_size[r];
    for (const auto& [g, n] : overlap[r]) {
      const double iou = double(n) / double(reported_size[r] + instance_size[g] - n);
      if (iou > res.iou || (iou == res.iou && g < res.best_instance)) {
        res.iou = iou;
        res.best_instance = g;
      }
    }
    const auto it = object_of.find(res.best_instance);
    if (it != object_of.end()) {
      res.best_name = displayName(*it->second);
      res.best_class = it->second->class_name;
    }
    res.correct = res.iou > params.min_object_iou && res.best_class == reported[r].class_name;
    ++m.reported;
    if (res.correct) {
      ++m.reported_correct;
      found.insert(res.best_instance);
    }
    m.per_reported.push_back(std::move(res));
  }
  for (const GtClassObject& o : objects) {
    const auto n = instance_size.find(o.instance_id);
    if (!isEvaluated(o, n == instance_size.end() ? 0 : n->second, params) ||
        !isDetectable(o, params))
      continue;
    ++m.objects;
    if (found.count(o.instance_id) != 0)
      ++m.objects_found;
    else
      m.missed.push_back(displayName(o));
  }
  m.precision = m.reported > 0 ? double(m.reported_correct) / double(m.reported) : std::nan("");
  m.recall = m.objects > 0 ? double(m.objects_found) / double(m.objects) : std::nan("");
  return m;
}

}  // namespace rasm::classification
