#include "rasm/io/Trajectory.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "TextFiles.h"
#include "rasm/core/AtomicFile.h"
#include "rasm/core/Error.h"

namespace rasm::io {

Trajectory readTumTrajectory(const std::string& path) {
  const auto lines = detail::readFieldLines(path, "trajectory");
  Trajectory traj;
  traj.reserve(lines.size());
  static const char* names[8] = {"timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};
  for (const auto& l : lines) {
    if (l.fields.size() != 8)
      throwInputError(detail::where(path, l.number),
                      "expected 8 fields 'timestamp tx ty tz qx qy qz qw' (TUM format), got " +
                          std::to_string(l.fields.size()));
    double v[8];
    for (int k = 0; k < 8; ++k) v[k] = detail::parseDouble(l.fields[k], path, l.number, names[k]);
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    const double n = q.norm();
    if (!(n > 1e-9))
      throwInputError(detail::where(path, l.number), "quaternion (qx qy qz qw) has zero norm");
    q.coeffs() /= n;
    StampedPose p;
    p.timestamp_s = v[0];
    p.T_world_cam.setIdentity();
    p.T_world_cam.linear() = q.toRotationMatrix();
    p.T_world_cam.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    traj.push_back(p);
  }
  std::stable_sort(traj.begin(), traj.end(), [](const StampedPose& a, const StampedPose& b) {
    return a.timestamp_s < b.timestamp_s;
  });
  return traj;
}

std::string formatTumLine(const StampedPose& p) {
  Eigen::Quaterniond q(p.T_world_cam.linear());
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();  // canonical sign, stable diffs between runs
  const Eigen::Vector3d t = p.T_world_cam.translation();
  char buf[256];
  std::snprintf(buf, sizeof(buf), "%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f", p.timestamp_s, t.x(),
                t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
  return buf;
}

static std::FILE* openForWrite(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f)
    throwInputError("trajectory " + path,
                    std::string("cannot open for writing: ") + std::strerror(errno));
  return f;
}

std::string tumTrajectoryText(const Trajectory& traj, const std::string& header_comment) {
  std::string text;
  std::size_t pos = 0;
  while (pos < header_comment.size()) {
    const std::size_t e = header_comment.find('\n', pos);
    text += "# " + header_comment.substr(pos, e == std::string::npos ? e : e - pos) + "\n";
    if (e == std::string::npos) break;
    pos = e + 1;
  }
  text += "# timestamp tx ty tz qx qy qz qw\n";
  for (const auto& p : traj) text += formatTumLine(p) + "\n";
  return text;
}

void writeTumTrajectory(const std::string& path, const Trajectory& traj,
                        const std::string& header_comment) {
  try {
    writeFileAtomic(path, tumTrajectoryText(traj, header_comment));
  } catch (const std::runtime_error& e) {
    throwInputError("trajectory " + path, e.what());
  }
}

std::optional<Eigen::Isometry3d> interpolatePose(const Trajectory& traj, double t,
                                                 double max_dt_s) {
  if (traj.empty()) return std::nullopt;
  const auto it = std::lower_bound(traj.begin(), traj.end(), t, [](const StampedPose& p, double v) {
    return p.timestamp_s < v;
  });
  if (it == traj.end()) {
    const auto& last = traj.back();
    if (std::abs(t - last.timestamp_s) <= max_dt_s) return last.T_world_cam;
    return std::nullopt;
  }
  if (it->timestamp_s == t || it == traj.begin()) {
    if (std::abs(it->timestamp_s - t) <= max_dt_s) return it->T_world_cam;
    return std::nullopt;
  }
  const StampedPose& p0 = *(it - 1);
  const StampedPose& p1 = *it;
  if (std::min(t - p0.timestamp_s, p1.timestamp_s - t) > max_dt_s) return std::nullopt;
  const double a = (t - p0.timestamp_s) / (p1.timestamp_s - p0.timestamp_s);
  const Eigen::Quaterniond q0(p0.T_world_cam.linear()), q1(p1.T_world_cam.linear());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q0.slerp(a, q1).normalized().toRotationMatrix();
  T.translation() = (1 - a) * p0.T_world_cam.translation() + a * p1.T_world_cam.translation();
  return T;
}

TumTrajectoryWriter::TumTrajectoryWriter(const std::string& path, const std::string& header_comment)
    : f_(openForWrite(path)), path_(path) {
  std::fputs(tumTrajectoryText({}, header_comment).c_str(), f_);
  std::fflush(f_);
}

TumTrajectoryWriter::~TumTrajectoryWriter() {
  if (f_) std::fclose(f_);
}

void TumTrajectoryWriter::write(const StampedPose& p) {
  if (!f_) throwInputError("trajectory " + path_, "write after close()");
  std::fprintf(f_, "%s\n", formatTumLine(p).c_str());
  std::fflush(f_);
}

void TumTrajectoryWriter::close() {
  if (!f_) return;
  const bool ok = std::ferror(f_) == 0;
  const bool closed = std::fclose(f_) == 0;
  f_ = nullptr;
  if (!ok || !closed) throwInputError("trajectory " + path_, "write failed (disk full?)");
}

}  // namespace rasm::io
