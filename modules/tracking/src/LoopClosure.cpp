#include "rasm/tracking/LoopClosure.h"
#include "rasm/core/Angles.h"

#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/graphslam/levmarq.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussianInf.h>

#include <algorithm>
#include <cmath>

#include "rasm/compute/Parallel.h"
#include "rasm/core/SE3.h"

namespace rasm::tracking {

namespace {

double angleOf(const Eigen::Matrix3d& R) {
  return Eigen::AngleAxisd(R).angle();
}

}  // namespace

const char* LoopVerdict::name() const {
  switch (kind) {
    case Kind::Agrees:
      return "agrees";
    case Kind::Refused:
      return "refused";
    case Kind::Accepted:
      return "closed";
  }
  return "?";
}

Eigen::Isometry3d TrajectoryCorrection::at(double time_s) const {
  Eigen::Isometry3d C = Eigen::Isometry3d::Identity();
  if (t_s.empty()) return C;
  const auto it = std::upper_bound(t_s.begin(), t_s.end(), time_s);
  if (it == t_s.begin() || it == t_s.end()) {
    const std::size_t k = it == t_s.begin() ? 0 : t_s.size() - 1;
    C.linear() = q[k].toRotationMatrix();
    C.translation() = t[k];
    return C;
  }
  const std::size_t k1 = std::size_t(it - t_s.begin()), k0 = k1 - 1;
  const double span = t_s[k1] - t_s[k0];
  const double a = span > 0 ? (time_s - t_s[k0]) / span : 1.0;
  C.linear() = q[k0].slerp(a, q[k1]).toRotationMatrix();
  C.translation() = (1.0 - a) * t[k0] + a * t[k1];
  return C;
}

LoopClosure::LoopClosure(const TLoopClosureParams& params) : m_params(params) {
  m_params.validate("loop_closure");
}

void LoopClosure::reset() {
  m_nodes.clear();
  m_chain.clear();
  m_loops.clear();
}

LoopClosure::Edge LoopClosure::chainEdge(const Node& a, const Node& b, double weak_fraction) const {
  Edge e;
  e.from = m_nodes.size() - 1;
  e.to = m_nodes.size();
  e.Z = a.T.inverse() * b.T;
  e.sigma_m =
      std::max(m_params.chain_sigma_min_m, m_params.chain_sigma_m_per_m * e.Z.translation().norm());
  const double turned_deg = angleOf(e.Z.linear()) / kRadPerDeg,
               travelled_m = e.Z.translation().norm();
  e.sigma_rad = kRadPerDeg * std::max(m_params.chain_sigma_min_deg,
                                      std::hypot(m_params.chain_sigma_deg_per_deg * turned_deg,
                                                 m_params.chain_sigma_deg_per_m * travelled_m));
  const double weak =
      1.0 + (m_params.chain_sigma_weak_factor - 1.0) * std::clamp(weak_fraction, 0.0, 1.0);
  e.sigma_m *= weak;
  e.sigma_rad *= weak;
  return e;
}

bool LoopClosure::addNode(double t_s, const Eigen::Isometry3d& T_world_cam, bool force,
                          double weak_fraction) {
  if (!m_nodes.empty()) {
    if (t_s < m_nodes.back().t_s) return false;
    if (!force && t_s - m_nodes.back().t_s < m_params.node_every_s) return false;
  }
  const Node n{t_s, T_world_cam};
  if (!m_nodes.empty()) m_chain.push_back(chainEdge(m_nodes.back(), n, weak_fraction));
  m_nodes.push_back(n);
  return true;
}

std::size_t LoopClosure::nodeNear(double t_s) const {
  const auto it = std::lower_bound(m_nodes.begin(), m_nodes.end(), t_s,
                                   [](const Node& n, double t) { return n.t_s < t; });
  if (it == m_nodes.end()) return m_nodes.size() - 1;
  const std::size_t k = std::size_t(it - m_nodes.begin());
  if (k > 0 && t_s - m_nodes[k - 1].t_s < it->t_s - t_s) return k - 1;
  return k;
}

double LoopClosure::pathLengthSince(double t_from_s, const Eigen::Isometry3d& T_now) const {
  if (m_nodes.empty()) return 0.0;
  double path = 0.0;
  for (std::size_t k = nodeNear(t_from_s) + 1; k < m_nodes.size(); ++k)
    path += (m_nodes[k].T.translation() - m_nodes[k - 1].T.translation()).norm();
  return path + (T_now.translation() - m_nodes.back().T.translation()).norm();
}

Eigen::Isometry3d LoopClosure::constrain(const Eigen::Isometry3d& C) const {
  if (!m_up) return C;
  const Eigen::Vector3d& up = *m_up;
  const Eigen::Vector3d e = up.unitOrthogonal();
  Eigen::Vector3d re = C.linear() * e;
  re -= up * up.dot(re);
  const double yaw = std::atan2(up.dot(e.cross(re)), e.dot(re));
  Eigen::Isometry3d P = Eigen::Isometry3d::Identity();
  P.linear() = Eigen::AngleAxisd(yaw, up).toRotationMatrix();
  P.translation() = C.translation() - up * up.dot(C.translation());
  return P;
}

LoopVerdict LoopClosure::judge(const Eigen::Isometry3d& T_active,
                               const Eigen::Isometry3d& T_inactive, double t_old_s,
                               double t_now_s) const {
  (void)t_now_s;
  LoopVerdict v;
  v.correction = constrain(T_inactive * T_active.inverse());
  v.T_loop = v.correction * T_active;
  // The size of the correction where the camera is (a rotation about the world origin moves a
  // camera far from it more than one near it).
  const Eigen::Isometry3d rel = v.T_loop * T_active.inverse();
  v.correction_m = (v.T_loop.translation() - T_active.translation()).norm();
  v.correction_deg = angleOf(rel.linear()) / kRadPerDeg;
  v.path_m = pathLengthSince(t_old_s, T_active);
  v.bound_m = m_params.max_correction_m + m_params.drift_m_per_m * v.path_m;
  v.bound_deg = m_params.max_correction_deg + m_params.drift_deg_per_m * v.path_m;
  if (m_nodes.size() < 2 || (v.correction_m < m_params.min_correction_m &&
                             v.correction_deg < m_params.min_correction_deg))
    v.kind = LoopVerdict::Kind::Agrees;
  else if (v.correction_m > v.bound_m || v.correction_deg > v.bound_deg)
    v.kind = LoopVerdict::Kind::Refused;
  else
    v.kind = LoopVerdict::Kind::Accepted;
  return v;
}

bool LoopClosure::sameCorrection(const LoopVerdict& a, const LoopVerdict& b,
                                 const Eigen::Isometry3d& T_world_cam) const {
  const Eigen::Isometry3d Ta = a.correction * T_world_cam, Tb = b.correction * T_world_cam;
  const double d_m = translationDistance(Ta, Tb);
  const double d_deg = rotationAngle(Ta, Tb) / kRadPerDeg;
  return d_m <= m_params.min_correction_m + 0.25 * std::max(a.correction_m, b.correction_m) &&
         d_deg <= m_params.min_correction_deg + 0.25 * std::max(a.correction_deg, b.correction_deg);
}

TrajectoryCorrection LoopClosure::close(double t_now_s, const Eigen::Isometry3d& T_active,
                                        const Eigen::Isometry3d& T_loop, double t_old_s,
                                        double weak_fraction) {
  TrajectoryCorrection out;
  if (m_nodes.size() < 2) return out;
  const std::size_t old = nodeNear(t_old_s);
  addNode(std::max(t_now_s, m_nodes.back().t_s), T_active, true, weak_fraction);
  const std::size_t cur = m_nodes.size() - 1;
  if (old >= cur) return out;
  Edge loop;
  loop.from = old;
  loop.to = cur;
  loop.Z = m_nodes[old].T.inverse() * T_loop;
  loop.sigma_m = m_params.loop_sigma_m;
  loop.sigma_rad = m_params.loop_sigma_deg * kRadPerDeg;

  using Graph = mrpt::graphs::CNetworkOfPoses3DInf;
  Graph g;
  g.root = 0;
  for (std::size_t k = 0; k < m_nodes.size(); ++k) g.nodes[k] = toCPose3D(m_nodes[k].T);
  const auto insert = [&](const Edge& e) {
    mrpt::math::CMatrixDouble66 info;
    info.setZero();
    for (int i = 0; i < 3; ++i) info(i, i) = 1.0 / (e.sigma_m * e.sigma_m);
    for (int i = 3; i < 6; ++i) info(i, i) = 1.0 / (e.sigma_rad * e.sigma_rad);
    g.insertEdge(e.from, e.to, mrpt::poses::CPose3DPDFGaussianInf(toCPose3D(e.Z), info));
  };
  for (const Edge& e : m_chain) insert(e);
  for (const Edge& e : m_loops) insert(e);
  insert(loop);
  mrpt::graphslam::TResultInfoSpaLevMarq info;
  mrpt::containers::yaml extra;
  extra["max_iterations"] = 20;
  try {
    mrpt::graphslam::optimize_graph_spa_levmarq(g, info, nullptr, extra);
  } catch (const std::exception&) {
    m_nodes.pop_back();
    m_chain.pop_back();
    return out;
  }
  m_loops.push_back(loop);
  out.t_s.reserve(m_nodes.size());
  for (std::size_t k = 0; k < m_nodes.size(); ++k) {
    const Eigen::Isometry3d T_new = fromCPose3D(g.nodes.at(k));
    // The correction moves what was made at node k with it; with an up axis, about it only.
    const Eigen::Isometry3d C = constrain(T_new * m_nodes[k].T.inverse());
    m_nodes[k].T = C * m_nodes[k].T;
    out.t_s.push_back(m_nodes[k].t_s);
    out.q.emplace_back(C.linear());
    out.t.push_back(C.translation());
  }
  return out;
}

int deformSurfels(maps::SurfelStore& store, const TrajectoryCorrection& c) {
  if (c.empty() || store.empty()) return 0;
  const maps::SurfelArrays a = store.arrays();
  const int moved = compute::reduce1D<int>(a.size, [&](int i, int& n) {
    if (!a.alive(i)) return;
    const Eigen::Isometry3d C = c.at(store.fromMapTime(a.t_init[i]));
    if (C.translation().norm() < 1e-4 && angleOf(C.linear()) < 1e-6) return;
    const Eigen::Matrix3f R = C.linear().cast<float>();
    const Eigen::Vector3f t = C.translation().cast<float>();
    a.pos_conf[i].head<3>() = R * a.pos_conf[i].head<3>() + t;
    a.normal_radius[i].head<3>() = R * a.normal_radius[i].head<3>();
    a.basis[i] = R * a.basis[i];
    ++n;
  });
  if (moved > 0) store.rebuildIndex();
  return moved;
}

void correctKeyframes(std::vector<maps::Keyframe>& keyframes, const TrajectoryCorrection& c) {
  if (c.empty()) return;
  for (maps::Keyframe& kf : keyframes) {
    const Eigen::Isometry3d C = c.at(kf.timestamp_s);
    kf.T_world_cam = C * kf.T_world_cam;
    const Eigen::Isometry3f Cf = C.cast<float>();
    for (Eigen::Vector3f& p : kf.points_world) p = Cf * p;
  }
}

}  // namespace rasm::tracking
