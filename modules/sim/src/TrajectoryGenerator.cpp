#include "rasm/sim/TrajectoryGenerator.h"
#include "rasm/core/Angles.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <optional>
#include <sstream>

#include "GenUtil.h"
#include "rasm/core/AtomicFile.h"
#include "rasm/core/Error.h"
#include "rasm/models/ClassVocabulary.h"
#include "rasm/sim/CameraPoses.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/RgbdSensor.h"
#include "rasm/sim/SimulatedDiffDriveRobot.h"
#include "rasm/sim/SimulatedSequence.h"
#include "rasm/sim/Trajectory.h"
#include "rasm/sim/ViewStats.h"
#include "rasm/sim/World.h"

namespace fs = std::filesystem;

namespace rasm::sim {
namespace {

using gen::num;
using gen::Rng;
using V3 = Eigen::Vector3d;

/// Runs this thread's OpenMP regions on one thread while alive: the view check's 80 x 60 images
/// are too small to share (on a busy machine, spinning worker threads made them 30x slower).
class SerialOpenMp {
 public:
#ifdef _OPENMP
  SerialOpenMp() : m_threads(omp_get_max_threads()) {
    omp_set_num_threads(1);
  }
  ~SerialOpenMp() {
    omp_set_num_threads(m_threads);
  }

 private:
  int m_threads;
#endif
};

/// Low-resolution renders (80 x 60, the Kinect's field of view) for the view check: the fraction
/// of pixels with a depth in [0.4 m, max_depth_m] that survives the sensor's dropouts (a floor
/// seen beyond about 3 m from the robot's camera is at a grazing angle and missing).
/// Low-resolution renders (80 x 60, the Kinect's field of view) for the view checks: exact depth
/// in [0.4 m, max_depth_m] with the sensor's dropouts (a floor seen beyond about 3 m from the
/// robot's camera is at a grazing angle and missing) and labels, summarised by viewStats.
class ViewCheck {
 public:
  ViewCheck(const RayScene& scene, double max_depth_m) : m_max_depth_m(max_depth_m) {
    TSensorParams p;
    p.width = 80;
    p.height = 60;
    p.fx = p.fy = 525.0 / 8.0;
    p.cx = 39.5;
    p.cy = 29.5;
    p.noise = false;  // exact depth, but the sensor's grazing-angle and shadow dropouts
    p.labels = true;
    p.max_depth_m = max_depth_m;
    m_sensor = std::make_unique<RgbdSensor>(scene, p);
  }
  ViewStats stats(const Eigen::Isometry3d& T_world_cam) {
    m_sensor->render(T_world_cam, 0, 0, m_frame);
    return viewStats(m_frame, m_max_depth_m);
  }
  double fraction(const Eigen::Isometry3d& T_world_cam) {
    return stats(T_world_cam).valid_fraction;
  }

 private:
  double m_max_depth_m;
  std::unique_ptr<RgbdSensor> m_sensor;
  RgbdFrame m_frame;
};

/// The hand-held view rule (TTrajectoryGenParams): enough valid pixels, enough of them on
/// objects and furniture, normals spread over three directions. The margin of a view is its
/// lowest ratio to the three bounds: >= 1 passes.
struct ViewRule {
  double min_valid = 0.6, min_object = 0.25, min_eig = 0.005;
  double margin(const ViewStats& s) const {
    return std::min(
        {s.valid_fraction / min_valid, s.object_fraction / min_object, s.normal_min_eig / min_eig});
  }
};

/// The worst views along a path: the lowest margin and the lowest value of each statistic.
struct ViewWorst {
  double margin = 1e30, valid = 1.0, object = 1.0, eig = 1.0;
  double t_worst = 0.0;  ///< time of the view with the lowest margin
  void add(const ViewStats& s, const ViewRule& r, double t) {
    const double m = r.margin(s);
    if (m < margin) t_worst = t;
    margin = std::min(margin, m);
    valid = std::min(valid, s.valid_fraction);
    object = std::min(object, s.object_fraction);
    eig = std::min(eig, s.normal_min_eig);
  }
};

GenRect inset(const GenRect& r, double m) {
  return {r.x0 + m, r.y0 + m, r.x1 - m, r.y1 - m};
}

std::string vec(const V3& v) {
  return "[" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + "]";
}

/// Body angular velocity (camera frame, rad/s) of a trajectory's smooth path at t.
V3 bodyRate(const HandheldTrajectory& traj, double t, double h = 1.0 / 600.0) {
  const Eigen::Matrix3d R0 = traj.smoothPose(t).linear(), R1 = traj.smoothPose(t + h).linear();
  const Eigen::AngleAxisd aa(R0.transpose() * R1);
  return aa.axis() * aa.angle() / h;
}

// ---- hand-held --------------------------------------------------------------------------------

struct Key {
  double t = 0.0;
  V3 pos = V3::Zero();
  bool look = true;  ///< look_at `target`, else yaw/pitch/roll
  V3 target = V3::Zero();
  double yaw = 0.0, pitch = 0.0, roll = 0.0;  ///< degrees
  double dpitch = 0.0;  ///< fast: how far above `target` the keyframe aims (deg)
  Eigen::Isometry3d pose() const {
    return look ? cameraPoseLookingAt(pos, target) : cameraPoseFromHeading(pos, yaw, pitch, roll);
  }
};

HandheldTrajectory trajectoryOf(const std::vector<Key>& keys) {
  std::vector<HandheldKeyframe> kf;
  for (const Key& k : keys) kf.push_back({k.t, k.pose()});
  HandJitter none;
  none.translation_m = 0.0;
  none.rotation_deg = 0.0;
  return HandheldTrajectory(kf, none, 0);
}

/// Peak |rate| per camera axis (deg/s) over [t0, t1].
V3 peakRates(const HandheldTrajectory& traj, double t0, double t1, double step = 1.0 / 240.0) {
  V3 peak = V3::Zero();
  for (double t = t0; t < t1; t += step)
    peak = peak.cwiseMax(bodyRate(traj, t).cwiseAbs() / kRadPerDeg);
  return peak;
}

/// Re-times each swing so the peak rate about its dominant axis is its target (the spline's
/// Catmull-Rom tangents couple neighbouring segments, hence the iterations).
void tuneSwings(std::vector<Key>& keys, const std::vector<int>& swings,
                const std::vector<double>& targets) {
  std::vector<double> dt(keys.size() - 1);
  for (std::size_t i = 0; i + 1 < keys.size(); ++i) dt[i] = keys[i + 1].t - keys[i].t;
  for (int it = 0; it < 12; ++it) {
    const HandheldTrajectory traj = trajectoryOf(keys);
    bool converged = true;
    for (std::size_t s = 0; s < swings.size(); ++s) {
      const int i = swings[s];
      const Eigen::Matrix3d R0 = keys[std::size_t(i)].pose().linear(),
                            R1 = keys[std::size_t(i) + 1].pose().linear();
      const Eigen::AngleAxisd aa(R0.transpose() * R1);
      int axis = 0;
      (aa.axis() * aa.angle()).cwiseAbs().maxCoeff(&axis);
      const V3 peak = peakRates(traj, keys[std::size_t(i)].t, keys[std::size_t(i) + 1].t);
      const double ratio = std::clamp(peak[axis] / targets[s], 0.5, 2.0);
      if (std::abs(ratio - 1.0) > 0.005) converged = false;
      dt[std::size_t(i)] *= ratio;
    }
    for (std::size_t i = 0; i + 1 < keys.size(); ++i)
      keys[i + 1].t = std::round((keys[i].t + dt[i]) * 1000.0) / 1000.0;
    if (converged) break;
  }
}

/// Checks the smooth path of `keys` (>= 2) from keyframe `first` on: positions stay where a
/// person can stand (area + 0.15 m, 1.0-1.9 m high) and every view sampled along it passes the
/// rule. `frame_step_s` > 0 samples at the frame times t0 + k step (the final check);
/// otherwise each segment is sampled `per_segment` times plus every `segment_step_s` (the
/// drafter's checks of the segments a new keyframe changes). Returns the worst views; margin
/// -1 when the path leaves the area.
ViewWorst checkPath(const std::vector<Key>& keys, std::size_t first, const GenRect& area,
                    ViewCheck& view, const ViewRule& rule, double frame_step_s,
                    double segment_step_s = 0.1, int per_segment = 4) {
  const HandheldTrajectory traj = trajectoryOf(keys);
  const GenRect ok = inset(area, -0.15);
  ViewWorst w;
  auto sample = [&](double t) {
    const Eigen::Isometry3d T = traj.smoothPose(t);
    const V3 p = T.translation();
    if (!ok.contains(p.x(), p.y()) || p.z() < 1.0 || p.z() > 1.9) return false;
    w.add(view.stats(T), rule, t);
    return true;
  };
  if (frame_step_s > 0.0) {
    const double t0 = keys[first].t;
    for (long long k = 0;; ++k) {
      const double t = t0 + double(k) * frame_step_s;
      if (t > traj.endTime() + 1e-9) break;
      if (!sample(t)) return {-1.0, 0.0, 0.0, 0.0};
    }
    return w;
  }
  if (first == 0 && !sample(keys[0].t)) return {-1.0, 0.0, 0.0, 0.0};
  for (std::size_t i = first; i + 1 < keys.size(); ++i) {
    const double t0 = keys[i].t, dt = keys[i + 1].t - t0;
    const int n = std::max(per_segment, int(std::ceil(dt / segment_step_s)));
    for (int j = 1; j <= n; ++j)
      if (!sample(t0 + dt * j / n)) return {-1.0, 0.0, 0.0, 0.0};
  }
  return w;
}

class HandheldDrafter {
 public:
  HandheldDrafter(const GeneratedWorld& g, const RayScene& scene, Rng& rng, ViewCheck& view,
                  const ViewRule& rule)
      : m_scene(scene), m_rng(rng), m_view(view), m_rule(rule) {
    // Where the person holding the camera may stand: the robot's free area widened by the
    // robot's radius (still clearance_m from every footprint).
    m_area = inset(g.free_area, -g.params.robot_radius_m);
    for (const V3& p : g.view_targets)
      if (p.z() > 0.2 && p.z() < 2.3) m_targets.push_back(p);
    m_room = g.rooms.empty() ? GenRect{0.0, 0.0, g.params.width_m, g.params.depth_m}
                             : g.rooms.front().interior;
  }
  const GenRect& area() const { return m_area; }

  bool visible(const V3& eye, const V3& target) const {
    const Eigen::Vector3f o = eye.cast<float>(), d = (target - eye).cast<float>();
    const RayHit h = m_scene.castRay(o, d, 0.f, 1.f);
    return !h.hit || h.t * d.norm() >= d.norm() - 0.2f;
  }

  /// A camera position in the area looking at `target` from 1-3 m (at least 0.6 m away
  /// horizontally, so never straight down), unobstructed; the nearest of the candidates to `prev`
  /// (within 2.5 m) when given.
  std::optional<V3> standpoint(const V3& target, const std::optional<V3>& prev) {
    std::optional<V3> best;
    double best_score = 1e30;
    for (int k = 0; k < 60; ++k) {
      const double a = m_rng.uniform(-M_PI, M_PI), r = m_rng.uniform(0.6, 2.9);
      const V3 c(target.x() + r * std::cos(a), target.y() + r * std::sin(a),
                 m_rng.uniform(1.2, 1.7));
      if (!m_area.contains(c.x(), c.y())) continue;
      const double d = (c - target).norm();
      if (d < 1.0 || d > 3.0 || !visible(c, target)) continue;
      if (prev && (c - *prev).norm() > 2.5) continue;
      const double score = prev ? (c - *prev).norm() : m_rng.uniform();
      if (score < best_score) {
        best_score = score;
        best = c;
      }
    }
    return best;
  }

  /// Position of a point along the room's perimeter (m, counter-clockwise from the south-west
  /// corner), measured at its nearest wall.
  double perimeterAt(const V3& q) const {
    const V3 p(q.x() - m_room.x0, q.y() - m_room.y0, q.z());
    const double w = m_room.width(), d = m_room.depth();
    const double ds = p.y(), de = w - p.x(), dn = d - p.y(), dw = p.x();
    const double m = std::min({ds, de, dn, dw});
    if (m == ds) return std::clamp(p.x(), 0.0, w);
    if (m == de) return w + std::clamp(p.y(), 0.0, d);
    if (m == dn) return w + d + std::clamp(w - p.x(), 0.0, w);
    return 2 * w + d + std::clamp(d - p.y(), 0.0, d);
  }
  double perimeter() const { return 2 * (m_room.width() + m_room.depth()); }

  /// A target near perimeter position `s`, random among the nearest few.
  std::optional<V3> targetNear(double s) {
    if (m_targets.empty()) return std::nullopt;
    std::vector<std::pair<double, int>> by;
    for (int i = 0; i < int(m_targets.size()); ++i)
      by.emplace_back(
          std::abs(std::remainder(perimeterAt(m_targets[std::size_t(i)]) - s, perimeter())), i);
    std::sort(by.begin(), by.end());
    const int n = std::min<int>(4, int(by.size()));
    return m_targets[std::size_t(by[std::size_t(m_rng.index(n))].second)];
  }

  /// Keyframes every 3-5 s over 20-30 s, walking along the room's furniture, 1.2-2.2 m of
  /// perimeter from one keyframe's target to the next (0.6-1.6 times that for each candidate,
  /// so bare stretches of wall can be skipped). Each keyframe is the first of up to 12
  /// candidates (target, standpoint) whose path from the previous keyframes passes the view
  /// rule; when none does, the previous keyframe is drawn again (up to 20 times), else the best
  /// candidate is kept.
  std::vector<Key> normal() {
    const double T = r1(m_rng.uniform(20.0, 30.0));
    const int n = std::max(5, int(std::lround(T / m_rng.uniform(3.0, 5.0))) + 1);
    const double s0 = m_rng.uniform(0.0, perimeter()), dir = m_rng.chance(0.5) ? 1.0 : -1.0;
    const double step = std::min(m_rng.uniform(1.2, 2.2), 0.9 * perimeter() / (n - 1));
    std::vector<Key> keys;
    int backtracks = 0;
    while (int(keys.size()) < n) {
      const int k = int(keys.size());
      std::optional<V3> prev;
      if (!keys.empty()) prev = keys.back().pos;
      std::optional<Key> best;
      double best_margin = -2.0;
      for (int c = 0; c < 12 && best_margin < 1.0; ++c) {
        const double s =
            keys.empty() ? s0
                         : perimeterAt(keys.back().target) + dir * step * m_rng.uniform(0.6, 1.6);
        const std::optional<V3> target = targetNear(s);
        const std::optional<V3> cam = target ? standpoint(*target, prev) : std::nullopt;
        if (!cam) continue;
        Key key;
        key.t = T * k / (n - 1);
        key.pos = round3(*cam);
        key.target = round3(*target);
        std::vector<Key> trial = keys;
        trial.push_back(key);
        const double m = checkSegments(trial, keys.size() >= 2 ? keys.size() - 2 : 0, 0.25);
        if (m > best_margin) {
          best_margin = m;
          best = key;
        }
      }
      if (best_margin < 1.0 && k > 0 && backtracks < 20) {
        keys.pop_back();
        ++backtracks;
        continue;
      }
      if (!best) return {};
      keys.push_back(*best);
    }
    return keys;
  }

  /// Hold-swing-hold: swings about the camera's x, y and z axes (tilt, pan, roll), each swing
  /// timed for a peak of 125-142 deg/s about its axis (`peaks`, see tuneSwings), slow holds in
  /// between; 20-30 s. The camera keeps an object or piece of furniture in view: every keyframe
  /// aims at a target (a point on an object or furniture) with a small pitch offset. A hold
  /// drifts the camera 0.1-0.3 m in 1-1.8 s while it keeps its target; a tilt (20-36 deg)
  /// pivots about the target, from aiming above it to below it or back (the target stays in
  /// the 43 deg vertical field of view), or swings to another target 20-40 deg higher or lower;
  /// a pan (50-110 deg) swings to another target found by casting a ray that way (the first
  /// surface hit, on an object or furniture 0.8-3.2 m away); a roll (to 30-45 deg across level)
  /// keeps the target. Each hold + swing is the first of up to 12 candidates whose path passes
  /// the view rule; when none does, the previous hold + swing is drawn again (up to 40 times),
  /// else the best candidate is kept.
  std::vector<Key> fast(std::vector<int>& swing_segments, std::vector<double>& peaks) {
    const double T = m_rng.uniform(20.0, 30.0);
    std::vector<Key> keys;
    double best_margin = -2.0;
    for (int c = 0; c < 12 && best_margin < 1.0; ++c) {
      const std::optional<V3> target = targetNear(m_rng.uniform(0.0, perimeter()));
      const std::optional<V3> cam = target ? standpoint(*target, std::nullopt) : std::nullopt;
      if (!cam) continue;
      const Key k0 = aimedAt(round3(*cam), round3(*target), 0.0, 0.0, 0.0);
      const double m = m_rule.margin(m_view.stats(k0.pose()));
      if (m > best_margin) {
        best_margin = m;
        keys = {k0};
      }
    }
    if (keys.empty()) return {};
    int swings[3] = {0, 0, 0};
    std::vector<int> axes;  // axis of each accepted swing
    std::vector<int> cycle = {0, 1, 2};
    std::size_t ci = cycle.size();
    int backtracks = 0;
    while (keys.back().t < T || std::min({swings[0], swings[1], swings[2]}) < 2) {
      if (keys.size() > 80) return {};
      if (ci == cycle.size()) {
        for (std::size_t i = cycle.size(); i > 1; --i)
          std::swap(cycle[i - 1], cycle[std::size_t(m_rng.index(int(i)))]);
        ci = 0;
      }
      const int axis = cycle[ci++];
      const double peak = m_rng.uniform(125.0, 142.0);
      std::vector<Key> best;
      best_margin = -2.0;
      for (int c = 0; c < 12 && best_margin < 1.0; ++c) {
        const std::optional<std::pair<Key, Key>> hs = holdAndSwing(keys.back(), axis);
        if (!hs) continue;
        std::vector<Key> trial = keys;
        trial.push_back(hs->first);
        trial.push_back(hs->second);
        tuneSwings(trial, {int(trial.size()) - 2}, {peak});
        const double m = checkSegments(trial, keys.size() >= 2 ? keys.size() - 2 : 0);
        if (m > best_margin) {
          best_margin = m;
          best = std::move(trial);
        }
      }
      if (best_margin < 1.0 && !axes.empty() && backtracks < 40) {
        keys.resize(keys.size() - 2);
        --swings[axes.back()];
        axes.pop_back();
        swing_segments.pop_back();
        peaks.pop_back();
        ++backtracks;
        continue;
      }
      if (best.empty()) return {};
      keys = std::move(best);
      swing_segments.push_back(int(keys.size()) - 2);  // segment from the hold to the swing
      peaks.push_back(peak);
      axes.push_back(axis);
      ++swings[axis];
    }
    // Settle: roll back to level, still looking at the last target.
    std::vector<Key> best;
    best_margin = -2.0;
    for (int c = 0; c < 6 && best_margin < 1.0; ++c) {
      const Key& b = keys.back();
      Key last = aimedAt(drift(b.pos, 0.15), b.target, 0.0, 0.0, b.yaw);
      last.t = b.t + m_rng.uniform(1.5, 2.0);
      std::vector<Key> trial = keys;
      trial.push_back(last);
      const double m = checkSegments(trial, keys.size() - 2);
      if (m > best_margin) {
        best_margin = m;
        best = std::move(trial);
      }
    }
    return best;
  }

 private:
  /// Worst margin of the segments from keyframe `first` on (each sampled every `step_s`, at
  /// least 4 times), or of the single keyframe's view. Appending a keyframe changes the last
  /// segment before it (Catmull-Rom tangents): check from keys.size() - 2 of the old keys.
  double checkSegments(const std::vector<Key>& keys, std::size_t first, double step_s = 0.1) {
    if (keys.size() == 1) return m_rule.margin(m_view.stats(keys[0].pose()));
    return checkPath(keys, first, m_area, m_view, m_rule, 0.0, step_s).margin;
  }

  /// A yaw/pitch/roll keyframe at `pos` aiming `dpitch` degrees above `target` (yaw unwrapped
  /// next to `prev_yaw`, angles rounded to 0.1 deg as written).
  static Key aimedAt(const V3& pos, const V3& target, double dpitch, double roll, double prev_yaw) {
    Key k;
    k.look = false;
    k.pos = pos;
    k.target = target;
    k.dpitch = dpitch;
    double yaw = 0.0, pitch = 0.0;
    headingTo(target - pos, yaw, pitch);
    k.yaw = r1(prev_yaw + std::remainder(yaw - prev_yaw, 360.0));
    k.pitch = r1(pitch + dpitch);
    k.roll = r1(roll);
    return k;
  }

  /// The first surface along (yaw, pitch) from `eye` when it belongs to an object or piece of
  /// furniture 0.8-3.2 m away and more than 0.5 m away horizontally (a look-at target).
  std::optional<V3> rayTarget(const V3& eye, double yaw_deg, double pitch_deg) const {
    const double y = yaw_deg * kRadPerDeg, p = pitch_deg * kRadPerDeg;
    const V3 d(std::cos(p) * std::cos(y), std::cos(p) * std::sin(y), std::sin(p));
    const RayHit h = m_scene.castRay(eye.cast<float>(), d.cast<float>(), 0.f, 3.2f);
    if (!h.hit || h.object < 0 ||
        models::isStructureClass(m_scene.world().objects[std::size_t(h.object)].class_id))
      return std::nullopt;
    const V3 q = h.point.cast<double>();
    if ((q - eye).norm() < 0.8 || (q - eye).head<2>().norm() < 0.5) return std::nullopt;
    return round3(q);
  }

  /// A slow hold after `prev` (1-1.8 s later, the camera drifted 0.1-0.3 m, still aiming at its
  /// target, the pitch offset `dpitch`) and a swing from it about camera axis `axis` (0 tilt,
  /// 1 pan, 2 roll), timed roughly (tuneSwings sets its peak); none when no target was found.
  std::optional<std::pair<Key, Key>> holdAndSwing(const Key& prev, int axis) {
    const V3 hold_pos = drift(prev.pos, m_rng.uniform(0.1, 0.3));
    const double hold_t = prev.t + m_rng.uniform(1.0, 1.8);
    const V3 pos = drift(hold_pos, 0.05);
    auto hold = [&](double dpitch) {
      Key h = aimedAt(hold_pos, prev.target, dpitch, prev.roll, prev.yaw);
      h.t = hold_t;
      return h;
    };
    std::optional<std::pair<Key, Key>> hs;
    if (axis == 2) {  // roll (camera z): across level to the other side, 30-45 deg
      const double r = m_rng.uniform(30.0, 45.0);
      const double roll = prev.roll > 0 ? -r : prev.roll < 0 ? r : (m_rng.chance(0.5) ? r : -r);
      const Key h = hold(prev.dpitch * 0.5);
      hs = std::pair{h, aimedAt(pos, h.target, h.dpitch, roll, h.yaw)};
    } else if (axis == 0 && m_rng.chance(0.5)) {  // tilt pivoting about the target
      const double d = m_rng.uniform(20.0, 36.0), sign = m_rng.chance(0.5) ? 1.0 : -1.0;
      const Key h = hold(sign * d / 2);
      hs = std::pair{h, aimedAt(pos, h.target, -sign * d / 2, h.roll, h.yaw)};
    } else {
      const Key h = hold(0.0);
      for (int k = 0; k < 6 && !hs; ++k) {
        double yaw = h.yaw, pitch = h.pitch;
        if (axis == 0) {  // tilt (camera x) to a target 20-40 deg above or below
          pitch += (m_rng.chance(0.5) ? 1 : -1) * m_rng.uniform(20.0, 40.0);
          yaw += m_rng.uniform(-10.0, 10.0);
        } else {  // pan (camera y): to a target 50-110 deg to the side
          yaw += (m_rng.chance(0.5) ? 1 : -1) * m_rng.uniform(50.0, 110.0);
          pitch = std::clamp(h.pitch + m_rng.uniform(-15.0, 15.0), -60.0, 10.0);
        }
        const std::optional<V3> target = rayTarget(pos, yaw, pitch);
        if (!target) continue;
        const Key c = aimedAt(pos, *target, 0.0, h.roll, h.yaw);
        const bool dominant =
            axis == 0 ? std::abs(c.pitch - h.pitch) >= 15.0 : std::abs(c.yaw - h.yaw) >= 45.0;
        if (dominant) hs = std::pair{h, c};
      }
    }
    if (!hs) return std::nullopt;
    const Key &h = hs->first, &s = hs->second;
    if (h.pitch < -72.0 || h.pitch > 22.0 || s.pitch < -72.0 || s.pitch > 22.0) return std::nullopt;
    const Eigen::AngleAxisd aa(h.pose().linear().transpose() * s.pose().linear());
    hs->second.t = h.t + std::max(0.15, 1.5 * (aa.angle() / kRadPerDeg) / 135.0);
    return hs;
  }

  static void headingTo(const V3& d, double& yaw_deg, double& pitch_deg) {
    yaw_deg = std::atan2(d.y(), d.x()) / kRadPerDeg;
    pitch_deg = std::atan2(d.z(), d.head<2>().norm()) / kRadPerDeg;
  }
  V3 drift(const V3& p, double dist) {
    const double a = m_rng.uniform(-M_PI, M_PI);
    V3 q = p + dist * V3(std::cos(a), std::sin(a), 0.0);
    q.x() = std::clamp(q.x(), m_area.x0, m_area.x1);
    q.y() = std::clamp(q.y(), m_area.y0, m_area.y1);
    q.z() = std::clamp(q.z() + m_rng.uniform(-0.05, 0.05), 1.2, 1.7);
    return round3(q);
  }
  static V3 round3(const V3& v) {
    return V3(std::round(v.x() * 1000) / 1000, std::round(v.y() * 1000) / 1000,
              std::round(v.z() * 1000) / 1000);
  }
  static double r1(double v) { return std::round(v * 10.0) / 10.0; }

  const RayScene& m_scene;
  Rng& m_rng;
  ViewCheck& m_view;
  ViewRule m_rule;
  GenRect m_area;
  std::vector<V3> m_targets;
  GenRect m_room;  ///< the room the person walks in
};

/// The world as the hand-held drafter sees it: one room. In a flat, the room with the most view
/// targets (the first of those), its free area and its targets.
GeneratedWorld handheldRoom(const GeneratedWorld& g) {
  if (g.rooms.size() <= 1) return g;
  std::size_t best = 0, best_n = 0;
  for (std::size_t i = 0; i < g.rooms.size(); ++i) {
    std::size_t n = 0;
    for (const V3& p : g.view_targets) n += g.rooms[i].interior.contains(p.x(), p.y()) ? 1 : 0;
    if (n > best_n) {
      best = i;
      best_n = n;
    }
  }
  GeneratedWorld r = g;
  const GeneratedWorld::Room room = g.rooms[best];
  r.rooms = {room};
  r.free_area = room.free_area;
  r.view_targets.clear();
  for (const V3& p : g.view_targets)
    if (room.interior.contains(p.x(), p.y())) r.view_targets.push_back(p);
  return r;
}

/// The options of `rasm sim generate` beyond --seed that made the world (a flat's layout).
std::string layoutOptions(const GeneratedWorld& g) {
  if (g.params.layout != WorldLayout::Flat) return "";
  return " --layout flat --rooms " + std::to_string(g.params.rooms);
}

std::string handheldYaml(const std::vector<Key>& keys, const TTrajectoryGenParams& p,
                         const GeneratedWorld& g, const std::string& comment) {
  std::ostringstream o;
  o << "# Random " << (p.fast ? "fast " : "") << "hand-held trajectory for the generated world "
    << g.name << " (rasm sim generate --seed " << p.seed << layoutOptions(g)
    << (p.fast ? " --fast" : "") << "; schema: docs/sim.md).\n"
    << comment;
  o << "type: handheld\n";
  o << "description: " << (p.fast ? "fast " : "") << "hand-held sweep of " << g.name << "\n";
  if (!p.world_ref.empty()) o << "world: " << p.world_ref << "\n";
  o << "rate_hz: " << num(p.rate_hz) << "\n";
  o << "jitter: {translation_m: 0.003, rotation_deg: " << (p.fast ? "0.3" : "0.4")
    << ", frequency_hz: 1.5}\n";
  o << "keyframes:\n";
  for (const Key& k : keys) {
    o << "  - {t: " << num(k.t) << ", position: " << vec(k.pos);
    if (k.look)
      o << ", look_at: " << vec(k.target) << "}\n";
    else
      o << ", yaw_deg: " << num(k.yaw, 1) << ", pitch_deg: " << num(k.pitch, 1)
        << ", roll_deg: " << num(k.roll, 1) << "}\n";
  }
  return o.str();
}

// ---- robot --------------------------------------------------------------------------------------

struct DriveCheck {
  bool ok = false;
  std::string why;
  double time_s = 0.0, worst_view = 1.0, length_m = 0.0;
};

/// Drives the spec as SimulatedSequence does (pure pursuit at control_substeps x rate) without
/// rendering, every substep checked for collisions, a low-resolution view every 3rd frame.
DriveCheck drive(const RayScene& scene, const TrajectorySpec& spec, ViewCheck& view) {
  DriveCheck r;
  TRobotParams rp;
  applyParamOverrides(rp, "sim_robot", spec.robot_overrides, spec.source + " robot:");
  std::unique_ptr<SimulatedDiffDriveRobot> robot;
  try {
    robot = std::make_unique<SimulatedDiffDriveRobot>(scene, rp, spec.start_pose, 0);
  } catch (const InputError&) {
    r.why = "start pose collides";
    return r;
  }
  std::vector<Eigen::Vector2d> path{spec.start_pose.head<2>()};
  path.insert(path.end(), spec.waypoints.begin(), spec.waypoints.end());
  PurePursuit pp(path, spec.controller, spec.loop, spec.laps);
  r.length_m = pp.totalLength();
  const double dt = 1.0 / spec.rate_hz;
  const long long max_frames = (long long)(spec.max_duration_s * spec.rate_hz);
  for (long long f = 0; f < max_frames; ++f) {
    if (f % 3 == 0) r.worst_view = std::min(r.worst_view, view.fraction(robot->cameraPose()));
    if (pp.done()) {
      r.ok = true;
      r.time_s = double(f) * dt;
      return r;
    }
    for (int k = 0; k < spec.control_substeps; ++k) {
      const Eigen::Vector2d cmd = pp.command(robot->pose());
      robot->setVelocityCommand(cmd.x(), cmd.y());
      robot->step(dt / spec.control_substeps);
      if (robot->collided()) {
        char b[96];
        std::snprintf(b, sizeof(b), "collides at (%.2f, %.2f)", robot->pose().x(),
                      robot->pose().y());
        r.why = b;
        return r;
      }
    }
  }
  r.why = "does not finish";
  return r;
}

std::string robotYaml(const TTrajectoryGenParams& p, const GeneratedWorld& g, const V3& start,
                      const std::vector<Eigen::Vector2d>& wps, const std::string& comment) {
  std::ostringstream o;
  o << "# Random " << (p.fast ? "fast " : "") << "robot loop for the generated world " << g.name
    << " (rasm sim generate --seed " << p.seed << layoutOptions(g) << (p.fast ? " --fast" : "")
    << "; schema: docs/sim.md).\n"
    << comment;
  o << "type: robot\n";
  o << "description: " << (p.fast ? "robot loop with 90 deg/s turns in place" : "robot loop")
    << (g.params.layout == WorldLayout::Flat ? " along the hallway of "
                                             : " through the free area of ")
    << g.name << "\n";
  if (!p.world_ref.empty()) o << "world: " << p.world_ref << "\n";
  o << "rate_hz: " << num(p.rate_hz) << "\n";
  o << "start: {x: " << num(start.x()) << ", y: " << num(start.y())
    << ", yaw_deg: " << num(start.z(), 1) << "}\n";
  o << "waypoints: [";
  for (std::size_t i = 0; i < wps.size(); ++i)
    o << (i ? ", " : "") << "[" << num(wps[i].x()) << ", " << num(wps[i].y()) << "]";
  o << "]\nloop: true\n";
  if (p.fast)
    o << "controller: {lookahead_m: 0.5, max_v_mps: 0.35, max_w_degps: 90, rotate_in_place_deg: "
         "20}\n"
      << "robot: {footprint_radius_m: " << num(g.params.robot_radius_m)
      << ", camera_height_m: 0.55, camera_pitch_deg: -10, max_w_degps: 90}\n";
  else
    o << "controller: {lookahead_m: 0.5, max_v_mps: 0.35, max_w_degps: 45, rotate_in_place_deg: "
         "30}\n"
      << "robot: {footprint_radius_m: " << num(g.params.robot_radius_m)
      << ", camera_height_m: 0.55, camera_pitch_deg: -10}\n";
  return o.str();
}

}  // namespace

GeneratedTrajectory generateHandheldTrajectory(const GeneratedWorld& g, const World& world,
                                               const TTrajectoryGenParams& p) {
  const SerialOpenMp serial;
  const RayScene scene(world);
  ViewCheck view(scene, p.max_view_depth_m);
  ViewRule rule;
  rule.min_valid = p.min_valid_handheld;
  rule.min_object = p.min_object_fraction_handheld;
  rule.min_eig = p.min_normal_eig_handheld;
  Rng rng(p.seed ^ (p.fast ? 0xA4093822299F31D0ull : 0x13198A2E03707344ull));
  const GeneratedWorld room = handheldRoom(g);
  HandheldDrafter drafter(room, scene, rng, view, rule);
  std::vector<Key> best;
  ViewWorst best_view;
  best_view.margin = -2.0;
  V3 best_peak = V3::Zero();
  int attempts = 0;
  for (; attempts < 30; ++attempts) {
    std::vector<int> swings;
    std::vector<double> peaks;
    std::vector<Key> keys = p.fast ? drafter.fast(swings, peaks) : drafter.normal();
    if (keys.size() < 2) continue;
    if (p.fast) tuneSwings(keys, swings, peaks);
    const HandheldTrajectory traj = trajectoryOf(keys);
    const V3 peak = peakRates(traj, traj.startTime(), traj.endTime());
    if (p.fast && (peak.minCoeff() < 120.0 || peak.maxCoeff() > 150.0)) continue;
    const ViewWorst v = checkPath(keys, 0, drafter.area(), view, rule, 1.0 / p.rate_hz);
    if (v.margin > best_view.margin) {
      best_view = v;
      best = keys;
      best_peak = peak;
    }
    if (v.margin >= 1.0) break;
  }
  if (best.empty())
    throw std::runtime_error("generateHandheldTrajectory: no feasible keyframes for world " +
                             g.name);
  GeneratedTrajectory out;
  out.duration_s = best.back().t - best.front().t;
  out.min_valid_fraction = std::max(0.0, best_view.valid);
  out.min_object_fraction = std::max(0.0, best_view.object);
  out.min_normal_eig = std::max(0.0, best_view.eig);
  out.peak_rate_degps = best_peak;
  char line[320];
  std::snprintf(line, sizeof(line),
                "%.1f s, %zu keyframes, peak rates about camera x/y/z %.0f/%.0f/%.0f deg/s, worst "
                "view %.0f%% of pixels within 0.4-%.0f m, %.0f%% of them on objects, normal "
                "spread %.3f%s",
                out.duration_s, best.size(), best_peak.x(), best_peak.y(), best_peak.z(),
                100.0 * out.min_valid_fraction, p.max_view_depth_m, 100.0 * out.min_object_fraction,
                out.min_normal_eig,
                best_view.margin >= 1.0 ? "" : " (WARNING: below the check's bounds)");
  out.summary = line;
  out.yaml = handheldYaml(best, p, g, "# Checked when generated: " + out.summary + ".\n");
  return out;
}

GeneratedTrajectory generateRobotTrajectory(const GeneratedWorld& g, const World& world,
                                            const TTrajectoryGenParams& p) {
  const SerialOpenMp serial;
  const RayScene scene(world);
  ViewCheck view(scene, p.max_view_depth_m);
  Rng rng(p.seed ^ (p.fast ? 0x082EFA98EC4E6C89ull : 0x452821E638D01377ull));
  std::string best_yaml, best_summary;
  DriveCheck best;
  best.worst_view = -1.0;
  bool have = false;
  for (int attempt = 0; attempt < 12; ++attempt) {
    const GenRect F = inset(g.free_area, 0.05 * (attempt / 2));
    if (F.width() < 0.0 || F.depth() < 0.0) break;
    const bool ccw = rng.chance(0.5);
    // Corners counter-clockwise from the south-west; a degenerate side becomes a line.
    std::vector<Eigen::Vector2d> c = {{F.x0, F.y0}, {F.x1, F.y0}, {F.x1, F.y1}, {F.x0, F.y1}};
    if (!ccw) std::reverse(c.begin(), c.end());
    const int leg = rng.index(4);  // start in the middle of this leg, heading along it
    const Eigen::Vector2d a = c[std::size_t(leg)], b = c[std::size_t((leg + 1) % 4)];
    const Eigen::Vector2d s = 0.5 * (a + b);
    const V3 start(std::round(s.x() * 1000) / 1000, std::round(s.y() * 1000) / 1000,
                   std::round(std::atan2(b.y() - a.y(), b.x() - a.x()) / kRadPerDeg * 10) / 10);
    std::vector<Eigen::Vector2d> wps;
    for (int k = 1; k <= 4; ++k) {
      wps.push_back(c[std::size_t((leg + k) % 4)]);
      if (p.fast && k == 2) {
        // A spur from the middle of the opposite leg to the middle of the area and back: a
        // 180 deg turn in place at its end.
        const Eigen::Vector2d m =
            0.5 * (c[std::size_t((leg + 2) % 4)] + c[std::size_t((leg + 3) % 4)]);
        const Eigen::Vector2d centre(0.5 * (F.x0 + F.x1), 0.5 * (F.y0 + F.y1));
        if ((m - centre).norm() > 0.4) {
          wps.push_back(m);
          wps.push_back(centre);
          wps.push_back(m);
        }
      }
    }
    // Drop repeated points (a line-shaped area).
    std::vector<Eigen::Vector2d> clean;
    for (const auto& w : wps) {
      const Eigen::Vector2d q(std::round(w.x() * 1000) / 1000, std::round(w.y() * 1000) / 1000);
      const Eigen::Vector2d last = clean.empty() ? start.head<2>() : clean.back();
      if ((q - last).norm() > 0.05) clean.push_back(q);
    }
    if (clean.empty()) continue;
    const std::string draft = robotYaml(p, g, start, clean, "");
    const TrajectorySpec spec = loadTrajectorySpecFromString(draft, "generated robot spec");
    const DriveCheck d = drive(scene, spec, view);
    char line[256];
    if (d.ok)
      std::snprintf(line, sizeof(line),
                    "loop of %.1f m driven in %.1f s without a collision, worst view %.0f%% of "
                    "pixels within 0.4-%.0f m%s",
                    d.length_m, d.time_s, 100.0 * d.worst_view, p.max_view_depth_m,
                    d.worst_view >= p.min_valid_robot ? "" : " (WARNING: below the check's bound)");
    else
      std::snprintf(line, sizeof(line), "WARNING: %s", d.why.c_str());
    const bool better =
        !have || (d.ok && !best.ok) || (d.ok == best.ok && d.worst_view > best.worst_view);
    if (better) {
      have = true;
      best = d;
      best_summary = line;
      best_yaml =
          robotYaml(p, g, start, clean, std::string("# Checked when generated: ") + line + ".\n");
    }
    if (d.ok && d.worst_view >= p.min_valid_robot) break;
  }
  if (!have) throw std::runtime_error("generateRobotTrajectory: no free area in world " + g.name);
  GeneratedTrajectory out;
  out.yaml = best_yaml;
  out.summary = best_summary;
  out.duration_s = best.time_s;
  out.min_valid_fraction = best.worst_view;
  return out;
}

namespace {

void writeAtomically(const std::string& path, const std::string& text) {
  try {
    writeFileAtomic(path, text);
  } catch (const std::runtime_error& e) {
    throwInputError(path, e.what());
  }
}

}  // namespace

GenerateFilesResult generateWorldFiles(const TWorldGenParams& wp, const std::string& out_yaml,
                                       const std::string& trajectories, bool fast) {
  if (out_yaml.empty()) throwInputError("rasm sim generate", "expected <out.yaml>");
  const fs::path out(out_yaml);
  if (fs::is_directory(out))
    throwInputError(out_yaml, "is a folder; expected the path of the world file to write");
  const GeneratedWorld g = generateWorld(wp);
  const fs::path out_dir = out.parent_path();
  if (!out_dir.empty()) fs::create_directories(out_dir);
  // Load it back as the recorder will (also resolves the meshes).
  const World world = loadWorldFromString(g.yaml, out.string(), out_dir.string());

  std::string prefix;
  if (trajectories.empty()) {
    prefix = (out_dir / out.stem()).string();
  } else if (fs::is_directory(trajectories) || trajectories.back() == '/') {
    fs::create_directories(trajectories);
    prefix = (fs::path(trajectories) / out.stem()).string();
  } else {
    prefix = trajectories;
    const fs::path pd = fs::path(prefix).parent_path();
    if (!pd.empty()) fs::create_directories(pd);
  }
  GenerateFilesResult res;
  writeAtomically(out.string(), g.yaml);
  res.world_path = out.string();
  std::size_t statics = 0;
  for (const auto& o : world.objects) statics += o.is_static ? 1 : 0;
  char line[320];
  if (g.params.layout == WorldLayout::Flat)
    std::snprintf(line, sizeof(line),
                  "%s: %s flat of %d rooms %s x %s m, %zu static + %zu objects, hallway free area "
                  "%s x %s m",
                  res.world_path.c_str(), roomKindName(g.params.kind), g.params.rooms,
                  num(g.params.width_m).c_str(), num(g.params.depth_m).c_str(), statics,
                  world.objects.size() - statics, num(g.free_area.width(), 2).c_str(),
                  num(g.free_area.depth(), 2).c_str());
  else
    std::snprintf(
        line, sizeof(line), "%s: %s room %s x %s m, %zu static + %zu objects, free area %s x %s m",
        res.world_path.c_str(), roomKindName(g.params.kind), num(g.params.width_m).c_str(),
        num(g.params.depth_m).c_str(), statics, world.objects.size() - statics,
        num(g.free_area.width(), 2).c_str(), num(g.free_area.depth(), 2).c_str());
  res.summary.push_back(line);

  const fs::path traj_dir = fs::path(prefix).parent_path();
  TTrajectoryGenParams tp;
  tp.seed = wp.seed;
  const fs::path abs_world = fs::absolute(out).lexically_normal();
  const fs::path abs_dir =
      fs::absolute(traj_dir.empty() ? fs::path(".") : traj_dir).lexically_normal();
  tp.world_ref = abs_world.lexically_relative(abs_dir).string();
  if (tp.world_ref.empty()) tp.world_ref = abs_world.string();
  for (int f = 0; f < (fast ? 2 : 1); ++f) {
    tp.fast = f == 1;
    const std::string suffix = tp.fast ? "_fast.yaml" : ".yaml";
    const GeneratedTrajectory h = generateHandheldTrajectory(g, world, tp);
    const std::string hp = prefix + "_handheld" + suffix;
    writeAtomically(hp, h.yaml);
    res.trajectory_paths.push_back(hp);
    res.summary.push_back(hp + ": " + h.summary);
    const GeneratedTrajectory r = generateRobotTrajectory(g, world, tp);
    const std::string rp = prefix + "_robot" + suffix;
    writeAtomically(rp, r.yaml);
    res.trajectory_paths.push_back(rp);
    res.summary.push_back(rp + ": " + r.summary);
  }
  return res;
}

}  // namespace rasm::sim
