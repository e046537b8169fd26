#pragma once
// Section IV as a stage of the Mapper, after fuse (Mapper::assemble):
//   process      fuses the detector results that arrived (each with the L^p of the frame it was
//                computed on: association by IoU, Bayes update of the segment's surfels), then
//                offers every n-th fused frame to the detector workers (DetectorWorker.h: a busy
//                detector skips the frame, counted; one that throws is disabled and reported);
//   finishRun    waits for the detections in flight and fuses them.
// The L^p of frames in flight follow the segmentation's merges and renumbering (the renamings
// the SegmentLayer publishes), so a late result lands on the segments its pixels belong to now.
// Sections [classification] and one per detector ([sim_detector], [dnn_detector], [zero_shot]);
// the simulator's detector is added to classification's DetectorSections here (SimDetector.h).
// The object layer (classification/ObjectMap.h, section [objects]) follows every fused result
// (views, detections, class evidence) and the relabelling, and regroups the segments into objects
// after each batch of results.
// Outputs: objects.json (the objects: id, segments, class histogram, existence probability,
// frames, boxes, pose hint; the other classified segments with the reason),
// classes.json (the map's class list), map_classes.ply (coloured by class; MappingRun writes
// map_classes.3Dscene with [output] write_3dscene, next to map_segments.3Dscene).

#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <vector>

#include "rasm/classification/ClassList.h"
#include "rasm/classification/DetectorFactory.h"
#include "rasm/classification/DetectorWorker.h"
#include "rasm/classification/ObjectMap.h"
#include "rasm/classification/ObjectVerdict.h"
#include "rasm/classification/PoseConsensus.h"
#include "rasm/classification/TClassificationParams.h"
#include "rasm/classification/TObjectParams.h"
#include "rasm/core/CameraIntrinsics.h"
#include "rasm/pipeline/MapperStage.h"
#include "rasm/pipeline/SegmentLayer.h"

namespace rasm::sim {
class RayScene;
}

namespace rasm::pipeline {

class ClassificationStage : public MapperStage {
 public:
  enum Part { kFuse = 0 };
  /// `segments`: what the segmentation publishes (may be null: no segments, nothing fused); it
  /// must outlive the stage.
  explicit ClassificationStage(SegmentLayer* segments);
  ~ClassificationStage() override;

  std::vector<ParamsSection> sections() override;
  void configure(const TMapperParams& mapper) override;
  bool writesMap() const override { return true; }  ///< class evidence of surfels
  void process(FrameContext& ctx, maps::CSurfelMap& map) override;
  void finishRun(maps::CSurfelMap& map) override;
  void csvColumns(std::vector<std::string>& columns) const override;
  void csvValues(const FrameContext& ctx, CsvRow& row) const override;
  void report(nlohmann::json& rep) const override;
  void writeOutputs(OutputFolder& out, const maps::CSurfelMap& map) override;
  /// classes_legend.png: the classes that are some stable surfel's best, by surfel count.
  void writeClassLegend(OutputFolder& out, const maps::CSurfelMap& map) const;

  /// Adds a detector besides the configured ones (tests, programs embedding the Mapper); before
  /// the first frame.
  void addDetector(std::unique_ptr<classification::Detector> detector);
  /// The simulator's scene for the simulated detector's occlusion test (before the first frame).
  void setSimScene(const sim::RayScene* scene) { m_sim_scene = scene; }
  /// Resolves [classification] detectors = auto and threaded = auto for the run's source
  /// (TClassificationParams::resolveAuto) before the first frame, so that config.ini records
  /// what ran; unresolved at the first frame, they follow whether a simulator scene was set.
  void resolveAuto(bool simulated_source);
  const classification::TClassificationParams& params() const { return m_params; }
  const classification::ClassList& classList() const { return m_classes; }
  /// Whether any class evidence has been fused into the map (the class map has something to show).
  bool fusedAnyEvidence() const { return m_surfel_updates > 0; }
  /// The class name of every segment of an object reported now (objects.json's "objects": the
  /// object layer's last grouping, its segments renamed by the relabelling since), by segment id.
  std::map<std::uint32_t, std::string> segmentClassNames(const maps::CSurfelMap& map) const;
  /// The object layer (its objects are those of the last batch of results fused).
  const classification::ObjectMap& objectMap() const { return m_object_map; }
  /// The objects objects.json would list now ({"objects": [...]} as in objects.json: class,
  /// probability, oriented box, ...), from the object layer's last grouping (the live view draws
  /// them while the run goes).
  nlohmann::json reportedObjects() const;
  /// Detections fused per segment so far (follows relabelling).
  const std::map<std::uint32_t, int>& detectionsPerSegment() const { return m_fused_per_segment; }

 private:
  /// Regroups the object layer with the segment table as it is now.
  void updateObjects();
  /// objects.json's entry of one object, and of one segment that is not part of a reported one.
  nlohmann::json objectEntry(const classification::MapObject& o) const;
  nlohmann::json segmentEntry(std::uint32_t segment, const classification::MapObject& object) const;
  /// L^p of a frame whose detections are still running.
  struct Pending {
    Image<std::uint32_t> labels;
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();  ///< the frame's pose
    CameraIntrinsics intrinsics;
    int outstanding = 0;  ///< workers that took the frame and have not returned
  };
  struct PoseRecord {
    classification::PoseHint pose;
    int class_id = 0;
    float score = 0.f;
  };
  void startWorkers(maps::CSurfelMap& map);
  void fuseArrived(maps::CSurfelMap& map);
  void fuseResult(const classification::DetectorResult& r, Pending& p, maps::CSurfelMap& map);
  /// A detection with a template pose through the pose consensus (PoseConsensus.h): what it
  /// releases, its own evidence among them only once views agree.
  classification::PoseConsensus::Released consensus(
      const classification::Detection& det, std::uint32_t segment, int class_id,
      std::vector<classification::SegmentEvidence> items, const Pending& p, std::size_t frame,
      std::vector<std::int32_t> surfels);
  /// The surfels of each segment a posed detection of `r` went to (for the ones held; at most
  /// 50 000 per segment, else none: that segment's evidence goes to the segment at release).
  std::map<std::uint32_t, std::vector<std::int32_t>> surfelsOfPosedSegments(
      const classification::DetectorResult& r,
      const std::vector<classification::Association>& assoc, const maps::CSurfelMap& map) const;
  /// Fuses held detections released now: into the surfels they saw (or their segment), and into
  /// the object layer as detections of `segment` in their own frames.
  void fuseReleasedEarlier(std::vector<classification::ReleasedDetection>& earlier,
                           std::uint32_t segment, int worker, maps::CSurfelMap& map);
  void relabel(const std::vector<std::uint32_t>& table);

  const SegmentLayer* m_segments;
  classification::TClassificationParams m_params;
  classification::TObjectParams m_object_params;
  classification::ObjectMap m_object_map;
  classification::PoseConsensus m_pose_consensus;
  /// [sim_detector] (sim::TDetectorParams), a kind of m_detector_sections; null in a build
  /// without the simulator.
  std::unique_ptr<mrpt::config::CLoadableOptions> m_sim_detector;
  classification::DetectorSections m_detector_sections;
  const sim::RayScene* m_sim_scene = nullptr;
  classification::ClassList m_classes;
  std::vector<std::unique_ptr<classification::DetectorWorker>> m_workers;
  std::vector<std::vector<int>> m_class_ids;  ///< per worker: detector class index -> map id
  std::vector<std::string> m_warnings;
  std::vector<std::unique_ptr<classification::Detector>> m_extra_detectors;
  bool m_started = false;
  std::map<std::size_t, Pending> m_pending;  ///< by frame index
  std::size_t m_frames_seen = 0;
  // Run totals (report.json) and per-frame counts (frames.csv).
  std::size_t m_results = 0, m_detections = 0, m_associated = 0, m_surfel_updates = 0,
              m_dropped_updates = 0, m_frames_offered = 0;
  int m_frame_detections = 0, m_frame_associated = 0;
  std::map<std::uint32_t, int> m_fused_per_segment;
  std::map<std::uint32_t, PoseRecord> m_pose_per_segment;
  /// Named objects of the final map by class (writeOutputs; report.json "objects_by_class").
  std::map<std::string, int> m_objects_by_class;
  bool m_objects_counted = false;
};

}  // namespace rasm::pipeline
