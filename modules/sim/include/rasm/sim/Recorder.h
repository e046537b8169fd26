#pragma once
// The recorder behind `rasm sim record`: renders a world along a scripted trajectory and writes
//  - <out>.rawlog: CObservation3DRangeScan per frame (+ CObservationOdometry for the ground
//    robot) through rasm::io::RawlogWriter, sensor pose = ground truth;
//  - <out stem>_groundtruth.txt: T_world_cam per frame (TUM format, optical frame);
//  - <out stem>_labels/instance_NNNNNN.png and class_NNNNNN.png (16-bit PNG, frame index
//    NNNNNN) and <out stem>_labels/classes.json (class and instance tables).
// Same world, spec, options and seed give byte-identical files. Timestamps are simulated:
// frame i is at i / rate_hz seconds.

#include <cstdint>
#include <functional>
#include <map>
#include <string>

#include "rasm/core/RgbdFrame.h"
#include "rasm/sim/Trajectory.h"
#include "rasm/sim/World.h"

namespace rasm::sim {

struct RecordOptions {
  std::string world;            ///< shipped name or YAML path
  std::string trajectory_spec;  ///< shipped name or YAML path
  std::string out_rawlog;       ///< output path (.rawlog)
  std::uint64_t seed = 0;
  /// [sim_sensor] / [sim_robot] keys applied after the spec's own `sensor:` / `robot:` blocks
  /// (the command line's --noise and --camera end up here).
  std::map<std::string, std::string> sensor_overrides, robot_overrides;
  bool write_labels = true;
  bool external_images = false;  ///< PNG images next to the rawlog (MRPT external storage)
  /// Stop after this many frames (< 0: as the spec says). For tests and previews.
  long long max_frames = -1;
  bool progress = false;  ///< frames, rate and ETA on stderr
};

struct RecordResult {
  std::size_t frames = 0;
  double duration_s = 0.0;  ///< simulated
  std::string rawlog_path, groundtruth_path, labels_dir;
  bool robot_collided = false;  ///< the ground robot hit something (recording stopped there)
};

/// Loads world and spec and records. Throws InputError on bad input; without the io module the
/// rawlog cannot be written and this throws std::runtime_error.
RecordResult recordSequence(const RecordOptions& opt);

/// Records from an already loaded world and spec (tests). `on_frame`, when set, sees every
/// rendered frame before it is written.
RecordResult recordSequence(const World& world, const TrajectorySpec& spec,
                            const RecordOptions& opt,
                            const std::function<void(const RgbdFrame&)>& on_frame = {});

}  // namespace rasm::sim
