#pragma once
// Section III as a stage of the Mapper, between index_map and fuse (Mapper::assemble):
//   process      edge map -> connected components L_t (GeometricSegmenter), L^r from the index
//                map at T_t and label propagation -> L^p into FrameContext::labels, which fusion
//                uses for the segment weights and the labels of new surfels;
//   finishFrame  (after fusion) the merge confidence Psi, merges into the smaller label, and every
//                remap_every_n_frames frames the dense renumbering of labels and the segment
//                statistics (SegmentTable).
// What it publishes (the segment table, every renaming of segment ids) goes into the Mapper's
// SegmentLayer, which the stages after it read. Section [segmentation]. Outputs: segments.json (the
// segment table) and map_segments.ply (the map coloured by segment). report.json "segmentation":
// segments, merges, label changes of stable surfels.

#include <cstdint>

#include "rasm/pipeline/MapperStage.h"
#include "rasm/pipeline/SegmentLayer.h"
#include "rasm/segmentation/GeometricSegmenter.h"
#include "rasm/segmentation/LabelPropagation.h"
#include "rasm/segmentation/MergeConfidence.h"
#include "rasm/segmentation/SegmentTable.h"

namespace rasm::pipeline {

class SegmentationStage : public MapperStage {
 public:
  enum Part { kEdges = 0, kComponents, kPropagation, kMerge };
  /// `published`: where the table and the renamings go (the Mapper's; it outlives the stage).
  explicit SegmentationStage(SegmentLayer& published)
      : MapperStage("segmentation",
                    {"seg_edges", "seg_components", "seg_propagation", "seg_merge"}),
        m_published(published) {}

  std::vector<ParamsSection> sections() override { return {{"segmentation", &m_params}}; }
  void configure(const TMapperParams& mapper) override;
  bool writesMap() const override { return true; }  ///< merges relabel surfels (finishFrame)
  void process(FrameContext& ctx, maps::CSurfelMap& map) override;
  void finishFrame(FrameContext& ctx, maps::CSurfelMap& map) override;
  void csvColumns(std::vector<std::string>& columns) const override;
  void csvValues(const FrameContext& ctx, CsvRow& row) const override;
  void report(nlohmann::json& rep) const override;
  void writeOutputs(OutputFolder& out, const maps::CSurfelMap& map) override;

  const segmentation::TSegmentationParams& params() const { return m_params; }
  const segmentation::FrameSegments& lastSegments() const { return m_segmenter.last(); }
  const segmentation::Propagation& lastPropagation() const { return m_prop; }
  const segmentation::SegmentTable& table() const { return m_published.table(); }
  const segmentation::MergeConfidence& mergeConfidence() const { return m_psi; }
  /// Recomputes the segment table from the map now (and renumbers labels densely).
  void refreshTable(maps::CSurfelMap& map);

 private:
  void applyRelabelling(maps::CSurfelMap& map, const std::vector<std::uint32_t>& table);
  /// Merges the due pairs (union into the smallest label); returns the merges applied.
  int merge(maps::CSurfelMap& map, const std::vector<segmentation::MergeConfidence::Pair>& due);

  segmentation::TSegmentationParams m_params;
  segmentation::GeometricSegmenter m_segmenter;
  /// The frame's grey levels at the segmentation level (colour_edges; empty when off or the
  /// source has no colour).
  Image<std::uint8_t> m_intensity;
  const Image<std::uint8_t>* intensityAt(const RgbdFrame& frame, int width, int height);
  segmentation::Propagation m_prop;
  segmentation::MergeConfidence m_psi;
  SegmentLayer& m_published;
  std::uint32_t m_next_label = 1;
  bool m_ran = false;     ///< this frame was segmented
  bool m_seeded = false;  ///< m_next_label is above every label of the map (loaded maps)
  std::uint64_t m_frames = 0;
  // Per frame (frames.csv) and run totals (report.json).
  int m_frame_merges = 0;
  std::size_t m_merges = 0, m_label_changes_stable = 0, m_psi_max = 0;
  long long m_stable_final = -1;  ///< stable surfels of the final map (writeOutputs), -1 unknown
};

}  // namespace rasm::pipeline
