#pragma once
// Params of the run itself: where frames come from ([source]), what the Mapper does around the
// stages ([mapper]) and what is written ([output]). Stage params live in their modules
// ([tracking] and [robot] in tracking, [fusion] in fusion, [sim] in sim, ...).

#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace rasm::pipeline {

/// [source]: the frame stream of a run.
struct TSourceParams : mrpt::config::CLoadableOptions {
  /// sim | rawlog | tum | 7scenes | auto (auto: rawlog file, TUM or 7-Scenes folder by inspection)
  /// | openni2 (a live camera, section [openni2]; docs/hardware.md)
  std::string type = "sim";
  std::string path;     ///< rawlog file or dataset folder (not for sim, openni2)
  int max_frames = 0;   ///< 0 = all
  int start_frame = 0;  ///< frames before this are skipped
  int frame_step = 1;   ///< use every n-th frame
  /// Optional TUM trajectory to evaluate against (ATE in report.json) instead of the source's
  /// own ground truth (rawlogs without poses, e.g. converted elsewhere). Frames without a pose
  /// of their own take it (io::GroundTruthFrameSource): a run replayed from its annotated.rawlog
  /// with its groundtruth.txt starts at the true pose and reports its world-frame error.
  std::string groundtruth;
  /// Frames read ahead on a separate thread (io::PrefetchingFrameSource) while the previous one
  /// is mapped; 0 = read in the mapping thread.
  int prefetch_frames = 2;
  /// Read the frames into memory before mapping starts (io::PreloadedFrameSource; for benchmarks:
  /// frames/s then measures the mapping, not the decoding of the dataset's image files).
  /// ~2.2 MB per 640x480 frame. Replaces the read-ahead thread.
  bool preload = false;
  /// Upper bound of the preloaded frames' memory (MiB): a run over it stops before mapping.
  int preload_max_mib = 4096;
  /// Fault injection for robustness tests (kidnapping evaluation), as source frame
  /// index ranges "a-b" (inclusive, comma-separated; empty = none): frames in drop_frames are
  /// skipped (the camera jumps), frames in blank_frames get all-zero depth and black colour (a
  /// covered lens). Indices count every frame of the source, before start_frame / frame_step.
  std::string drop_frames;
  std::string blank_frames;
  /// Replays (rawlog, tum, 7scenes): offer frames at their timestamps, as a camera would; a frame
  /// that arrives while the mapper is busy is dropped (io::RealTimeFrameSource; report.json
  /// "real_time"). false: every frame at full speed (deterministic). Live sources (openni2) are
  /// real time whatever this says.
  bool real_time = false;

  /// Whether source frame `index` lies in the ranges of drop_frames / blank_frames.
  bool dropped(long long index) const;
  bool blanked(long long index) const;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// [mapper]: per-frame preprocessing around tracking and fusion (II-A).
struct TMapperParams : mrpt::config::CLoadableOptions {
  int pyramid_levels = 3;        ///< II-C: quarter, half, full resolution
  double min_depth_m = 0.3;      ///< measurements nearer than this are ignored
  double max_depth_m = 4.0;      ///< ... and further (Kinect-class noise grows with z^2)
  bool bilateral_filter = true;  ///< filter depth before computing normals (KinectFusion)
  double bilateral_sigma_space_px = 4.5;
  double bilateral_sigma_depth_m = 0.03;
  double normal_max_jump_rel = 0.05;  ///< neighbour depth jump that invalidates a normal
  /// Where poses come from: "tracked" (ICP, II-C) or "groundtruth" (the source's ground-truth
  /// pose of every frame, for evaluating the later stages apart from tracking; a frame without
  /// one is an error).
  std::string poses = "tracked";
  /// A previous run's map.surfelmap to continue in (`rasm run --map`): the camera is localised
  /// in it by relocalisation against its keyframes before anything is fused. Empty = new map.
  std::string load_map;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// [output]: the run's output folder and which files go in it.
struct TOutputParams : mrpt::config::CLoadableOptions {
  std::string dir = "rasm_out";
  bool write_ply = true;
  bool write_3dscene = true;
  /// mesh.ply (and mesh_classes.ply when any surfel carries a class): a triangle mesh of the map
  /// ([mesh], meshing/SurfelMesh.h)
  bool write_mesh = true;
  bool save_map = true;       ///< map.surfelmap: the CSurfelMap serialized for reloading
  bool write_rawlog = false;  ///< annotated.rawlog: input observations with estimated pose
  bool preview_png = true;    ///< preview.png: colour render of the map from the last pose
  bool floorplan = true;      ///< floorplan.png / floorplan.svg: the labelled plan (FloorPlan.h)
  /// A simulated source that is not explored: the objects carrying their class against the
  /// world's truth (SimObjectScore) every this many seconds of the sequence, into frames.csv
  /// objects_correct and plot_objects.png (0 = never). An exploring run measures them every
  /// [exploration] metrics_period_s instead.
  double objects_score_period_s = 1.0;
  /// A folder that is not empty (RunFolder.h OverwritePolicy): auto = reuse the folder of an
  /// earlier run (only its files are removed), refuse one holding other files; true (rasm run
  /// --force) = also write beside other files (left alone); false = only an empty or new folder.
  std::string overwrite = "auto";
  /// Messages shown on the console from this level up: debug, info, warning, error (`rasm run
  /// -v` / `-q`: debug / warning). run.log in the folder holds every message whatever this says.
  std::string log_level = "info";

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

}  // namespace rasm::pipeline
