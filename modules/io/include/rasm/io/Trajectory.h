#pragma once
// Camera trajectories and the TUM RGB-D trajectory file format: one pose per line,
// "timestamp tx ty tz qx qy qz qw" (T_world_cam, optical camera frame, metres, unit quaternion
// of the rotation), '#' comments. Timestamps are written with "%.6f" (microseconds of UNIX
// time), translations with 9 decimals, quaternions with 9 decimals.

#include <Eigen/Geometry>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace rasm::io {

struct StampedPose {
  double timestamp_s = 0.0;
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
};

using Trajectory = std::vector<StampedPose>;

/// Reads a TUM trajectory. Separators may be spaces, tabs or commas (as evaluate_ate.py accepts).
/// Quaternions are normalised; a zero or non-finite quaternion, a line without 8 numbers or a
/// missing file throw InputError naming "file:line". The result is sorted by time.
Trajectory readTumTrajectory(const std::string& path);

/// The TUM text of `traj`: each line of `header_comment` as a "# " comment, the column names, one
/// line per pose.
std::string tumTrajectoryText(const Trajectory& traj, const std::string& header_comment = "");
/// Writes tumTrajectoryText atomically (rasm/core/AtomicFile.h). Throws InputError when the file
/// cannot be written.
void writeTumTrajectory(const std::string& path, const Trajectory& traj,
                        const std::string& header_comment = "");

/// One TUM line (no newline).
std::string formatTumLine(const StampedPose& p);

/// Pose at time t: linear interpolation of the translation and slerp of the rotation between the
/// samples bracketing t, when the nearest sample is within max_dt_s (the benchmark's association
/// tolerance); the nearest sample when t lies outside the trajectory but within max_dt_s of its
/// end; std::nullopt otherwise. `traj` must be sorted by time.
std::optional<Eigen::Isometry3d> interpolatePose(const Trajectory& traj, double t,
                                                 double max_dt_s = 0.02);

/// Appends poses to a TUM file as they come (flushed per line), for long runs.
class TumTrajectoryWriter {
 public:
  explicit TumTrajectoryWriter(const std::string& path, const std::string& header_comment = "");
  ~TumTrajectoryWriter();
  TumTrajectoryWriter(const TumTrajectoryWriter&) = delete;
  TumTrajectoryWriter& operator=(const TumTrajectoryWriter&) = delete;
  void write(const StampedPose& p);
  void close();

 private:
  std::FILE* f_ = nullptr;
  std::string path_;
};

}  // namespace rasm::io
