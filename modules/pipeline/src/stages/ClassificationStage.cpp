#include "rasm/pipeline/stages/ClassificationStage.h"
#include "rasm/core/Log.h"

#include "rasm/classification/ObjectVerdict.h"

#include <cstdio>
#include <filesystem>

#include "rasm/classification/ClassFusion.h"
#include "rasm/core/Error.h"
#include "rasm/core/Timing.h"
#include "rasm/pipeline/ClassLegend.h"
#include "rasm/pipeline/OutputFiles.h"
#ifdef RASM_HAVE_SIM
#include "rasm/pipeline/SimDetector.h"
#endif
#include "rasm/surfel_map/MapExport.h"

namespace rasm::pipeline {

using namespace rasm::classification;

namespace {
/// Without the simulator (-DRASM_WITH_SIM=OFF) there is no sim_detector: an InputError that says
/// so rather than a run without it.
void requireBuiltDetectors(const TClassificationParams& params) {
#ifdef RASM_HAVE_SIM
  (void)params;
#else
  if (!params.enabled) return;
  for (const std::string& name : params.detectorList())
    if (name == "sim_detector")
      throwInputError("[classification] detectors = " + params.detectors,
                      "sim_detector: this rasm was built without the simulator "
                      "(-DRASM_WITH_SIM=OFF); use dnn_detector or zero_shot");
#endif
}
}  // namespace

ClassificationStage::ClassificationStage(SegmentLayer* segments)
    : MapperStage("classification", {"cls_fuse"}), m_segments(segments) {
#ifdef RASM_HAVE_SIM
  auto sim_params = std::make_unique<sim::TDetectorParams>();
  const sim::TDetectorParams* sim_detector = sim_params.get();
  m_sim_detector = std::move(sim_params);
  const auto make = [this, sim_detector](const TClassificationParams& params) {
    return std::make_unique<SimDetector>(*sim_detector, m_sim_scene, std::uint64_t(params.seed));
  };
  m_detector_sections.added.push_back({"sim_detector", m_sim_detector.get(), make});
#endif
  if (segments)
    segments->addRelabelListener(
        [this](const std::vector<std::uint32_t>& table) { relabel(table); });
}

ClassificationStage::~ClassificationStage() = default;

std::vector<ParamsSection> ClassificationStage::sections() {
  std::vector<ParamsSection> out = {{"classification", &m_params}, {"objects", &m_object_params}};
  for (const auto& [name, params] : m_detector_sections.list()) out.push_back({name, params});
  return out;
}

void ClassificationStage::configure(const TMapperParams& /*mapper*/) {
  if (m_started)
    throw std::logic_error("ClassificationStage: reconfigured after its detectors started");
  requireBuiltDetectors(m_params);
}

void ClassificationStage::addDetector(std::unique_ptr<Detector> detector) {
  if (m_started) throw std::logic_error("ClassificationStage::addDetector: after the first frame");
  m_extra_detectors.push_back(std::move(detector));
}

void ClassificationStage::resolveAuto(bool simulated_source) {
  if (m_started) throw std::logic_error("ClassificationStage::resolveAuto: after the first frame");
  m_params.resolveAuto(simulated_source);
}

void ClassificationStage::startWorkers(maps::CSurfelMap& map) {
  m_params.resolveAuto(m_sim_scene != nullptr);
  m_started = true;
  // The map's class list: a loaded map's, else the default; the detectors' classes join it.
  m_classes = ClassList(map.classes().empty() ? ClassList::defaultClasses() : map.classes(),
                        map.creationOptions().n_classes);
  m_object_map = ObjectMap(m_object_params, m_params);
  m_pose_consensus = PoseConsensus(m_params.pose_agreement_deg, m_params.pose_min_view_change_deg,
                                   m_params.pose_max_fraction_of_view_change);
  if (!m_params.enabled) return;
  requireBuiltDetectors(m_params);
  DetectorBuild built = makeDetectors(m_params, m_detector_sections);
  for (auto& d : m_extra_detectors) built.detectors.push_back(std::move(d));
  m_extra_detectors.clear();
  m_warnings = std::move(built.warnings);
  for (const std::string& w : m_warnings) log::warning(w);
  for (auto& d : built.detectors) {
    m_class_ids.push_back(m_classes.registerDetector(*d));
    m_object_map.setDetectorClasses(int(m_workers.size()), m_class_ids.back());
    m_workers.push_back(
        std::make_unique<DetectorWorker>(std::move(d), int(m_workers.size()), m_params.threaded));
  }
  map.classes() = m_classes.classes();
}

void ClassificationStage::process(FrameContext& ctx, maps::CSurfelMap& map) {
  m_frame_detections = m_frame_associated = 0;
  if (!m_started) startWorkers(map);
  if (m_workers.empty()) return;
  const auto t = Clock::now();
  fuseArrived(map);
  recordMs(ctx, kFuse, msSince(t));
  if (!ctx.result.fusable() || ctx.labels.empty()) return;
  if (m_frames_seen++ % std::size_t(m_params.every_n_frames) != 0) return;
  // The workers share one copy of the frame; its L^p waits here for their results.
  auto frame = std::make_shared<const RgbdFrame>(*ctx.frame);
  Pending& pending = m_pending[frame->index];
  pending.labels = ctx.labels;
  pending.T_world_cam = ctx.result.T_world_cam;
  pending.intrinsics = frame->intrinsics;
  ++m_frames_offered;
  for (auto& w : m_workers) pending.outstanding += w->offer(frame);
  if (pending.outstanding == 0) m_pending.erase(frame->index);
  if (!m_params.threaded) {
    const auto t2 = Clock::now();
    fuseArrived(map);
    recordMs(ctx, kFuse, msSince(t2));
  }
}

void ClassificationStage::fuseArrived(maps::CSurfelMap& map) {
  std::vector<DetectorResult> arrived;
  for (auto& w : m_workers) w->collect(arrived);
  for (const DetectorResult& r : arrived) {
    auto it = m_pending.find(r.frame_index);
    if (it == m_pending.end())
      throw std::logic_error("ClassificationStage: a result for frame " +
                             std::to_string(r.frame_index) + " that was never offered");
    fuseResult(r, it->second, map);
    if (--it->second.outstanding == 0) m_pending.erase(it);
  }
  if (!arrived.empty()) updateObjects();
}

void ClassificationStage::updateObjects() {
  if (m_segments)
    m_object_map.update(m_segments->table().segments());
  else
    m_object_map.update({});
}

void ClassificationStage::fuseResult(const DetectorResult& r, Pending& p, maps::CSurfelMap& map) {
  if (r.failed) {  // the worker disabled the detector; said now and in report.json "detectors"
    log::warning(m_workers[std::size_t(r.worker)]->error() + " (mapping goes on without it)");
    return;
  }
  ++m_results;
  m_detections += r.detections.size();
  m_frame_detections += int(r.detections.size());
  const std::vector<Association> assoc =
      associateDetections(p.labels, r.detections, float(m_params.min_iou),
                          float(m_object_params.piece_min_inside_fraction));
  const std::vector<int>& ids = m_class_ids[std::size_t(r.worker)];
  DetectorView view;  // what the object layer learns from this result
  view.frame = r.frame_index;
  view.detector = r.worker;
  view.segment_pixels = segmentPixelCounts(p.labels);
  std::vector<SegmentEvidence>& evidence = view.evidence;
  std::map<std::uint32_t, std::vector<std::int32_t>> held_surfels =
      surfelsOfPosedSegments(r, assoc, map);
  for (std::size_t d = 0; d < r.detections.size(); ++d) {
    if (assoc[d].segment == 0) continue;
    ++m_associated;
    ++m_frame_associated;
    const Detection& det = r.detections[d];
    std::vector<SegmentEvidence> items;
    for (const ClassScore& cs : det.scores) {
      if (cs.class_index < 0 || cs.class_index >= int(ids.size())) continue;
      items.push_back({assoc[d].segment, ids[std::size_t(cs.class_index)],
                       detectionProbability(cs.score, m_params.scoreModel(),
                                            float(m_params.max_detection_probability),
                                            float(m_params.vote_neutral_score)),
                       m_params.iou_weighted_evidence ? assoc[d].iou : 1.f});
    }
    const bool posed = det.pose.valid && det.bestIndex() >= 0 && det.bestIndex() < int(ids.size());
    if (posed && m_params.pose_consensus) {
      const int class_id = ids[std::size_t(det.bestIndex())];
      PoseConsensus::Released released =
          consensus(det, assoc[d].segment, class_id, std::move(items), p, r.frame_index,
                    held_surfels.count(assoc[d].segment) ? held_surfels[assoc[d].segment]
                                                         : std::vector<std::int32_t>{});
      evidence.insert(evidence.end(), released.evidence.begin(), released.evidence.end());
      fuseReleasedEarlier(released.earlier, assoc[d].segment, r.worker, map);
      if (!released.this_one) continue;  // held until another view agrees
    } else {
      evidence.insert(evidence.end(), items.begin(), items.end());
    }
    ++m_fused_per_segment[assoc[d].segment];
    view.detected_segments.push_back(assoc[d].segment);
    for (const std::uint32_t piece : assoc[d].pieces)
      view.co_detected.emplace_back(assoc[d].segment, piece);
    if (posed) {
      PoseRecord& rec = m_pose_per_segment[assoc[d].segment];
      if (det.bestScore() >= rec.score)
        rec = {det.pose, ids[std::size_t(det.bestIndex())], det.bestScore()};
    }
  }
  const FusionCounts c = fuseSegmentEvidence(map.store().arraysForClassEvidence(), evidence);
  m_surfel_updates += c.surfels;
  m_dropped_updates += c.dropped;
  m_object_map.addDetectorView(view);
}

std::map<std::uint32_t, std::vector<std::int32_t>> ClassificationStage::surfelsOfPosedSegments(
    const DetectorResult& r, const std::vector<Association>& assoc,
    const maps::CSurfelMap& map) const {
  // A held detection keeps at most this many surfels (an object the zero-shot classifier looks
  // for is far smaller); a larger segment's evidence goes to the segment at release.
  constexpr std::size_t kMaxHeldSurfels = 50000;
  std::map<std::uint32_t, std::vector<std::int32_t>> out;
  if (!m_params.pose_consensus) return out;
  for (std::size_t d = 0; d < r.detections.size(); ++d)
    if (assoc[d].segment != 0 && r.detections[d].pose.valid) out[assoc[d].segment];
  if (out.empty()) return out;
  const maps::SurfelArrays a = map.store().arrays();
  for (int i = 0; i < a.size; ++i) {
    if (!a.alive(i)) continue;
    const auto it = out.find(a.segment[i]);
    if (it != out.end() && it->second.size() <= kMaxHeldSurfels) it->second.push_back(i);
  }
  for (auto& [segment, list] : out)
    if (list.size() > kMaxHeldSurfels) list.clear();
  return out;
}

void ClassificationStage::fuseReleasedEarlier(std::vector<ReleasedDetection>& earlier,
                                              std::uint32_t segment, int worker,
                                              maps::CSurfelMap& map) {
  for (ReleasedDetection& e : earlier) {
    const maps::SurfelArrays a = map.store().arraysForClassEvidence();
    const FusionCounts c = e.surfels.empty() ? fuseSegmentEvidence(a, e.evidence)
                                             : fuseSurfelListEvidence(a, e.surfels, e.evidence);
    m_surfel_updates += c.surfels;
    m_dropped_updates += c.dropped;
    ++m_fused_per_segment[segment];
    DetectorView v;  // detected in its own frame after all, with its evidence
    v.frame = e.frame;
    v.detector = worker;
    v.detected_segments.push_back(segment);
    v.evidence = std::move(e.evidence);
    for (SegmentEvidence& item : v.evidence) item.segment = segment;
    m_object_map.addDetectorView(v);
  }
}

PoseConsensus::Released ClassificationStage::consensus(const Detection& det, std::uint32_t segment,
                                                       int class_id,
                                                       std::vector<SegmentEvidence> items,
                                                       const Pending& p, std::size_t frame,
                                                       std::vector<std::int32_t> surfels) {
  const cv::Point2f centre(det.box.x + 0.5f * det.box.width, det.box.y + 0.5f * det.box.height);
  const Eigen::Vector3d ray_cam((centre.x - p.intrinsics.cx) / p.intrinsics.fx,
                                (centre.y - p.intrinsics.cy) / p.intrinsics.fy, 1.0);
  PoseObservation o;
  o.R_world_model = impliedModelRotation(det.pose, p.T_world_cam.linear(), ray_cam);
  o.sight_world = (p.T_world_cam.linear() * ray_cam).normalized();
  o.azimuth_period_deg = det.pose.azimuth_period_deg;
  o.frame = frame;
  o.evidence = std::move(items);
  o.surfels = std::move(surfels);
  return m_pose_consensus.add(segment, class_id, std::move(o));
}

void ClassificationStage::relabel(const std::vector<std::uint32_t>& table) {
  const auto apply = [&](std::uint32_t l) { return l < table.size() ? table[l] : l; };
  m_object_map.relabel(table);
  m_pose_consensus.relabel(table);
  for (auto& [index, p] : m_pending)
    for (int y = 0; y < p.labels.height(); ++y) {
      std::uint32_t* row = p.labels.row(y);
      for (int x = 0; x < p.labels.width(); ++x) row[x] = apply(row[x]);
    }
  std::map<std::uint32_t, int> counts;
  for (const auto& [l, n] : m_fused_per_segment)
    if (apply(l) != 0) counts[apply(l)] += n;
  m_fused_per_segment = std::move(counts);
  std::map<std::uint32_t, PoseRecord> poses;
  for (const auto& [l, rec] : m_pose_per_segment) {
    const std::uint32_t n = apply(l);
    if (n != 0 && (poses.count(n) == 0 || rec.score > poses[n].score)) poses[n] = rec;
  }
  m_pose_per_segment = std::move(poses);
}

void ClassificationStage::finishRun(maps::CSurfelMap& map) {
  for (auto& w : m_workers) w->waitIdle();
  fuseArrived(map);
}

void ClassificationStage::csvColumns(std::vector<std::string>& c) const {
  c.insert(c.end(), {"cls_detections", "cls_fused", "cls_pending", "objects"});
}

void ClassificationStage::csvValues(const FrameContext& /*ctx*/, CsvRow& row) const {
  std::size_t objects = 0;
  for (const MapObject& o : m_object_map.objects()) objects += o.verdict == ObjectVerdict::Object;
  row.add(m_frame_detections).add(m_frame_associated).add(m_pending.size()).add(objects);
}

void ClassificationStage::report(nlohmann::json& rep) const {
  nlohmann::json j;
  j["enabled"] = m_params.enabled;
  j["threaded"] = m_params.threaded;
  j["every_n_frames"] = m_params.every_n_frames;
  j["frames_offered"] = m_frames_offered;
  j["results_fused"] = m_results;
  j["detections"] = m_detections;
  j["detections_fused"] = m_associated;
  j["detections_without_segment"] = m_detections - m_associated;
  j["surfel_updates"] = m_surfel_updates;
  j["pose_consensus"] = {{"enabled", m_params.pose_consensus},
                         {"detections_released", m_pose_consensus.releasedDetections()},
                         {"detections_held", m_pose_consensus.heldDetections()}};
  j["surfel_updates_dropped"] = m_dropped_updates;
  j["class_evidence_bytes_per_surfel"] = sizeof(maps::ClassEvidence);
  j["classes"] = m_classes.size();
  nlohmann::json dets = nlohmann::json::array();
  for (const auto& w : m_workers) {
    const DetectorWorkerStats s = w->stats();
    nlohmann::json d = {{"name", w->detector().name()},
                        {"frames_offered", s.offered},
                        {"frames_detected", s.calls},
                        {"frames_skipped", s.skipped},
                        {"detections", s.detections},
                        {"ms_per_call", s.calls > 0 ? s.ms_total / double(s.calls) : 0.0},
                        {"ms_max", s.ms_max}};
    if (w->disabled()) d["disabled"] = w->error();
    dets.push_back(d);
  }
  j["detectors"] = dets;
  j["warnings"] = m_warnings;
  if (m_objects_counted) {  // the final map's (after writeOutputs)
    int n = 0;
    for (const auto& [c, k] : m_objects_by_class) n += k;
    j["objects"] = n;
    j["objects_by_class"] = m_objects_by_class;
  }
  rep["classification"] = j;
}

}  // namespace rasm::pipeline

namespace rasm::pipeline {

namespace {

nlohmann::json vec3(const Eigen::Vector3d& v) {
  return nlohmann::json{v.x(), v.y(), v.z()};
}

nlohmann::json axesJson(const Eigen::Matrix3d& axes) {
  nlohmann::json out = nlohmann::json::array();
  for (int k = 0; k < 3; ++k) out.push_back(vec3(axes.col(k)));
  return out;
}

/// The oriented box of a segment: its upright (z-up) axes and extents about their centre.
nlohmann::json orientedBox(const segmentation::SegmentStats& s) {
  return {{"centre", vec3(s.upright_centre)},
          {"axes", axesJson(s.upright_axes)},
          {"extents_m", vec3(s.upright_extents)}};
}

}  // namespace

nlohmann::json ClassificationStage::objectEntry(const MapObject& o) const {
  nlohmann::json histogram = nlohmann::json::array();
  for (const ClassProbability& c : o.top)
    histogram.push_back({{"class", m_classes.name(c.class_id)},
                         {"class_id", c.class_id},
                         {"probability", c.probability}});
  nlohmann::json j = {{"id", o.id},
                      {"class", m_classes.name(o.best.class_id)},
                      {"class_id", o.best.class_id},
                      {"probability", o.best.probability},
                      {"runner_up", m_classes.name(o.runner_up.class_id)},
                      {"runner_up_probability", o.runner_up.probability},
                      {"histogram", histogram},
                      {"existence_probability", o.existence_probability},
                      {"views", o.views},
                      {"views_detected", o.views_detected},
                      {"frames",
                       {{"first_seen", o.first_seen_frame},
                        {"last_seen", o.last_seen_frame},
                        {"seen", o.frames_seen},
                        {"detected", o.frames_detected}}},
                      {"segments", o.segments},
                      {"surfels", o.surfels},
                      {"detections_fused", o.detections}};
  if (o.has_geometry) {
    j["centroid"] = vec3(o.centroid);
    j["box"] = {{"min", vec3(o.bbox_min)},
                {"max", vec3(o.bbox_max)},
                {"centre", vec3(0.5 * (o.bbox_min + o.bbox_max))},
                {"size_m", vec3(o.bbox_max - o.bbox_min)}};
    j["oriented_box"] = {{"centre", vec3(o.box_centre)},
                         {"axes", axesJson(o.box_axes)},
                         {"extents_m", vec3(o.box_extents_m)}};
  }
  const PoseRecord* best_pose = nullptr;  // the best-scoring template match over its segments
  for (const std::uint32_t s : o.segments) {
    const auto pose = m_pose_per_segment.find(s);
    if (pose != m_pose_per_segment.end() && (!best_pose || pose->second.score > best_pose->score))
      best_pose = &pose->second;
  }
  if (best_pose)
    j["pose_hint"] = {{"class", m_classes.name(best_pose->class_id)},
                      {"azimuth_deg", best_pose->pose.azimuth_deg},
                      {"elevation_deg", best_pose->pose.elevation_deg},
                      {"template", best_pose->pose.template_index},
                      {"score", best_pose->score}};
  return j;
}

nlohmann::json ClassificationStage::segmentEntry(std::uint32_t segment,
                                                 const MapObject& object) const {
  const ObjectMap::SegmentRecord* r = m_object_map.segmentRecord(segment);
  const maps::BestClass b = r ? maps::bestClass(r->histogram) : maps::BestClass{};
  const bool named = b.id != 0 && b.probability >= m_params.min_object_probability;
  nlohmann::json j = {{"segment", segment},
                      {"object", object.id},
                      {"class", named ? m_classes.name(b.id) : std::string("none")},
                      {"class_id", named ? b.id : 0},
                      {"best_class", m_classes.name(b.id)},
                      {"probability", b.probability},
                      {"detections_fused", r ? r->detections : 0},
                      {"not_an_object", toString(object.verdict)}};
  const segmentation::SegmentStats* s = m_segments ? m_segments->table().find(segment) : nullptr;
  if (s) {
    j["surfels"] = s->surfels;
    j["centroid"] = vec3(s->centroid);
    j["pca_extents_m"] = vec3(s->extents);
    j["oriented_box"] = orientedBox(*s);
  }
  return j;
}

void ClassificationStage::writeClassLegend(OutputFolder& folder,
                                           const maps::CSurfelMap& map) const {
  const maps::SurfelArrays a = map.store().arrays();
  std::map<int, long long> surfels;  // best class -> stable surfels
  for (int i = 0; i < a.size && a.n_classes > 0; ++i)
    if (a.alive(i) && a.stable(i)) {
      const int id = maps::bestClass(a, i).id;
      if (id != 0) ++surfels[id];
    }
  std::vector<ClassLegendEntry> entries;
  for (const auto& [id, n] : surfels) entries.push_back({id, m_classes.name(id), n});
  std::sort(entries.begin(), entries.end(),
            [](const auto& x, const auto& y) { return x.surfels > y.surfels; });
  folder.writeImage("classes_legend.png", classLegendImage(entries));
}

nlohmann::json ClassificationStage::reportedObjects() const {
  nlohmann::json objects = nlohmann::json::array();
  for (const MapObject& o : m_object_map.objects())
    if (o.verdict == ObjectVerdict::Object) objects.push_back(objectEntry(o));
  return nlohmann::json{{"objects", objects}};
}

void ClassificationStage::writeOutputs(OutputFolder& folder, const maps::CSurfelMap& map) {
  if (!m_params.enabled || !m_started) return;
  nlohmann::json classes = nlohmann::json::array();
  const auto rgb = [](int id) {
    const Bgr8 c = maps::labelColour(id);
    return nlohmann::json::array({c.r, c.g, c.b});
  };
  for (int id = 1; id <= m_classes.size(); ++id)
    classes.push_back({{"id", id},
                       {"name", m_classes.name(id)},
                       {"source", m_classes.classes()[std::size_t(id - 1)].source},
                       {"colour", rgb(id)}});
  folder.writeText("classes.json",
                   nlohmann::json{{"comment",
                                   "the map's class list (IV): surfel class evidence ids, "
                                   "source = where the name came from, colour = [r, g, b] in "
                                   "map_classes.ply / .3Dscene and preview_classes.png at "
                                   "probability 1, faded towards none_colour as it falls to "
                                   "0.5 (classes_legend.png shows the classes in the map)"},
                                  {"none_colour", rgb(0)},
                                  {"classes", classes}}
                           .dump(1) +
                       "\n");
  writeClassLegend(folder, map);
  updateObjects();  // the final map's segment table (the segmentation's writeOutputs published it)
  m_objects_by_class.clear();
  m_objects_counted = true;
  nlohmann::json objects = nlohmann::json::array(), others = nlohmann::json::array();
  for (const MapObject& o : m_object_map.objects()) {
    if (o.verdict == ObjectVerdict::Object) {
      ++m_objects_by_class[m_classes.name(o.best.class_id)];
      objects.push_back(objectEntry(o));
      continue;
    }
    if (!o.has_geometry) continue;              // its segments are gone from the map
    for (const std::uint32_t s : o.segments) {  // segments that carry a class or a detection
      const ObjectMap::SegmentRecord* r = m_object_map.segmentRecord(s);
      if (r && (r->detections > 0 || !maps::classEvidenceEmpty(r->histogram)))
        others.push_back(segmentEntry(s, o));
    }
  }
  nlohmann::json out;
  out["comment"] =
      "rasm objects (section IV): objects = the object layer's objects (one or more segments "
      "of one confirmed class whose boxes touch and which detections saw together, [objects]), "
      "each once, with a persistent id; "
      "class = best of the histogram of its detections (log-odds, IV), reaching [classification] "
      "min_object_probability; at least min_object_surfels surfels and min_object_size_m of "
      "extent, not structure (a thin plane larger than structure_min_extent_m both ways, or one "
      "in the plane of such a segment: structure_piece_*) and "
      "existence_probability = (views_detected + 1) / (views + 2) reaching [objects] "
      "min_existence_probability; frames: frame indices of the views (frames a detector "
      "processed in which it covered min_view_pixels of L^p); box: axis-aligned box of its "
      "segments; oriented_box: upright axes (z up) and extents about its centre. "
      "other_segments = the segments of objects not reported that carry a class or had "
      "detections fused, with not_an_object = unconfirmed | fragment | structure | "
      "rarely_detected (of their object) and object = its id; world frame, metres";
  out["objects"] = objects;
  out["other_segments"] = others;
  folder.writeText("objects.json", out.dump(1) + "\n");
  folder.write("map_classes.ply", [&](const std::string& part) {
    maps::writeSurfelPly(map.store(), part, false, maps::SurfelColouring::Class);
  });
}

std::map<std::uint32_t, std::string> ClassificationStage::segmentClassNames(
    const maps::CSurfelMap& /*map*/) const {
  std::map<std::uint32_t, std::string> names;
  for (const auto& [segment, id] : m_object_map.objectIdOfSegment()) {
    const MapObject* o = m_object_map.object(id);
    if (o && o->verdict == ObjectVerdict::Object) names[segment] = m_classes.name(o->best.class_id);
  }
  return names;
}

}  // namespace rasm::pipeline
