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
#include <memory>
#include <string>
#include <vector>

#include "rasm/core/RgbdFrame.h"
#include "rasm/pipeline/FrameContext.h"
#include "rasm/pipeline/MapperStage.h"
#include "rasm/pipeline/RunParams.h"
#include "rasm/surfel_map/CSurfelMap.h"
#include "rasm/surfel_map/SurfelRenderer.h"

namespace rasm::pipeline {

class TrackingStage;

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
  /// frames.csv: the columns of the stages (index and timestamp first, timers last) and the row
  /// of the last frame processed.
  std::string csvHeader() const;
  std::string csvRow() const;
  /// Fields of the stages for report.json.
  void report(nlohmann::json& rep) const;
  /// The stages' own output files in `dir`.
  void writeOutputs(const std::string& dir);

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
  /// Renders the map's colour / segment view at a pose (previews, annotated rawlogs).
  void renderView(const Eigen::Isometry3d& T_world_cam, const CameraIntrinsics& K, maps::RenderedMaps& out);

 private:
  /// Builds the stage list: the one place a new stage is added.
  void assemble();
  /// Timer slots of the stages (after any change of the list).
  void indexTimers();
  /// Checks the sections together, configures every stage and creates the map.
  void configure();

  TMapperParams m_mapper;
  maps::CSurfelMap::TCreationOptions m_map_options;
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
