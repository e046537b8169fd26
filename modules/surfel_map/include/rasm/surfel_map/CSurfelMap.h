#pragma once
// rasm::maps::CSurfelMap: the global semantic and geometric surfel map M of II-A as an MRPT
// metric map (DESIGN.md "The surfel map"):
//  - serializable (rawlogs, .simplemap-style files), versioned, every attribute round-trips;
//  - creatable from an INI file through MRPT's map-definition registry:
//        [MAP]
//        surfelMap_count = 1
//        [MAP_surfelMap_00_creationOpts]   n_classes, view_bins_azimuth, view_bins_elevation,
//                                          block_size_m
//        [MAP_surfelMap_00_insertOpts]     any [fusion] key (rasm::fusion::TFusionParams)
//        [MAP_surfelMap_00_likelihoodOpts] sigma_m, decimation, max_depth_m
//        [MAP_surfelMap_00_renderOpts]     colouring, point_size, stable_only, min_confidence
//    then TSetOfMetricMapInitializers::loadFromConfigFile(cfg, "MAP") + CMultiMetricMap, and
//    multimap.mapByClass<rasm::maps::CSurfelMap>();
//  - visualizable (getVisualizationInto: coloured point cloud for SceneViewer3D / RawLogViewer);
//  - insertObservation(CObservation3DRangeScan) fuses the frame at the given pose (no tracking)
//    through the fusion module (SurfelFrameInserter.h; link rasm::fusion);
//  - holds the relocalisation keyframes (Keyframe.h; made and used by rasm::tracking::Relocaliser)
//    and serializes them with the surfels, so a reloaded map can relocalise a camera.
// Storage, rendering and fusion work on the MRPT-free SurfelStore returned by store().

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/CMetricMap.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "rasm/surfel_map/Keyframe.h"
#include "rasm/surfel_map/MapExport.h"
#include "rasm/surfel_map/SurfelStore.h"

namespace rasm::maps {

class SurfelFrameInserter;

/// One class of the map's class list (IV): class id k + 1 is classes()[k]. `source` says where
/// the name came from ("coco": a COCO-trained detector's list; "rasm": the project's own classes;
/// otherwise the detector that added it, e.g. "zero_shot").
struct MapClass {
  std::string name;
  std::string source;
  bool operator==(const MapClass& o) const { return name == o.name && source == o.source; }
};

class CSurfelMap : public mrpt::maps::CMetricMap {
  DEFINE_SERIALIZABLE(CSurfelMap, rasm::maps)

 public:
  /// Layout of the storage, fixed at creation ([..._creationOpts]).
  struct TCreationOptions : public mrpt::config::CLoadableOptions {
    int n_classes = kDefaultNumClasses;  ///< class ids 1..n_classes (<= 255; ClassEvidence.h)
    int view_bins_azimuth = 8;
    int view_bins_elevation = 2;
    double block_size_m = 0.5;

    SurfelStoreOptions toStoreOptions() const;
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
  };

  /// Fusion parameters for insertObservation(): the keys of the section are [fusion] keys
  /// (rasm::fusion::TFusionParams), kept as INI text and parsed strictly when the inserter is
  /// created, so unknown keys are reported then (naming the section).
  struct TInsertionOptions : public mrpt::config::CLoadableOptions {
    std::vector<std::pair<std::string, std::string>> fusion_keys;
    std::string source = "CSurfelMap insertion options";

    /// "[fusion]\nkey = value\n..." as the inserter factory expects.
    std::string fusionIniText() const;
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
  };

  /// computeObservationLikelihood(): per-pixel Gaussian on the difference between the observed
  /// depth and the depth rendered from the map at the observation pose, on a decimated grid.
  struct TLikelihoodOptions : public mrpt::config::CLoadableOptions {
    double sigma_m = 0.03;
    int decimation = 8;
    double max_depth_m = 5.0;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
  };

  /// getVisualizationInto() and .3Dscene export.
  struct TRenderingOptions : public mrpt::config::CLoadableOptions {
    SurfelVisualOptions visual;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
  };

  CSurfelMap();
  explicit CSurfelMap(const TCreationOptions& creation);
  CSurfelMap(const CSurfelMap& o);  ///< copies surfels, keyframes and options, not the inserter
  CSurfelMap& operator=(const CSurfelMap& o);
  ~CSurfelMap() override;

  const TCreationOptions& creationOptions() const { return m_creation; }
  /// Drops all surfels and changes the layout (keyframes are kept: clear() drops them too).
  void resetLayout(const TCreationOptions& creation);

  TInsertionOptions insertionOptions;
  TLikelihoodOptions likelihoodOptions;
  TRenderingOptions renderingOptions;

  SurfelStore& store() { return m_store; }
  const SurfelStore& store() const { return m_store; }
  SurfelArrays arrays() { return m_store.arrays(); }
  SurfelArrays arrays() const { return m_store.arrays(); }
  int size() const { return m_store.size(); }
  int append(const Surfel& s) { return m_store.append(s); }
  /// Removal with compaction: see SurfelStore::remove for the index invalidation rule.
  void remove(std::vector<int> surfels, std::vector<std::pair<int, int>>* moved = nullptr) {
    m_store.remove(std::move(surfels), moved);
  }

  /// Relocalisation keyframes (rasm::tracking::Relocaliser::maybeAddKeyframe appends to it),
  /// serialized with the map (version 1), emptied by clear().
  std::vector<Keyframe>& keyframes() { return m_keyframes; }
  const std::vector<Keyframe>& keyframes() const { return m_keyframes; }

  /// The names of the class ids of the surfels' class evidence (id k + 1 = classes()[k]),
  /// serialized with the map (version 3); empty = not named yet (the classification stage fills
  /// it: rasm/classification/ClassList.h). Kept by clear(): it belongs to the layout.
  std::vector<MapClass>& classes() { return m_classes; }
  const std::vector<MapClass>& classes() const { return m_classes; }

  void saveToPly(const std::string& path, bool stable_only = false) const {
    writeSurfelPly(m_store, path, stable_only);
  }
  void saveTo3DScene(const std::string& path) const {
    writeSurfelScene(m_store, path, renderingOptions.visual);
  }

  // ---- mrpt::maps::CMetricMap ----
  bool isEmpty() const override { return m_store.empty(); }
  /// Writes "<prefix>.ply" (writeSurfelPly).
  void saveMetricMapRepresentationToFile(const std::string& filNamePrefix) const override;
  void getVisualizationInto(mrpt::opengl::CSetOfObjects& o) const override;
  std::string asString() const override;

 private:
  /// serializeFrom's parts: the layout (checked, then resetLayout), options and time origin;
  /// returns the stored class count. Then the surfel arrays, each checked as it is read.
  int32_t readLayoutAndOptions(mrpt::serialization::CArchive& in, uint8_t version,
                               const std::string& what);
  void readSurfelArrays(mrpt::serialization::CArchive& in, uint8_t version, int32_t nc,
                        const std::string& what);
  void internal_clear() override;
  /// CObservation3DRangeScan only (returns false for other types): the frame is fused at
  /// robotPose (+) obs.sensorPose without tracking.
  bool internal_insertObservation(
      const mrpt::obs::CObservation& obs,
      const std::optional<const mrpt::poses::CPose3D>& robotPose) override;
  double internal_computeObservationLikelihood(
      const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const override;
  bool internal_canComputeObservationLikelihood(const mrpt::obs::CObservation& obs) const override;

  TCreationOptions m_creation;
  SurfelStore m_store;
  std::vector<Keyframe> m_keyframes;
  std::vector<MapClass> m_classes;
  std::unique_ptr<SurfelFrameInserter> m_inserter;  ///< created on first insertion
  std::string m_inserter_ini;                       ///< the fusion INI text it was built from

 public:
  MAP_DEFINITION_START(CSurfelMap)
  TCreationOptions creationOpts;
  TInsertionOptions insertionOpts;
  TLikelihoodOptions likelihoodOpts;
  TRenderingOptions renderOpts;
  MAP_DEFINITION_END(CSurfelMap)
};

/// The class evidence of one surfel of a serialization version 0/1 map, whose row held n_classes
/// linear probabilities quantised to u8 (128 = the 0.5 prior): class index c becomes id c + 1,
/// L = logit(p) clamped (ClassEvidence.h), the kClassSlots of highest classEvidenceRank kept (lower
/// id on ties), so the old best class stays the best.
/// Throws std::invalid_argument when a class index >= 255 holds evidence. (CSurfelMap reads old
/// maps through it; public for tests and converters.)
ClassEvidence convertLinearClassRow(const std::uint8_t* row, int n_classes);

}  // namespace rasm::maps
