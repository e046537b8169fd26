#include "rasm/sim/Trajectory.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

#include "YamlNode.h"
#include "rasm/core/Error.h"
#include "rasm/sim/CameraPoses.h"
#include "rasm/sim/World.h"

namespace fs = std::filesystem;

namespace rasm::sim {

// ---- quaternion helpers (unit quaternions)
// -------------------------------------------------------

namespace {

Eigen::Vector3d quatLog(const Eigen::Quaterniond& q) {
  const Eigen::Vector3d v = q.vec();
  const double n = v.norm();
  if (n < 1e-12) return v;
  return v / n * std::atan2(n, q.w());
}

Eigen::Quaterniond quatExp(const Eigen::Vector3d& u) {
  const double t = u.norm();
  if (t < 1e-12) return Eigen::Quaterniond(1.0, u.x(), u.y(), u.z()).normalized();
  const Eigen::Vector3d v = u / t * std::sin(t);
  return Eigen::Quaterniond(std::cos(t), v.x(), v.y(), v.z());
}

}  // namespace

// ---- handheld -----------------------------------------------------------------------------------

HandheldTrajectory::HandheldTrajectory(std::vector<HandheldKeyframe> kf, const HandJitter& jitter,
                                       std::uint64_t seed)
    : m_kf(std::move(kf)), m_jitter(jitter) {
  if (m_kf.size() < 2)
    throw std::invalid_argument("HandheldTrajectory: needs at least 2 keyframes");
  for (std::size_t i = 1; i < m_kf.size(); ++i)
    if (!(m_kf[i].t_s > m_kf[i - 1].t_s))
      throw std::invalid_argument("HandheldTrajectory: keyframe times must increase strictly");
  const std::size_t n = m_kf.size();
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Quaterniond q(m_kf[i].T_world_cam.linear());
    q.normalize();
    if (i > 0 && q.dot(m_q.back()) < 0) q.coeffs() = -q.coeffs();
    m_q.push_back(q);
  }
  // Angular velocity (body frame) at each keyframe, Catmull-Rom style like the position
  // tangents: (r_i-1,i + r_i,i+1) / (t_i+1 - t_i-1) with r_a,b = log(q_a^-1 q_b); zero at the ends.
  m_w.assign(n, Eigen::Vector3d::Zero());
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const Eigen::Vector3d r_prev = 2.0 * quatLog(m_q[i - 1].conjugate() * m_q[i]);
    const Eigen::Vector3d r_next = 2.0 * quatLog(m_q[i].conjugate() * m_q[i + 1]);
    m_w[i] = (r_prev + r_next) / (m_kf[i + 1].t_s - m_kf[i - 1].t_s);
  }
  // Jitter: per axis three sinusoids, random frequency in [0.5, 1.5] f0 and phase, amplitudes
  // scaled so the RMS of their sum is the configured amplitude.
  std::mt19937_64 rng(seed ^ 0x6A09E667F3BCC909ull);
  // Raw engine bits, not std::uniform_real_distribution: the same sequence on every std library.
  auto uniform = [&rng]() { return double(rng() >> 11) * (1.0 / 9007199254740992.0); };
  for (int axis = 0; axis < 6; ++axis) {
    const double target = axis < 3 ? jitter.translation_m : jitter.rotation_deg * M_PI / 180.0;
    double sum_sq = 0;
    for (int k = 0; k < 3; ++k) {
      Wave w{jitter.frequency_hz * (0.5 + uniform()), 2.0 * M_PI * uniform(),
             0.5 + 0.5 * uniform()};
      sum_sq += 0.5 * w.amp * w.amp;
      m_waves[axis].push_back(w);
    }
    for (auto& w : m_waves[axis]) w.amp *= sum_sq > 0 ? target / std::sqrt(sum_sq) : 0.0;
  }
}

Eigen::Isometry3d HandheldTrajectory::smoothPose(double t) const {
  const std::size_t n = m_kf.size();
  t = std::clamp(t, m_kf.front().t_s, m_kf.back().t_s);
  std::size_t i = 0;
  while (i + 2 < n && t > m_kf[i + 1].t_s) ++i;
  const double t0 = m_kf[i].t_s, t1 = m_kf[i + 1].t_s, dt = t1 - t0;
  const double h = (t - t0) / dt;
  // Cubic Hermite position with Catmull-Rom tangents (zero velocity at the ends).
  auto tangent = [&](std::size_t k) -> Eigen::Vector3d {
    if (k == 0 || k + 1 == n) return Eigen::Vector3d::Zero();
    return (m_kf[k + 1].T_world_cam.translation() - m_kf[k - 1].T_world_cam.translation()) /
           (m_kf[k + 1].t_s - m_kf[k - 1].t_s);
  };
  const double h2 = h * h, h3 = h2 * h;
  const Eigen::Vector3d p = (2 * h3 - 3 * h2 + 1) * m_kf[i].T_world_cam.translation() +
                            (h3 - 2 * h2 + h) * dt * tangent(i) +
                            (-2 * h3 + 3 * h2) * m_kf[i + 1].T_world_cam.translation() +
                            (h3 - h2) * dt * tangent(i + 1);
  // Orientation: cubic Bezier on SO(3) evaluated by De Casteljau with slerp (Shoemake 1985).
  // Inner control points b1 = q_i exp(dt w_i / 3), b2 = q_i+1 exp(-dt w_i+1 / 3) make the
  // angular velocity at each keyframe w_i from both sides: C1 in time, not just in h.
  const Eigen::Quaterniond b0 = m_q[i], b3 = m_q[i + 1];
  const Eigen::Quaterniond b1 = b0 * quatExp(m_w[i] * (dt / 6.0));  // quatExp takes half angles
  const Eigen::Quaterniond b2 = b3 * quatExp(-m_w[i + 1] * (dt / 6.0));
  const Eigen::Quaterniond a1 = b0.slerp(h, b1), a2 = b1.slerp(h, b2), a3 = b2.slerp(h, b3);
  const Eigen::Quaterniond c1 = a1.slerp(h, a2), c2 = a2.slerp(h, a3);
  const Eigen::Quaterniond q = c1.slerp(h, c2).normalized();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.toRotationMatrix();
  T.translation() = p;
  return T;
}

Eigen::Isometry3d HandheldTrajectory::pose(double t) const {
  const Eigen::Isometry3d T = smoothPose(t);
  double v[6];
  for (int axis = 0; axis < 6; ++axis) {
    v[axis] = 0;
    for (const Wave& w : m_waves[axis])
      v[axis] += w.amp * std::sin(2.0 * M_PI * w.freq_hz * t + w.phase);
  }
  Eigen::Isometry3d J = Eigen::Isometry3d::Identity();  // jitter in the camera frame
  J.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  const Eigen::Vector3d r(v[3], v[4], v[5]);
  if (r.norm() > 0) J.linear() = Eigen::AngleAxisd(r.norm(), r.normalized()).toRotationMatrix();
  return T * J;
}

// ---- pure pursuit -------------------------------------------------------------------------------

PurePursuit::PurePursuit(std::vector<Eigen::Vector2d> path, const PurePursuitParams& p, bool loop,
                         int laps)
    : m_path(std::move(path)), m_p(p), m_loop(loop) {
  if (m_path.size() < 2) throw std::invalid_argument("PurePursuit: path needs at least 2 points");
  if (m_loop) m_path.push_back(m_path.front());
  m_cum.push_back(0.0);
  for (std::size_t i = 1; i < m_path.size(); ++i)
    m_cum.push_back(m_cum.back() + (m_path[i] - m_path[i - 1]).norm());
  m_lap = m_cum.back();
  if (!(m_lap > 0)) throw std::invalid_argument("PurePursuit: path has zero length");
  m_total = m_loop ? m_lap * std::max(1, laps) : m_lap;
}

Eigen::Vector2d PurePursuit::pointAt(double s) const {
  s = std::clamp(s, 0.0, m_total);
  if (m_loop && s < m_total) s = std::fmod(s, m_lap);
  const std::size_t k =
      std::size_t(std::upper_bound(m_cum.begin(), m_cum.end(), s) - m_cum.begin());
  if (k >= m_cum.size()) return m_path.back();
  const std::size_t i = k - 1;
  const double seg = m_cum[i + 1] - m_cum[i];
  const double h = seg > 0 ? (s - m_cum[i]) / seg : 0.0;
  return m_path[i] + h * (m_path[i + 1] - m_path[i]);
}

Eigen::Vector2d PurePursuit::command(const Eigen::Vector3d& pose) {
  if (m_done) return Eigen::Vector2d::Zero();
  const Eigen::Vector2d xy = pose.head<2>();
  // Progress: closest path point in a window ahead of the current progress (monotone, so a
  // path that passes near itself is followed in order).
  const double step = 0.01;
  double best_s = m_progress, best_d = (pointAt(m_progress) - xy).squaredNorm();
  for (double s = m_progress; s <= std::min(m_total, m_progress + 2.0 * m_p.lookahead_m);
       s += step) {
    const double d = (pointAt(s) - xy).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best_s = s;
    }
  }
  m_progress = best_s;
  const Eigen::Vector2d goal = pointAt(m_total);
  const double to_goal = (goal - xy).norm();
  if (m_progress >= m_total - m_p.lookahead_m && to_goal <= m_p.goal_tolerance_m) {
    m_done = true;
    return Eigen::Vector2d::Zero();
  }
  const Eigen::Vector2d target = pointAt(m_progress + m_p.lookahead_m);
  const double c = std::cos(pose.z()), s = std::sin(pose.z());
  const Eigen::Vector2d d = target - xy;
  const Eigen::Vector2d local(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
  const double L = local.norm();
  const double alpha = std::atan2(local.y(), local.x());
  const double wmax = m_p.max_w_degps * M_PI / 180.0;
  if (L < 1e-6) return Eigen::Vector2d::Zero();
  if (std::abs(alpha) > m_p.rotate_in_place_deg * M_PI / 180.0)
    return {0.0, alpha > 0 ? wmax : -wmax};
  const double kappa = 2.0 * std::sin(alpha) / L;
  const double remaining = (m_total - m_progress) + to_goal;
  double v = std::min(m_p.max_v_mps, std::max(0.05, m_p.slowdown_gain * remaining));
  double w = kappa * v;
  if (std::abs(w) > wmax) {
    v *= wmax / std::abs(w);
    w = w > 0 ? wmax : -wmax;
  }
  return {v, w};
}

// ---- spec loading
// ---------------------------------------------------------------------------------

namespace {

using detail::YNode;

std::string scalarText(const YNode& n) {
  if (n.raw().IsScalar()) return n.asString();
  if (n.isSequence()) {
    std::string s;
    for (const YNode& e : n.items()) s += (s.empty() ? "" : " ") + e.asString();
    return s;
  }
  n.fail("expected a value or a list of values");
}

std::map<std::string, std::string> overrides(const YNode& n) {
  n.requireMap();
  std::map<std::string, std::string> m;
  for (const auto& kv : n.raw()) {
    const std::string k = kv.first.as<std::string>();
    m[k] = scalarText(n[k]);
  }
  return m;
}

HandheldKeyframe parseKeyframe(const YNode& k) {
  k.allowKeys({"t", "position", "look_at", "yaw_deg", "pitch_deg", "roll_deg"});
  HandheldKeyframe kf;
  kf.t_s = k.has("t") ? k["t"].asDouble(0, 1e6) : -1.0;
  const Eigen::Vector3d eye = k["position"].asPosition();
  if (k.has("look_at")) {
    for (const char* key : {"yaw_deg", "pitch_deg", "roll_deg"})
      if (k.has(key)) k[key].fail("give either look_at or yaw_deg/pitch_deg/roll_deg");
    try {
      kf.T_world_cam = cameraPoseLookingAt(eye, k["look_at"].asPosition());
    } catch (const std::invalid_argument& e) {
      k["look_at"].fail(e.what());
    }
  } else {
    if (!k.has("yaw_deg")) k.fail("missing key 'look_at' or 'yaw_deg'");
    kf.T_world_cam =
        cameraPoseFromHeading(eye, k["yaw_deg"].asDouble(),
                              k.has("pitch_deg") ? k["pitch_deg"].asDouble(-89.9, 89.9) : 0.0,
                              k.has("roll_deg") ? k["roll_deg"].asDouble(-180, 180) : 0.0);
  }
  return kf;
}

}  // namespace

TrajectorySpec loadTrajectorySpecFromString(const std::string& text, const std::string& source) {
  const YNode doc = YNode::parse(text, source);
  if (doc.isNull()) doc.fail("empty trajectory spec");
  doc.requireMap();
  TrajectorySpec spec;
  spec.source = source;
  const std::string type = doc["type"].asString();
  if (type == "handheld") {
    spec.kind = TrajectorySpec::Kind::Handheld;
    doc.allowKeys(
        {"type", "description", "world", "rate_hz", "duration_s", "keyframes", "jitter", "sensor"});
  } else if (type == "robot") {
    spec.kind = TrajectorySpec::Kind::Robot;
    doc.allowKeys({"type", "description", "world", "rate_hz", "duration_s", "max_duration_s",
                   "start", "waypoints", "loop", "laps", "controller", "control_substeps", "robot",
                   "sensor"});
  } else {
    doc["type"].fail("unknown trajectory type '" + type + "'; expected handheld or robot");
  }
  if (auto w = doc.optional("world")) spec.world = w->asString();
  if (auto r = doc.optional("rate_hz")) spec.rate_hz = r->asDouble(0.1, 1000);
  if (auto d = doc.optional("duration_s")) spec.duration_s = d->asDouble(1e-3, 1e6);
  if (auto s = doc.optional("sensor")) spec.sensor_overrides = overrides(*s);

  if (spec.kind == TrajectorySpec::Kind::Handheld) {
    const YNode list = doc["keyframes"];
    const auto items = list.items();
    if (items.size() < 2) list.fail("expected at least 2 keyframes");
    int with_t = 0;
    for (const YNode& k : items) {
      spec.keyframes.push_back(parseKeyframe(k));
      with_t += spec.keyframes.back().t_s >= 0 ? 1 : 0;
    }
    if (with_t == 0) {
      if (!spec.duration_s)
        list.fail("keyframes without 't' need 'duration_s' to spread them over");
      for (std::size_t i = 0; i < spec.keyframes.size(); ++i)
        spec.keyframes[i].t_s = *spec.duration_s * double(i) / double(spec.keyframes.size() - 1);
    } else if (with_t != int(items.size())) {
      list.fail("give 't' for every keyframe or for none");
    }
    for (std::size_t i = 1; i < spec.keyframes.size(); ++i)
      if (!(spec.keyframes[i].t_s > spec.keyframes[i - 1].t_s))
        items[i]["t"].fail("keyframe times must increase");
    if (auto j = doc.optional("jitter")) {
      j->allowKeys({"translation_m", "rotation_deg", "frequency_hz"});
      if (auto v = j->optional("translation_m")) spec.jitter.translation_m = v->asDouble(0, 1);
      if (auto v = j->optional("rotation_deg")) spec.jitter.rotation_deg = v->asDouble(0, 45);
      if (auto v = j->optional("frequency_hz")) spec.jitter.frequency_hz = v->asDouble(0, 100);
    }
  } else {
    const YNode start = doc["start"];
    start.allowKeys({"x", "y", "yaw_deg"});
    spec.start_pose =
        Eigen::Vector3d(start["x"].asDouble(-kMaxCoordinate_m, kMaxCoordinate_m),
                        start["y"].asDouble(-kMaxCoordinate_m, kMaxCoordinate_m),
                        start.has("yaw_deg") ? start["yaw_deg"].asDouble() * M_PI / 180.0 : 0.0);
    const YNode wps = doc["waypoints"];
    for (const YNode& w : wps.items())
      spec.waypoints.push_back(w.asVector(2, -kMaxCoordinate_m, kMaxCoordinate_m));
    if (spec.waypoints.empty()) wps.fail("expected at least one waypoint [x, y]");
    if (auto l = doc.optional("loop")) spec.loop = l->asBool();
    if (auto l = doc.optional("laps")) spec.laps = int(l->asInt(1, 1000));
    if (auto m = doc.optional("max_duration_s")) spec.max_duration_s = m->asDouble(1e-3, 1e6);
    if (auto c = doc.optional("control_substeps")) spec.control_substeps = int(c->asInt(1, 100));
    if (auto c = doc.optional("controller")) {
      c->allowKeys({"lookahead_m", "max_v_mps", "max_w_degps", "rotate_in_place_deg",
                    "goal_tolerance_m", "slowdown_gain"});
      auto& p = spec.controller;
      if (auto v = c->optional("lookahead_m")) p.lookahead_m = v->asDouble(0.01, 100);
      if (auto v = c->optional("max_v_mps")) p.max_v_mps = v->asDouble(0.01, 20);
      if (auto v = c->optional("max_w_degps")) p.max_w_degps = v->asDouble(1, 3600);
      if (auto v = c->optional("rotate_in_place_deg")) p.rotate_in_place_deg = v->asDouble(0, 180);
      if (auto v = c->optional("goal_tolerance_m")) p.goal_tolerance_m = v->asDouble(0.001, 10);
      if (auto v = c->optional("slowdown_gain")) p.slowdown_gain = v->asDouble(0.01, 100);
    }
    if (auto r = doc.optional("robot")) spec.robot_overrides = overrides(*r);
  }
  return spec;
}

TrajectorySpec loadTrajectorySpec(const std::string& name) {
  std::string path = name;
  const fs::path shipped = fs::path(simDataDir()) / "trajectories" / (name + ".yaml");
  if (name.find('/') == std::string::npos && !fs::is_regular_file(name) &&
      fs::is_regular_file(shipped))
    path = shipped.string();
  std::ifstream f(path);
  if (!f)
    throwInputError("trajectory spec '" + name + "'",
                    "no such file (nor a shipped spec in " +
                        (fs::path(simDataDir()) / "trajectories").string() + ")");
  std::stringstream ss;
  ss << f.rdbuf();
  TrajectorySpec spec = loadTrajectorySpecFromString(ss.str(), path);
  if (!spec.world.empty() && fs::path(spec.world).is_relative())
    spec.world = (fs::path(path).parent_path() / spec.world).lexically_normal().string();
  return spec;
}

}  // namespace rasm::sim
