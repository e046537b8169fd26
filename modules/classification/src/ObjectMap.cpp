#include "rasm/classification/ObjectMap.h"

#include <algorithm>
#include <numeric>

namespace rasm::classification {

namespace {

using segmentation::SegmentStats;

const SegmentStats* findStats(const std::vector<SegmentStats>& segments, std::uint32_t id) {
  const auto it = std::lower_bound(segments.begin(), segments.end(), id,
                                   [](const SegmentStats& s, std::uint32_t v) { return s.id < v; });
  return it != segments.end() && it->id == id ? &*it : nullptr;
}

/// Whether `piece` is part of the structure segment `whole` (TClassificationParams
/// structure_piece_*): a thin plane, large both ways, in whole's plane (normals within 10
/// degrees, its centroid near the plane).
bool isStructurePiece(const SegmentStats& piece, const SegmentStats& whole,
                      const TClassificationParams& p) {
  const double kCos10 = 0.98480775;
  if (!(piece.extents.z() < p.structure_max_thickness_m &&
        piece.extents.y() >= p.structure_piece_min_extent_m))
    return false;
  const Eigen::Vector3d n_piece = piece.axes.col(2), n_whole = whole.axes.col(2);
  return std::abs(n_piece.dot(n_whole)) >= kCos10 &&
         std::abs(n_whole.dot(piece.centroid - whole.centroid)) <= p.structure_piece_max_offset_m;
}

/// Adds every class of `from` into `into` (log-odds of independent evidence add: IV).
void addHistogram(maps::ClassEvidence& into, const maps::ClassEvidence& from) {
  for (int k = 0; k < maps::kClassSlots; ++k)
    if (from.id[k] != 0) maps::classEvidenceAdd(into, from.id[k], from.logit[k]);
}

/// The largest gap between two axis-aligned boxes over the three axes (<= 0: they overlap).
double boxGap_m(const SegmentStats& a, const SegmentStats& b) {
  const Eigen::Vector3d gap =
      (a.bbox_min - b.bbox_max).cwiseMax(b.bbox_min - a.bbox_max);  // per axis
  return gap.maxCoeff();
}

/// The fraction of the smaller box's volume inside the other, both grown by `pad_m` on every
/// side (a flat segment's box then has a volume).
double boxContainment(const SegmentStats& a, const SegmentStats& b, double pad_m) {
  const Eigen::Vector3d pad = Eigen::Vector3d::Constant(pad_m);
  const Eigen::Vector3d a_lo = a.bbox_min - pad, a_hi = a.bbox_max + pad;
  const Eigen::Vector3d b_lo = b.bbox_min - pad, b_hi = b.bbox_max + pad;
  const Eigen::Vector3d common = (a_hi.cwiseMin(b_hi) - a_lo.cwiseMax(b_lo)).cwiseMax(0.0);
  const double smaller = std::min((a_hi - a_lo).prod(), (b_hi - b_lo).prod());
  return smaller > 0.0 ? common.prod() / smaller : 0.0;
}

/// The histogram's classes by decreasing log-odds (lower id first on ties).
std::vector<ClassProbability> sortedClasses(const maps::ClassEvidence& h) {
  std::vector<std::pair<int, int>> slots;  // (logit units, id)
  for (int k = 0; k < maps::kClassSlots; ++k)
    if (h.id[k] != 0) slots.emplace_back(h.logit[k], h.id[k]);
  std::sort(slots.begin(), slots.end(), [](const auto& x, const auto& y) {
    return x.first != y.first ? x.first > y.first : x.second < y.second;
  });
  std::vector<ClassProbability> out;
  for (const auto& [l, id] : slots)
    out.push_back({id, maps::logitProbability(maps::dequantizeClassLogit(l))});
  return out;
}

/// Union-find root with path halving.
std::size_t findRoot(std::vector<std::size_t>& parent, std::size_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

}  // namespace

std::vector<std::pair<std::uint32_t, int>> segmentPixelCounts(const Image<std::uint32_t>& labels) {
  std::map<std::uint32_t, int> counts;
  std::uint32_t run_label = 0;
  int run = 0;  // pixels of run_label not yet added (labels come in runs along a row)
  for (int y = 0; y < labels.height(); ++y) {
    const std::uint32_t* row = labels.row(y);
    for (int x = 0; x < labels.width(); ++x) {
      if (row[x] == run_label) {
        ++run;
        continue;
      }
      if (run_label != 0) counts[run_label] += run;
      run_label = row[x];
      run = 1;
    }
  }
  if (run_label != 0) counts[run_label] += run;
  return {counts.begin(), counts.end()};
}

void ObjectMap::setDetectorClasses(int detector, const std::vector<int>& class_ids) {
  m_detector_classes[detector] = std::set<int>(class_ids.begin(), class_ids.end());
}

bool ObjectMap::reportsClass(int detector, int class_id) const {
  const auto it = m_detector_classes.find(detector);
  return class_id == 0 || it == m_detector_classes.end() || it->second.count(class_id) != 0;
}

void ObjectMap::addDetectorView(const DetectorView& v) {
  const std::pair<std::size_t, int> key{v.frame, v.detector};
  for (const auto& [segment, pixels] : v.segment_pixels)
    if (segment != 0 && pixels >= m_params.min_view_pixels)
      m_segments[segment].views.emplace(key, false);
  for (const std::uint32_t segment : v.detected_segments) {
    if (segment == 0) continue;
    SegmentRecord& r = m_segments[segment];
    r.views[key] = true;  // a detected segment was seen, however few its pixels
    ++r.detections;
  }
  for (const SegmentEvidence& e : v.evidence)
    if (e.segment != 0)
      maps::classEvidenceAdd(m_segments[e.segment].histogram, e.class_id, evidenceLogitUnits(e));
  for (const auto& [a, b] : v.co_detected)
    if (a != 0 && b != 0 && a != b) ++m_codetections[{std::min(a, b), std::max(a, b)}];
}

bool ObjectMap::oneInsideTheOther(std::uint32_t a, std::uint32_t b, const SegmentStats& sa,
                                  const SegmentStats& sb) const {
  const double f = m_params.link_min_box_containment;
  if (f <= 0.0 || boxContainment(sa, sb, 0.01) < f) return false;
  // Only pieces never in one view: a desk top named "keyboard" by the boxes of the keyboard on
  // it contains the keyboard's box too, but the two were seen together and no detection held
  // the desk: two things.
  const auto& va = m_segments.at(a).views;
  const auto& vb = m_segments.at(b).views;
  for (const auto& [key, detected] : va)
    if (vb.count(key) != 0) return false;
  return true;
}

bool ObjectMap::seenTogether(std::uint32_t a, std::uint32_t b) const {
  const double f = m_params.link_min_codetection_fraction;
  if (f <= 0.0) return true;
  const auto it = m_codetections.find({std::min(a, b), std::max(a, b)});
  const int n = it == m_codetections.end() ? 0 : it->second;
  const int fewer = std::min(m_segments.at(a).detections, m_segments.at(b).detections);
  return n >= 1 && double(n) >= f * double(fewer);
}

void ObjectMap::relabel(const std::vector<std::uint32_t>& table) {
  const auto apply = [&](std::uint32_t l) { return l < table.size() ? table[l] : l; };
  std::map<std::uint32_t, SegmentRecord> records;
  for (auto& [old_label, r] : m_segments) {
    const std::uint32_t n = apply(old_label);
    if (n == 0) continue;
    auto [it, fresh] = records.try_emplace(n);
    if (fresh) {
      it->second = std::move(r);
      continue;
    }
    SegmentRecord& into = it->second;  // a merge: the two segments' evidence and views unite
    addHistogram(into.histogram, r.histogram);
    into.detections += r.detections;
    for (const auto& [key, detected] : r.views) into.views[key] = into.views[key] || detected;
  }
  m_segments = std::move(records);
  std::map<std::pair<std::uint32_t, std::uint32_t>, int>
      pairs;  // merged into one: no longer a pair
  for (const auto& [ab, n] : m_codetections) {
    const std::uint32_t a = apply(ab.first), b = apply(ab.second);
    if (a != 0 && b != 0 && a != b) pairs[{std::min(a, b), std::max(a, b)}] += n;
  }
  m_codetections = std::move(pairs);
  std::map<std::uint32_t, int> ids;  // a merged segment keeps the oldest of its objects' ids
  for (const auto& [old_label, id] : m_object_of_segment) {
    const std::uint32_t n = apply(old_label);
    if (n == 0) continue;
    auto [it, fresh] = ids.try_emplace(n, id);
    if (!fresh) it->second = std::min(it->second, id);
  }
  m_object_of_segment = std::move(ids);
}

std::vector<std::vector<std::uint32_t>> ObjectMap::groupSegments(
    const std::vector<SegmentStats>& segments) const {
  std::vector<std::uint32_t> labels;
  std::vector<int> link_class;  // the class a segment links by, 0: it links to nothing
  std::vector<const SegmentStats*> stats;
  for (const auto& [label, r] : m_segments) {
    const SegmentStats* s = findStats(segments, label);
    const maps::BestClass b = maps::bestClass(r.histogram);
    const bool links = s != nullptr && b.id != 0 &&
                       b.probability >= float(m_params.link_min_probability) &&
                       !isStructure(s->extents, m_thresholds);
    labels.push_back(label);
    link_class.push_back(links ? b.id : 0);
    stats.push_back(s);
  }
  std::vector<std::size_t> parent(labels.size());
  std::iota(parent.begin(), parent.end(), std::size_t(0));
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (link_class[i] == 0) continue;
    for (std::size_t j = i + 1; j < labels.size(); ++j)
      if (link_class[j] == link_class[i] &&
          boxGap_m(*stats[i], *stats[j]) <= m_params.link_max_gap_m &&
          (seenTogether(labels[i], labels[j]) ||
           oneInsideTheOther(labels[i], labels[j], *stats[i], *stats[j]))) {
        const std::size_t ri = findRoot(parent, i), rj = findRoot(parent, j);
        parent[std::max(ri, rj)] = std::min(ri, rj);
      }
  }
  std::map<std::size_t, std::vector<std::uint32_t>> groups;  // by root; labels stay sorted
  for (std::size_t i = 0; i < labels.size(); ++i) groups[findRoot(parent, i)].push_back(labels[i]);
  std::vector<std::vector<std::uint32_t>> out;
  for (auto& [root, g] : groups) out.push_back(std::move(g));
  return out;
}

void ObjectMap::assignIds(std::vector<MapObject>& objects) {
  // The largest objects choose first: each takes the oldest id among its segments' previous ones
  // that no larger object took, else a new one.
  std::vector<std::size_t> order(objects.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return objects[a].surfels > objects[b].surfels;
  });
  std::set<int> taken;
  for (const std::size_t k : order) {
    std::set<int> previous;
    for (const std::uint32_t s : objects[k].segments) {
      const auto it = m_object_of_segment.find(s);
      if (it != m_object_of_segment.end()) previous.insert(it->second);
    }
    int id = 0;
    for (const int p : previous)
      if (taken.count(p) == 0) {
        id = p;
        break;
      }
    objects[k].id = id != 0 ? id : m_next_id++;
    taken.insert(objects[k].id);
  }
  std::sort(objects.begin(), objects.end(),
            [](const MapObject& a, const MapObject& b) { return a.id < b.id; });
  m_object_of_segment.clear();
  for (const MapObject& o : objects)
    for (const std::uint32_t s : o.segments) m_object_of_segment[s] = o.id;
}

MapObject ObjectMap::describe(const std::vector<std::uint32_t>& group,
                              const std::vector<SegmentStats>& segments,
                              const std::vector<const SegmentStats*>& structure) const {
  MapObject o;
  o.segments = group;
  std::map<std::pair<std::size_t, int>, bool> views;  // (frame, detector) -> detected
  for (const std::uint32_t s : group) {
    const SegmentRecord& r = m_segments.at(s);
    addHistogram(o.histogram, r.histogram);
    o.detections += r.detections;
    for (const auto& [key, detected] : r.views) views[key] = views[key] || detected;
  }
  o.top = sortedClasses(o.histogram);
  if (!o.top.empty() && o.top[0].probability > 0.5f) o.best = o.top[0];
  if (o.top.size() > 1 && o.top[1].probability > 0.5f) o.runner_up = o.top[1];
  // Views by the detectors that report its class; frames by any detector.
  std::set<std::size_t> seen, detected_in;
  for (const auto& [key, detected] : views) {
    seen.insert(key.first);
    if (detected) detected_in.insert(key.first);
    if (!reportsClass(key.second, o.best.class_id)) continue;
    ++o.views;
    o.views_detected += detected;
  }
  o.existence_probability = double(o.views_detected + 1) / double(o.views + 2);
  o.frames_seen = int(seen.size());
  o.frames_detected = int(detected_in.size());
  if (!seen.empty()) {
    o.first_seen_frame = *seen.begin();
    o.last_seen_frame = *seen.rbegin();
  }
  describeGeometry(o, segments);
  SegmentClass c;
  c.surfels = o.surfels;
  c.best_id = o.best.class_id;
  c.best_p = o.best.probability;
  // A segment the table does not hold (gone from the map) has no surfels: a fragment at most.
  o.verdict = objectVerdict(c, o.box_extents_m, m_thresholds);
  if (o.verdict == ObjectVerdict::Object && partOfStructure(group, segments, structure))
    o.verdict = ObjectVerdict::Structure;
  if (o.verdict == ObjectVerdict::Object &&
      o.existence_probability < m_params.min_existence_probability)
    o.verdict = ObjectVerdict::RarelyDetected;
  return o;
}

bool ObjectMap::partOfStructure(const std::vector<std::uint32_t>& group,
                                const std::vector<SegmentStats>& segments,
                                const std::vector<const SegmentStats*>& structure) const {
  bool any = false;
  for (const std::uint32_t label : group) {
    const SegmentStats* s = findStats(segments, label);
    if (s == nullptr) continue;
    const bool piece = std::any_of(structure.begin(), structure.end(), [&](const SegmentStats* w) {
      return w != s && isStructurePiece(*s, *w, m_thresholds);
    });
    if (!piece) return false;
    any = true;
  }
  return any;
}

void ObjectMap::describeGeometry(MapObject& o, const std::vector<SegmentStats>& segments) const {
  std::vector<const SegmentStats*> parts;
  for (const std::uint32_t s : o.segments)
    if (const SegmentStats* st = findStats(segments, s)) parts.push_back(st);
  if (parts.empty()) return;
  o.has_geometry = true;
  const SegmentStats* largest = parts[0];
  o.bbox_min = parts[0]->bbox_min;
  o.bbox_max = parts[0]->bbox_max;
  for (const SegmentStats* st : parts) {
    o.surfels += st->surfels;
    o.centroid += double(st->surfels) * st->centroid;
    o.bbox_min = o.bbox_min.cwiseMin(st->bbox_min);
    o.bbox_max = o.bbox_max.cwiseMax(st->bbox_max);
    if (st->surfels > largest->surfels) largest = st;
  }
  if (o.surfels > 0) o.centroid /= double(o.surfels);
  // The upright box on the largest segment's axes that holds every segment's upright box
  // (percentile extents about its centre: SegmentTable.h).
  o.box_axes = largest->upright_axes;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const SegmentStats* st : parts)
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d sign((corner & 1) ? 0.5 : -0.5, (corner & 2) ? 0.5 : -0.5,
                                 (corner & 4) ? 0.5 : -0.5);
      const Eigen::Vector3d p_world =
          st->upright_centre + st->upright_axes * sign.cwiseProduct(st->upright_extents);
      const Eigen::Vector3d p_box = o.box_axes.transpose() * p_world;
      lo = lo.cwiseMin(p_box);
      hi = hi.cwiseMax(p_box);
    }
  o.box_centre = o.box_axes * (0.5 * (lo + hi));
  o.box_extents_m = hi - lo;
}

void ObjectMap::update(const std::vector<SegmentStats>& segments) {
  std::vector<MapObject> objects;
  std::vector<const SegmentStats*> structure;
  for (const SegmentStats& s : segments)
    if (isStructure(s.extents, m_thresholds)) structure.push_back(&s);
  for (const auto& group : groupSegments(segments))
    objects.push_back(describe(group, segments, structure));
  assignIds(objects);
  m_objects = std::move(objects);
}

const MapObject* ObjectMap::objectOfSegment(std::uint32_t segment) const {
  const auto it = m_object_of_segment.find(segment);
  return it == m_object_of_segment.end() ? nullptr : object(it->second);
}

const MapObject* ObjectMap::object(int id) const {
  const auto o = std::lower_bound(m_objects.begin(), m_objects.end(), id,
                                  [](const MapObject& x, int v) { return x.id < v; });
  return o != m_objects.end() && o->id == id ? &*o : nullptr;
}

const ObjectMap::SegmentRecord* ObjectMap::segmentRecord(std::uint32_t segment) const {
  const auto it = m_segments.find(segment);
  return it == m_segments.end() ? nullptr : &it->second;
}

}  // namespace rasm::classification
