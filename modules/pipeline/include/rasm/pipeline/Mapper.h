#pragma once
// The mapping front end of one frame (section II, III-V as they are added): an ordered list of
// stages (MapperStage.h) run over one FrameContext per frame. assemble() builds the list:
//   preprocess (II-A) -> tracking (II-C, odometry prior, relocalisation) -> index_map (II-D,
//   the map's 4x index map at T_t) -> fuse (II-B, II-D: update, add, carve, prune, merge)
// The known INI sections, config.ini, the timing table and the frames.csv columns come from the
// list. The Mapper owns the surfel map and its own sections [mapper] (preprocessing and depth
// range, shared by the stages) and [map] (the map's creation options).
//
//   Mapper mapper;                                 // defaults, or Mapper(ini, "my.ini")
//   for (frame : source) { FrameResult r = mapper.processFrame(frame); ... }
//   mapper.map().saveToPly("map.ply");

#include <mrpt/config/CConfigFileBase.h>

#include <Eigen/Geometry>
#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <thread>
#include <vector>

#include "rasm/core/ComputeOptions.h"
#include "rasm/core/RgbdFrame.h"
#include "rasm/pipeline/FrameContext.h"
#include "rasm/pipeline/MapperStage.h"
#include "rasm/pipeline/RunParams.h"
#include "rasm/pipeline/SegmentLayer.h"
#include "rasm/segmentation/SegmentTable.h"
#include "rasm/surfel_map/CSurfelMap.h"
#include "rasm/surfel_map/SurfelRenderer.h"

namespace rasm::pipeline {

class TrackingStage;

/// A consistent read-only copy of the map for other threads (exploration, V): the surfel store
/// (arrays and spatial index: SurfelRenderer renders from it) and the segment table, as they were
/// between two frames' map writes.
struct MapSnapshot {
  maps::SurfelStore store;
  std::vector<segmentation::SegmentStats> segments;  ///< as of the last table refresh
  std::uint64_t relabel_generation = 0;              ///< SegmentLayer::relabelGeneration()
  std::size_t frames = 0;                            ///< frames processed when it was taken
  double copy_ms = 0.0;                              ///< time the copy held the map lock
  double index_ms = 0.0;  ///< rebuilding the spatial index afterwards (no lock)
};

class Mapper {
 public:
  /// Every section at its defaults.
  Mapper();
  /// Every section of the Mapper and its stages loaded strictly from `ini` (InputError names
  /// `source`, the section and the key); other sections of `ini` are not looked at.
  Mapper(const mrpt::config::CConfigFileBase& ini, const std::string& source);
  ~Mapper();

  FrameResult processFrame(const RgbdFrame& frame);

  /// Inserts a stage before the stage named `before` (at the end when empty), at its params'
  /// defaults, configured at once: stages from outside the library (tests, experiments). Before
  /// the first frame; std::logic_error otherwise or when `before` is unknown. A stage of the
  /// product is added in assemble() instead.
  void addStage(std::unique_ptr<MapperStage> stage, const std::string& before = "");

  /// The INI sections of the Mapper ([mapper], [map]) and of its stages, in pipeline order.
  std::vector<ParamsSection> sections();
  std::vector<std::string> sectionNames() const;
  /// Every key of every section with its effective value, as INI sections.
  void saveParams(mrpt::config::CConfigFileBase& out) const;
  /// Timer names in FrameResult::ms order: each stage, its parts, then "total".
  const std::vector<std::string>& timerNames() const { return m_timers; }
  /// The stages' own timers in order (each holds its parts' time; they add up to the frame's
  /// work apart from the map lock wait).
  std::vector<std::string> stageTimerNames() const;
  /// frames.csv: the columns of the stages (index and timestamp first, timers last) and the row
  /// of the last frame processed.
  std::string csvHeader() const;
  std::string csvRow() const;
  /// Fields of the stages for report.json.
  void report(nlohmann::json& rep) const;
  /// The stages' own output files in the run's folder.
  void writeOutputs(OutputFolder& out);
  /// Ends a run: every stage's finishRun (work in flight lands in the map). Call after the last
  /// frame and before saving the map or writing outputs.
  void finishRun();

  /// The stage of type S (std::logic_error when the pipeline has none).
  template <typename S>
  S& stage() const {
    for (const auto& s : m_stages)
      if (auto* p = dynamic_cast<S*>(s.get())) return *p;
    throw std::logic_error("the Mapper has no such stage");
  }
  const std::vector<std::unique_ptr<MapperStage>>& stages() const { return m_stages; }

  const TMapperParams& mapperParams() const { return m_mapper; }
  maps::CSurfelMap& map() { return *m_map; }
  const maps::CSurfelMap& map() const { return *m_map; }
  /// The context of the last frame processed (its pyramid, index map, labels ...).
  const FrameContext& lastContext() const { return m_ctx; }
  std::size_t framesProcessed() const { return m_frames; }
  std::size_t framesLost() const { return m_lost; }
  std::size_t relocalisations() const;
  /// Replaces the map with one loaded from a .surfelmap file (a previous run's): the camera is
  /// then localised in it by relocalisation against its keyframes before anything is fused.
  /// Call before the first frame. Throws InputError when the file cannot be read.
  void loadMap(const std::string& path);
  /// Last good camera pose.
  const Eigen::Isometry3d& pose() const;
  /// Pose of the last frame processed (tracked or propagated while lost).
  const Eigen::Isometry3d& lastFramePose() const;
  /// A snapshot of the map, from any thread: copied under the map lock in shared mode, which the
  /// mapping thread holds exclusively only while stages write (writesMap(): index map, fusion,
  /// segmentation and every finishFrame); preprocessing and tracking read alongside the copy.
  /// The copy starts when the next write phase ends (or after 200 ms without one: the mapper is
  /// idle), so it runs during the mapping thread's read phase; the mapping thread waits only when
  /// a copy outlasts that phase (FrameResult::ms of timer "map_lock_wait"). Called from the
  /// mapping thread between frames (the deterministic exploration loop) it copies at once. Cost:
  /// docs/architecture.md.
  std::shared_ptr<const MapSnapshot> snapshot() const;
  /// The same into `out`, reusing its memory (a reader taking snapshots repeatedly saves the
  /// page faults of a fresh copy). Only the surfel arrays are copied under the lock; the spatial
  /// index is rebuilt after it is released, on the calling thread.
  void snapshotInto(MapSnapshot& out) const;
  /// A thinned snapshot for drawing (the live view): every k-th alive surfel, k = ceil(surfels /
  /// max_surfels), copied under the lock straight from the map (no full copy first) and not
  /// indexed; segments and frames as snapshotInto.
  void snapshotThinnedInto(MapSnapshot& out, int max_surfels) const;

  /// Renders the map's colour / segment view at a pose (previews, annotated rawlogs).
  void renderView(const Eigen::Isometry3d& T_world_cam, const CameraIntrinsics& K,
                  maps::RenderedMaps& out);

 private:
  /// The copy of snapshotInto (every surfel) or snapshotThinnedInto (max_surfels > 0), not indexed.
  void copySnapshot(MapSnapshot& out, int max_surfels) const;
  /// Builds the stage list: the one place a new stage is added.
  void assemble();
  /// Timer slots of the stages (after any change of the list).
  void indexTimers();
  /// Checks the sections together, configures every stage and creates the map.
  void configure();

  mutable std::shared_mutex m_map_mutex;  ///< exclusive while stages write the map
  // Write phases ended so far: snapshot() starts its copy right after one, at the start of the
  // mapping thread's read-only phase (preprocessing, tracking), so the copy rarely delays it.
  mutable std::mutex m_phase_mutex;
  mutable std::condition_variable m_phase_cv;
  std::uint64_t m_write_phases = 0;
  std::atomic<std::thread::id> m_mapping_thread{};  ///< the thread of the last processFrame
  int m_lock_timer = 0;                             ///< index of "map_lock_wait" in FrameResult::ms
  TMapperParams m_mapper;
  TComputeParams m_compute;  ///< [compute]: simd = false runs the kernel bodies alone
  maps::CSurfelMap::TCreationOptions m_map_options;
  SegmentLayer m_segments;  ///< section III's published table and renamings (before the stages:
                            ///< they hold it, so it outlives them)
  std::vector<std::unique_ptr<MapperStage>> m_stages;
  TrackingStage* m_tracking = nullptr;
  std::vector<std::string> m_timers;
  std::unique_ptr<maps::CSurfelMap> m_map;
  maps::SurfelRenderer m_renderer;
  FrameContext m_ctx;
  std::size_t m_frames = 0, m_lost = 0;
  double m_t0 = 0.0;  ///< timestamp of the first frame: surfel times are relative to it
};

}  // namespace rasm::pipeline
