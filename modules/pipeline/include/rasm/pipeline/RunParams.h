#pragma once
// Params of the run itself: where frames come from ([source]), what the Mapper does around the
// stages ([mapper]) and what is written ([output]). Stage params live in their modules
// ([tracking] in tracking, [fusion] in fusion, [sim] in sim, ...).

#include <mrpt/config/CLoadableOptions.h>

#include <Eigen/Geometry>
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

/// [robot]: the platform the camera rides on, for the odometry prior of tracking:
/// the camera's mounting pose on the base and the wheel odometry's noise. Used when the source
/// gives odometry (the simulated robot's CObservationOdometry in its rawlogs, later the
/// Segway's); hand-held sources have none and track with the motion model alone.
/// Base frame: x forward, y left, z up, on the floor at the rotation centre (MRPT's planar-robot
/// convention). The defaults are the simulated robot's mount ([sim_robot] camera_x_m,
/// camera_height_m, camera_pitch_deg), so its rawlogs track without an INI.
struct TRobotParams : mrpt::config::CLoadableOptions {
  /// The robot the camera rides on: auto (the simulated robot of a [source] type = sim robot
  /// spec, none otherwise), none (hand-held or a replay: nothing to drive, no exploration), sim
  /// (the simulator's), segway_rmp (a Segway RMP over UDP, section [segway_rmp]: its odometry
  /// stamps each live frame; docs/hardware.md).
  std::string type = "auto";
  bool use_odometry = true;  ///< false: ignore the source's odometry
  // Camera mount: position (m) and yaw, pitch (positive = looking up), roll (deg) of the camera's
  // viewing direction in the base frame.
  double camera_x_m = 0.10, camera_y_m = 0.0, camera_z_m = 0.55;
  double camera_yaw_deg = 0.0, camera_pitch_deg = -10.0, camera_roll_deg = 0.0;
  // Odometry noise of one frame's increment (d m travelled, a rad turned): standard deviations
  // sigma_xy = odometry_sigma_xy_m + odometry_sigma_xy_per_sqrt_m sqrt(d) along x and y, and
  // sigma_yaw = odometry_sigma_yaw_deg + odometry_sigma_yaw_per_sqrt_rad sqrt(a) [rad]
  // + odometry_sigma_yaw_per_sqrt_m sqrt(d) [rad]: random walks as the simulated robot's
  // ([sim_robot] odo_sigma_*), twice its values, plus a floor.
  double odometry_sigma_xy_m = 0.0005;
  double odometry_sigma_xy_per_sqrt_m = 0.02;
  double odometry_sigma_yaw_deg = 0.05;
  double odometry_sigma_yaw_per_sqrt_rad = 0.04;
  double odometry_sigma_yaw_per_sqrt_m = 0.01;
  /// The noise model of the odometry's heading: "wheels" (the random walks above) or "gyro" (a
  /// yaw-rate gyro's: one increment's yaw sigma is odometry_sigma_yaw_deg + gyro_sigma_yaw_per_rad
  /// x the turn (rad), twice the simulated gyro's 0.2% scale error). Wheels by default, also
  /// for the simulated robot whose heading is a gyro's ([sim_robot] odometry_heading): with the
  /// gyro's tight sigmas max_odometry_sigmas refuses the frames in which ICP turns the camera
  /// back onto the map after a heading error, and the world-frame panel lost more frames and
  /// more coverage than it gained in silent frames (docs/results-worldframe.md "A gyro").
  /// "gyro_when_degenerate": the wheels' sigmas, except in max_odometry_sigmas's check of a
  /// frame whose geometry leaves a direction free (MotionPrior::odometry_information_degenerate),
  /// where the gyro's hold: ICP may re-align the camera where the data constrain the heading,
  /// and may not slip where they do not.
  std::string odometry_heading = "wheels";
  double gyro_sigma_yaw_per_rad = 0.004;
  /// A ground robot's base stays on the floor: the increment's height, roll and pitch have these
  /// standard deviations (bumps, suspension).
  double odometry_sigma_z_m = 0.005;
  double odometry_sigma_tilt_deg = 0.3;
  /// Heading drift test (OdometryPrior::addHeadingResidual): over this many frames, the sum of
  /// the tracked-minus-odometry heading differences may reach heading_drift_max_sigmas standard
  /// deviations of the summed odometry noise; beyond, the frame is not fused (prior_conflict)
  /// and the pose takes the odometry's heading. 0 sigmas = off.
  int heading_drift_window_frames = 30;
  double heading_drift_max_sigmas = 3.0;
  /// Constrain the camera to the SE(2) motion of a ground robot: every tracked pose is projected
  /// to the floor plane of the first frame's base (fixed height, roll and pitch of the mount).
  bool planar_motion = false;
  /// The floor as an absolute measurement (OdometryPrior::floorMeasurement): for a base on a
  /// flat floor the camera's height above the first frame's floor and its roll and pitch are the
  /// mount's, whatever the map did. With odometry, the prior ICP fuses then takes x, y and yaw
  /// from the odometry increment (relative) and height, roll and pitch from the mount on the
  /// first floor (absolute) with the sigmas below. Soft: the data still weigh in, unlike
  /// planar_motion. On by default: on the simulated robot it holds the floor within the
  /// floor_target_* with the horizontal error no larger (docs/slam-eval.md "Floor prior").
  bool floor_prior = true;
  /// Height (m) and roll/pitch (deg) standard deviations of the floor measurement. Tighter than
  /// a real floor's unevenness (about 1 cm, 0.2 deg) because ICP weighs the map-relative data as
  /// if the map had no error ([tracking] prior_pixel_sigma_m over thousands of inliers): at a
  /// real floor's sigmas the height still drifts; at these it stays within floor_target_*.
  double floor_prior_sigma_z_m = 0.002;
  double floor_prior_sigma_tilt_deg = 0.05;
  /// Per-frame drift flag: a tracked camera with odometry more than this far above or below the
  /// mount's height over the first frame's floor, or tilted more than this from the mount, is
  /// counted in report.json (frames_off_floor): the map's floor has drifted (measured: 5-9 cm of
  /// height and 2-3 deg of tilt over simulated robot runs, with every frame agreeing with the
  /// map). It is reported, not refused: later frames agree with the drifted map. 0 = off.
  double floor_max_height_m = 0.03;
  double floor_max_tilt_deg = 1.5;
  /// Run-level floor drift (report.json floor_drift, the run's warning): the map's floor counts
  /// as drifted when more than floor_target_max_fraction of the tracked frames with odometry
  /// have their camera further than floor_target_height_m from the mount's height or tilted more
  /// than floor_target_tilt_deg. The targets are those a map must meet for surfaces fused a few
  /// centimetres off not to count as unseen (docs/slam-eval.md "Floor drift").
  double floor_target_height_m = 0.015;
  double floor_target_tilt_deg = 0.15;
  double floor_target_max_fraction = 0.05;

  /// T_base_cam of the mount (optical camera frame in the base frame).
  Eigen::Isometry3d T_base_cam() const;
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
