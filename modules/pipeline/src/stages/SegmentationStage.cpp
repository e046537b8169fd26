#include "rasm/pipeline/stages/SegmentationStage.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <numeric>
#include <opencv2/imgproc.hpp>

#include "rasm/core/Timing.h"
#include "rasm/pipeline/OutputFiles.h"
#include "rasm/surfel_map/MapExport.h"

namespace rasm::pipeline {

void SegmentationStage::configure(const TMapperParams& /*mapper*/) {
  m_segmenter.setParams(m_params);
}

const Image<std::uint8_t>* SegmentationStage::intensityAt(const RgbdFrame& frame, int width,
                                                          int height) {
  if (!m_params.colour_edges || frame.colour.empty()) return nullptr;
  const cv::Mat bgr(frame.colour.height(), frame.colour.width(), CV_8UC3,
                    const_cast<Bgr8*>(frame.colour.data()), frame.colour.pitchBytes());
  cv::Mat grey;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  m_intensity.resize(width, height);
  cv::Mat out(height, width, CV_8UC1, m_intensity.data(), m_intensity.pitchBytes());
  cv::resize(grey, out, out.size(), 0, 0, cv::INTER_AREA);
  return &m_intensity;
}

void SegmentationStage::process(FrameContext& ctx, maps::CSurfelMap& map) {
  m_ran = false;
  m_frame_merges = 0;
  if (!m_params.enabled || !ctx.result.fusable()) return;
  if (!m_seeded) {
    // A map loaded from a file (`rasm run --map`) already holds labels: new ones start above.
    const maps::SurfelArrays a = static_cast<const maps::CSurfelMap&>(map).store().arrays();
    for (int i = 0; i < a.size; ++i)
      if (a.alive(i)) m_next_label = std::max(m_next_label, a.segment[i] + 1);
    m_seeded = true;
  }
  const FrameLevel& L0 = ctx.pyramid[0];
  const FrameLevel& Ls =
      ctx.pyramid[std::min<std::size_t>(std::size_t(m_params.level), ctx.pyramid.size() - 1)];
  const segmentation::FrameSegments& seg =
      m_segmenter.segment(Ls.vertex, Ls.normal, L0.K.width, L0.K.height,
                          intensityAt(*ctx.frame, Ls.K.width, Ls.K.height));
  recordMs(ctx, kEdges, seg.ms_normals + seg.ms_edges);
  recordMs(ctx, kComponents, seg.ms_components);
  const auto t = Clock::now();
  const maps::CSurfelMap& cmap = map;
  segmentation::propagateLabels(seg, L0.vertex, ctx.index_map, cmap.store().arrays(), m_params,
                                m_next_label, m_prop);
  ctx.labels = m_prop.propagated;
  recordMs(ctx, kPropagation, msSince(t));
  m_ran = true;
}

void SegmentationStage::finishFrame(FrameContext& ctx, maps::CSurfelMap& map) {
  if (!m_ran) return;
  const auto t = Clock::now();
  m_label_changes_stable += std::size_t(ctx.result.fusion.relabelled_stable);
  const auto due = m_psi.update(m_prop.cosegmented, m_prop.visible, m_params.merge_threshold);
  m_psi_max = std::max(m_psi_max, m_psi.size());
  if (!due.empty()) m_frame_merges = merge(map, due);
  m_merges += std::size_t(m_frame_merges);
  if (++m_frames % std::uint64_t(m_params.remap_every_n_frames) == 0) refreshTable(map);
  recordMs(ctx, kMerge, msSince(t));
}

int SegmentationStage::merge(maps::CSurfelMap& map,
                             const std::vector<segmentation::MergeConfidence::Pair>& due) {
  int merges = 0;
  applyRelabelling(map, segmentation::mergeTable(due, merges));
  return merges;
}

void SegmentationStage::applyRelabelling(maps::CSurfelMap& map,
                                         const std::vector<std::uint32_t>& table) {
  map.store().relabelSegments(table);
  m_psi.remap(table);
  m_published.publishRelabelling(table);
}

void SegmentationStage::refreshTable(maps::CSurfelMap& map) {
  const maps::CSurfelMap& cmap = map;
  segmentation::SegmentTable& segments = m_published.tableToWrite();
  segments.compute(cmap.store().arrays());
  // Labels are remapped to fill unused ids (III); the table follows.
  const std::vector<std::uint32_t> dense = segmentation::denseRelabelling(segments);
  bool identity = true;
  for (std::uint32_t l = 1; l < dense.size() && identity; ++l) identity = dense[l] == l;
  if (!identity) {
    applyRelabelling(map, dense);
    segments.renumber(dense);
  }
  m_next_label = segments.maxLabel() + 1;
}

void SegmentationStage::csvColumns(std::vector<std::string>& c) const {
  c.insert(c.end(),
           {"seg_frame_segments", "seg_matched", "seg_created", "seg_merged", "seg_psi_pairs"});
}

void SegmentationStage::csvValues(const FrameContext& /*ctx*/, CsvRow& row) const {
  if (!m_ran) {
    row.add(0).add(0).add(0).add(0).add(m_psi.size());
    return;
  }
  row.add(m_segmenter.last().count)
      .add(m_prop.matched)
      .add(m_prop.created)
      .add(m_frame_merges)
      .add(m_psi.size());
}

void SegmentationStage::report(nlohmann::json& rep) const {
  nlohmann::json j;
  j["enabled"] = m_params.enabled;
  j["frames_segmented"] = m_frames;
  j["merges"] = m_merges;
  j["psi_pairs_max"] = m_psi_max;
  // Label stability: how often a stable surfel's segment changed (fusion's relabelled_stable).
  j["label_changes_stable"] = m_label_changes_stable;
  if (m_stable_final >= 0) {
    j["stable_surfels"] = m_stable_final;
    j["segments"] = table().segments().size();
  }
  rep["segmentation"] = j;
}

void SegmentationStage::writeOutputs(OutputFolder& folder, const maps::CSurfelMap& map) {
  if (!m_params.enabled) return;
  // The final map's table (no renumbering: the map is const here).
  segmentation::SegmentTable& segments = m_published.tableToWrite();
  segments.compute(map.store().arrays());
  const maps::SurfelArrays a = map.store().arrays();
  std::size_t stable = 0;
  for (int i = 0; i < a.size; ++i) stable += a.alive(i) && a.stable(i);
  m_stable_final = (long long)stable;
  nlohmann::json segs = nlohmann::json::array();
  const auto vec = [](const Eigen::Vector3d& v) { return nlohmann::json{v.x(), v.y(), v.z()}; };
  for (const segmentation::SegmentStats& s : segments.segments()) {
    nlohmann::json axes = nlohmann::json::array(), upright = nlohmann::json::array();
    for (int k = 0; k < 3; ++k) axes.push_back(vec(s.axes.col(k)));
    for (int k = 0; k < 2; ++k) upright.push_back(vec(s.upright_axes.col(k)));
    segs.push_back({{"id", s.id},
                    {"surfels", s.surfels},
                    {"stable_surfels", s.stable_surfels},
                    {"centroid", vec(s.centroid)},
                    {"axes", axes},
                    {"extents_m", vec(s.extents)},
                    {"upright_axes", upright},
                    {"upright_extents_m", vec(s.upright_extents)},
                    {"bbox_min", vec(s.bbox_min)},
                    {"bbox_max", vec(s.bbox_max)},
                    {"last_seen_s", s.last_seen}});
  }
  nlohmann::json out;
  out["comment"] =
      "rasm segment table (section III): world frame, metres; axes are the PCA directions (unit, "
      "by "
      "decreasing variance), extents the spread of the surfel centres along them (1st-99th "
      "percentile); "
      "upright_axes / upright_extents_m: the two horizontal principal directions and z (z up); "
      "last_seen_s is map time";
  out["segments"] = segs;
  out["stable_surfels"] = stable;
  out["label_changes_stable"] = m_label_changes_stable;
  folder.writeText("segments.json", out.dump(1) + "\n");
  folder.write("map_segments.ply", [&](const std::string& part) {
    maps::writeSurfelPly(map.store(), part, false, maps::SurfelColouring::Segment);
  });
}

}  // namespace rasm::pipeline
