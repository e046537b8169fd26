#pragma once
// rasm::tracking::LoopClosure: corrects the drift of the camera trajectory and of the surfel map
// when the camera sees again a part of the map it made long ago.
//
// Method (ElasticFusion, Whelan et al., RSS 2015, "local loop closure", with a pose graph in place
// of the deformation graph's optimisation):
//  - the trajectory graph: every node_every_s a tracked frame's pose becomes a node; consecutive
//    nodes are joined by their measured relative pose (the chain), whose uncertainty grows with
//    the motion between them;
//  - detection (the tracking stage): a tracked frame is registered by ICP both against the
//    ACTIVE map (surfels created within the last inactive_after_s: the trajectory's own
//    continuation) and against the INACTIVE map (surfels created before: what the camera mapped
//    on an earlier pass). The two poses differ by the drift accumulated in between; a
//    registration with a direction the geometry leaves free is no registration (no prior holds
//    it), and confirmations consecutive checks must ask for the same correction;
//  - judge(): a difference below min_correction_* is agreement; one beyond what drift over the
//    path since the old map can explain (max_correction_* + drift_*_per_m x path) is refused and
//    reported (a false loop, e.g. a similar room), never applied;
//  - close(): the frame's pose against the inactive map becomes a loop edge from the node of
//    the old map's time; the graph is solved (MRPT's sparse Levenberg-Marquardt,
//    mrpt::graphslam::optimize_graph_spa_levmarq) with the first node fixed; each node's
//    correction C_k = T_new_k T_old_k^-1 is returned by time (TrajectoryCorrection);
//  - the map follows: every surfel moves by the correction at its creation time t_init
//    (interpolated between the nodes around it), as ElasticFusion's deformation graph connects
//    surfels to the nodes of their time; so do the relocalisation keyframes.
// With an up axis (a ground robot whose floor prior holds height, roll and pitch) corrections are
// rotations about that axis and translations across it only.
//
//   LoopClosure lc(params);  lc.setUpAxis(up);     // robot runs
//   per tracked, fused frame:  lc.addNode(t, T_world_cam);
//   every check_every_frames:  T_act, T_inact from ICP; t_old = the inactive surfels' time
//     LoopVerdict v = lc.judge(T_act, T_inact, t_old, t);
//     if (v.accepted()) { TrajectoryCorrection c = lc.close(t, T_act, v.T_loop, t_old);
//                         deformSurfels(store, c); correctKeyframes(kfs, c); pose = c.at(t) * T; }

#include <Eigen/Geometry>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "rasm/surfel_map/Keyframe.h"
#include "rasm/surfel_map/SurfelStore.h"
#include "rasm/tracking/LoopClosureParams.h"

namespace rasm::tracking {

/// A correction of the map's world frame by time: at node times t_s[k] the rigid transform
/// (rotation q[k], translation t[k]) that moves what was made then; between nodes interpolated
/// (slerp, lerp), before the first and after the last node held.
struct TrajectoryCorrection {
  std::vector<double> t_s;
  std::vector<Eigen::Quaterniond> q;
  std::vector<Eigen::Vector3d> t;

  bool empty() const { return t_s.empty(); }
  Eigen::Isometry3d at(double time_s) const;
};

/// What judge() decided about one registration against the inactive map.
struct LoopVerdict {
  enum class Kind { Agrees, Refused, Accepted };
  Kind kind = Kind::Agrees;
  /// Correction of the world frame the inactive map asks for (T_inactive T_active^-1, about the
  /// up axis when there is one), its size and the bound it was judged against.
  Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();
  double correction_m = 0, correction_deg = 0;
  double bound_m = 0, bound_deg = 0;
  double path_m = 0;  ///< path length of the trajectory since the old map's time
  /// The frame's pose the loop edge asks for: correction * T_active.
  Eigen::Isometry3d T_loop = Eigen::Isometry3d::Identity();
  bool accepted() const { return kind == Kind::Accepted; }
  const char* name() const;
};

class LoopClosure {
 public:
  /// Throws InputError (naming [loop_closure] key) for out-of-range params.
  explicit LoopClosure(const TLoopClosureParams& params = {});
  const TLoopClosureParams& params() const { return m_params; }

  /// Corrections are then rotations about `up` (world frame, unit) and translations across it.
  void setUpAxis(const Eigen::Vector3d& up) { m_up = up.normalized(); }
  void reset();

  /// Adds a node at a tracked frame when node_every_s passed since the last one, or `force`.
  /// Times must not decrease. `weak_fraction`: of the frames since the last node, those the data
  /// did not hold in every direction (chain_sigma_weak_factor). Returns whether a node was added.
  bool addNode(double t_s, const Eigen::Isometry3d& T_world_cam, bool force = false,
               double weak_fraction = 0.0);
  std::size_t numNodes() const { return m_nodes.size(); }
  std::size_t numLoopEdges() const { return m_loops.size(); }
  double firstNodeTime() const { return m_nodes.empty() ? 0.0 : m_nodes.front().t_s; }
  /// Path length (m) of the nodes from the one nearest t_from_s to the last, plus to `T_now`.
  double pathLengthSince(double t_from_s, const Eigen::Isometry3d& T_now) const;

  /// The decision on a frame at t_now_s registered at T_active against the active map and
  /// T_inactive against the inactive map, made around t_old_s.
  LoopVerdict judge(const Eigen::Isometry3d& T_active, const Eigen::Isometry3d& T_inactive,
                    double t_old_s, double t_now_s) const;

  /// Adds a node at t_now_s (pose T_active), the loop edge from the node nearest t_old_s asking
  /// for T_loop, solves the graph and returns the correction of every node (the nodes take their
  /// new poses). Empty when the solve fails (nothing changed then).
  TrajectoryCorrection close(double t_now_s, const Eigen::Isometry3d& T_active,
                             const Eigen::Isometry3d& T_loop, double t_old_s,
                             double weak_fraction = 0.0);

  /// Whether two verdicts ask for the same correction of the camera at T_world_cam: positions
  /// within min_correction_m plus a quarter of the larger correction, rotations likewise.
  bool sameCorrection(const LoopVerdict& a, const LoopVerdict& b,
                      const Eigen::Isometry3d& T_world_cam) const;

  /// Rotation about the up axis and translation across it of a world-frame transform (the
  /// transform itself without an up axis).
  Eigen::Isometry3d constrain(const Eigen::Isometry3d& C) const;

 private:
  struct Node {
    double t_s;
    Eigen::Isometry3d T;  ///< current estimate (world <- camera)
  };
  struct Edge {
    std::size_t from, to;
    Eigen::Isometry3d Z;  ///< measured T_from^-1 T_to
    double sigma_m, sigma_rad;
  };
  std::size_t nodeNear(double t_s) const;
  Edge chainEdge(const Node& a, const Node& b, double weak_fraction) const;

  TLoopClosureParams m_params;
  std::optional<Eigen::Vector3d> m_up;
  std::vector<Node> m_nodes;
  std::vector<Edge> m_chain, m_loops;
};

/// Moves every surfel by c.at(its t_init): position and its rotation on normal and basis; then
/// rebuilds the store's spatial index. Returns the surfels that moved (by more than 0.1 mm or a
/// micro-radian).
int deformSurfels(maps::SurfelStore& store, const TrajectoryCorrection& c);
/// Moves each keyframe's pose and world points by c.at(its timestamp).
void correctKeyframes(std::vector<maps::Keyframe>& keyframes, const TrajectoryCorrection& c);

}  // namespace rasm::tracking
