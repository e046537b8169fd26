#include "rasm/autonomy/OraclePlanner.h"
#include "rasm/core/Angles.h"
#include "rasm/core/Log.h"

#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <queue>
#include <tuple>

#include "rasm/core/Error.h"
#include "rasm/core/Timing.h"
#include "rasm/exploration/PlanningGrid.h"
#include "rasm/exploration/ViewTour.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/SurfaceCoverage.h"

namespace rasm::autonomy {

namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

/// Targets binned by their xy in square cells, for the targets near a robot position.
struct TargetBins {
  Eigen::Vector2f org = Eigen::Vector2f::Zero();
  float cell = 1.f;
  int nx = 0, ny = 0;
  std::vector<std::vector<std::uint32_t>> bins;

  TargetBins(const std::vector<Eigen::Vector3f>& pts, float cell_m) : cell(cell_m) {
    if (pts.empty()) return;
    Eigen::Vector2f lo = pts[0].head<2>(), hi = lo;
    for (const auto& p : pts) lo = lo.cwiseMin(p.head<2>()), hi = hi.cwiseMax(p.head<2>());
    org = lo;
    nx = int(std::floor((hi.x() - lo.x()) / cell)) + 1;
    ny = int(std::floor((hi.y() - lo.y()) / cell)) + 1;
    bins.resize(std::size_t(nx) * ny);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const int ix = std::clamp(int((pts[i].x() - org.x()) / cell), 0, nx - 1);
      const int iy = std::clamp(int((pts[i].y() - org.y()) / cell), 0, ny - 1);
      bins[std::size_t(iy) * nx + ix].push_back(std::uint32_t(i));
    }
  }
};
}  // namespace

OraclePlanner::OraclePlanner(const sim::SurfaceCoverage& coverage, const sim::RayScene& scene,
                             const exploration::TExplorationParams& params,
                             const Eigen::Isometry3d& T_base_cam, const CameraIntrinsics& K)
    : ExplorationPlanner(exploration::GoalBlacklist(params.blacklist_radius_m)),
      m_coverage(coverage),
      m_params(params),
      m_T_base_cam(T_base_cam),
      m_headings(params.oracle_headings) {
  params.validate();
  if (K.width <= 0 || K.height <= 0 || !(K.fx > 0) || !(K.fy > 0))
    throwInputError("[camera]",
                    "the oracle planner needs intrinsics with a positive size and "
                    "focal lengths");
  const auto t0 = Clock::now();
  buildTargets(params.oracle_target_spacing_m);
  buildViewSets(scene, T_base_cam, K);
  m_done.assign(m_poses.size(), 0);
  excludeCrampedViews();
  m_reached_target.assign(numTargets(), 0);
  m_precompute_ms = msSince(t0);
  char text[256];
  std::snprintf(text, sizeof text,
                "oracle planner: %zu views (%zu free positions x %d headings), %zu targets for %zu "
                "observable samples, reachable fraction %.4f, %.1f s",
                m_poses.size(), m_positions.size(), m_headings, numTargets(),
                coverage.observableSamples(), m_reachable_fraction, m_precompute_ms / 1000.0);
  log::info(text);
}

/// Targets: the observable samples, one per cube of `spacing_m` (0: each its own), the first
/// of a cube in sample order representing it; the free positions' grid.
void OraclePlanner::buildTargets(double spacing_m) {
  const auto& samples = m_coverage.samples();
  std::map<std::tuple<int, int, int>, std::uint32_t> cube_target;
  std::vector<std::vector<std::uint32_t>> members;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!samples[i].observable) continue;
    std::uint32_t t = std::uint32_t(members.size());
    if (spacing_m > 0) {
      const Eigen::Vector3f q = samples[i].position / float(spacing_m);
      const auto key =
          std::make_tuple(int(std::floor(q.x())), int(std::floor(q.y())), int(std::floor(q.z())));
      t = cube_target.emplace(key, t).first->second;
    }
    if (t == members.size()) {
      members.emplace_back();
      m_target_sample.push_back(std::uint32_t(i));
    }
    members[t].push_back(std::uint32_t(i));
  }
  m_target_start.assign(1, 0);
  for (const auto& m : members) {
    m_target_members.insert(m_target_members.end(), m.begin(), m.end());
    m_target_start.push_back(std::uint32_t(m_target_members.size()));
  }
  m_left.resize(members.size());
  for (std::size_t t = 0; t < members.size(); ++t) m_left[t] = std::uint32_t(members[t].size());

  // The free positions lie on SurfaceCoverage's grid of position_spacing_m.
  m_positions = m_coverage.robotPositions();
  m_spacing = float(m_coverage.options().position_spacing_m);
  if (m_positions.empty()) return;
  Eigen::Vector2f lo = m_positions[0], hi = lo;
  for (const auto& p : m_positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  m_grid_org = lo;
  m_nx = int(std::lround((hi.x() - lo.x()) / m_spacing)) + 1;
  m_ny = int(std::lround((hi.y() - lo.y()) / m_spacing)) + 1;
  m_position_at.assign(std::size_t(m_nx) * m_ny, -1);
  for (std::size_t i = 0; i < m_positions.size(); ++i) {
    const Eigen::Vector2i c(int(std::lround((m_positions[i].x() - lo.x()) / m_spacing)),
                            int(std::lround((m_positions[i].y() - lo.y()) / m_spacing)));
    m_cell_of.push_back(c);
    m_position_at[std::size_t(c.y()) * m_nx + c.x()] = int(i);
  }
}

/// The view sets: per free position and heading, the targets the camera sees (one ray per
/// target in the field of view and depth range, cast from the target towards the camera).
void OraclePlanner::buildViewSets(const sim::RayScene& scene, const Eigen::Isometry3d& T_base_cam,
                                  const CameraIntrinsics& K) {
  const auto& samples = m_coverage.samples();
  const sim::CoverageOptions& o = m_coverage.options();
  const std::size_t n_targets = m_target_sample.size();
  std::vector<Eigen::Vector3f> pos(n_targets), nrm(n_targets);
  for (std::size_t t = 0; t < n_targets; ++t) {
    pos[t] = samples[m_target_sample[t]].position;
    nrm[t] = samples[m_target_sample[t]].normal;
  }
  const TargetBins bins(pos, 1.f);
  // A target in view lies within max_range / cos(the half-diagonal field of view) of the camera.
  const double half_diag =
      std::atan(std::hypot(std::max(K.cx + 0.5, K.width - 0.5 - K.cx) / K.fx,
                           std::max(K.cy + 0.5, K.height - 0.5 - K.cy) / K.fy));
  const double max_range_m = m_params.oracle_max_range_m > 0
                                 ? std::min(m_params.oracle_max_range_m, o.max_range_m)
                                 : o.max_range_m;
  const float reach = float(max_range_m / std::cos(std::min(half_diag, 80.0 * kRadPerDeg)) +
                            T_base_cam.translation().head<2>().norm() + 1e-3);
  const float cos_inc = float(std::cos(std::clamp(o.max_incidence_deg, 0.0, 90.0) * kRadPerDeg));
  const float rmin = float(o.min_range_m), rmax = float(max_range_m);
  const float fx = float(K.fx), fy = float(K.fy), cx = float(K.cx), cy = float(K.cy);
  const float umax = float(K.width) - 0.5f, vmax = float(K.height) - 0.5f;
  const int H = m_headings;
  m_poses.resize(m_positions.size() * std::size_t(H));
  m_sees.assign(m_poses.size(), {});
  const long long P = (long long)m_positions.size();
#pragma omp parallel for schedule(dynamic, 4)
  for (long long pi = 0; pi < P; ++pi) {
    const Eigen::Vector2f b = m_positions[std::size_t(pi)];
    std::vector<Eigen::Matrix3f> R_cw(H);
    std::vector<Eigen::Vector3f> t_wc(H);
    for (int k = 0; k < H; ++k) {
      const std::size_t c = std::size_t(pi) * H + k;
      m_poses[c] = Eigen::Vector3d(b.x(), b.y(), mrpt::math::wrapToPi(2.0 * M_PI * k / H));
      const Eigen::Isometry3d T = exploration::cameraPoseOf(m_poses[c], T_base_cam);
      R_cw[k] = T.linear().transpose().cast<float>();
      t_wc[k] = T.translation().cast<float>();
    }
    const int x0 = std::max(0, int((b.x() - reach - bins.org.x()) / bins.cell));
    const int x1 = std::min(bins.nx - 1, int((b.x() + reach - bins.org.x()) / bins.cell));
    const int y0 = std::max(0, int((b.y() - reach - bins.org.y()) / bins.cell));
    const int y1 = std::min(bins.ny - 1, int((b.y() + reach - bins.org.y()) / bins.cell));
    for (int iy = y0; iy <= y1; ++iy)
      for (int ix = x0; ix <= x1; ++ix)
        for (const std::uint32_t t : bins.bins[std::size_t(iy) * bins.nx + ix]) {
          if ((pos[t].head<2>() - b).norm() > reach) continue;
          for (int k = 0; k < H; ++k) {
            const Eigen::Vector3f pc = R_cw[k] * (pos[t] - t_wc[k]);
            if (pc.z() < rmin || pc.z() > rmax) continue;
            const float u = fx * pc.x() / pc.z() + cx, v = fy * pc.y() / pc.z() + cy;
            if (u < -0.5f || u > umax || v < -0.5f || v > vmax) continue;
            const Eigen::Vector3f to_cam = t_wc[k] - pos[t];
            const float d = to_cam.norm();
            const Eigen::Vector3f dir = to_cam / d;
            if (std::abs(dir.dot(nrm[t])) < cos_inc) continue;
            constexpr float kEps = 1e-3f;
            if (scene.occluded(pos[t], dir, kEps, d - kEps)) continue;
            m_sees[std::size_t(pi) * H + k].push_back(t);
          }
        }
    for (int k = 0; k < H; ++k) {
      auto& s = m_sees[std::size_t(pi) * H + k];
      std::sort(s.begin(), s.end());  // bins visit targets out of order
      s.shrink_to_fit();
    }
  }
  // What the views can reach at all.
  std::vector<std::uint8_t> seen(n_targets, 0);
  for (const auto& s : m_sees)
    for (const std::uint32_t t : s) seen[t] = 1;
  double area_seen = 0, area_all = 0;
  for (std::size_t t = 0; t < n_targets; ++t)
    for (std::uint32_t j = m_target_start[t]; j < m_target_start[t + 1]; ++j) {
      const double a = samples[m_target_members[j]].area_m2;
      area_all += a;
      if (seen[t]) area_seen += a, ++m_coverable_samples;
    }
  m_reachable_fraction = area_all > 0 ? area_seen / area_all : 0.0;
}

/// A view is offered only from a free position whose eight neighbours are free too: on the
/// edge of the free space the robot's disc touches furniture, and the navigator, which grows
/// obstacles by more than the disc, gets stuck or collides on the way there (tens of seconds
/// per such goal). The edge positions stay on the paths.
void OraclePlanner::excludeCrampedViews() {
  std::size_t cramped = 0;
  for (std::size_t i = 0; i < m_positions.size(); ++i) {
    const Eigen::Vector2i c = m_cell_of[i];
    bool interior = true;
    for (int dy = -1; dy <= 1 && interior; ++dy)
      for (int dx = -1; dx <= 1 && interior; ++dx) {
        const int x = c.x() + dx, y = c.y() + dy;
        interior = x >= 0 && y >= 0 && x < m_nx && y < m_ny &&
                   m_position_at[std::size_t(y) * m_nx + x] >= 0;
      }
    if (interior) continue;
    ++cramped;
    for (int k = 0; k < m_headings; ++k) m_done[i * std::size_t(m_headings) + k] = 1;
  }
  m_cramped_positions = cramped;
  m_offered.resize(m_done.size());
  for (std::size_t c = 0; c < m_done.size(); ++c) m_offered[c] = !m_done[c];
  // Coverable: what the offered views see (reachableFraction keeps every free position's).
  std::vector<std::uint8_t> seen(numTargets(), 0);
  for (std::size_t c = 0; c < m_sees.size(); ++c)
    if (m_offered[c])
      for (const std::uint32_t t : m_sees[c]) seen[t] = 1;
  m_coverable_samples = 0;
  for (std::size_t t = 0; t < seen.size(); ++t)
    if (seen[t]) m_coverable_samples += m_target_start[t + 1] - m_target_start[t];
}

void OraclePlanner::setCoveredSamples(const std::vector<std::uint8_t>& covered) {
  if (covered.size() != m_coverage.samples().size())
    throw std::invalid_argument("OraclePlanner::setCoveredSamples: one byte per sample expected");
  for (std::size_t t = 0; t + 1 < m_target_start.size(); ++t) {
    std::uint32_t left = 0;
    for (std::uint32_t j = m_target_start[t]; j < m_target_start[t + 1]; ++j)
      left += covered[m_target_members[j]] ? 0 : 1;
    m_left[t] = left;
  }
}

void OraclePlanner::updateCoverage(const maps::SurfelStore& store) {
  const maps::SurfelArrays a = store.arrays();
  m_points.clear();
  for (int i = 0; i < a.size; ++i)
    if (a.alive(i) && a.stable(i)) m_points.push_back(a.position(i));  // as the coverage metric
  std::vector<std::uint8_t> covered;
  m_coverage.evaluate(m_points, &covered);
  setCoveredSamples(covered);
}

std::uint64_t OraclePlanner::gain(std::size_t c) const {
  std::uint64_t g = 0;
  for (const std::uint32_t t : m_sees[c]) g += m_left[t];
  return g;
}

std::uint64_t OraclePlanner::gain(const std::vector<int>& views) const {
  std::vector<std::uint8_t> seen(m_left.size(), 0);
  std::uint64_t g = 0;
  for (const int c : views)
    for (const std::uint32_t t : m_sees[std::size_t(c)])
      if (!seen[t]) seen[t] = 1, g += m_left[t];
  return g;
}

std::vector<float> OraclePlanner::distanceField(int from) const {
  std::vector<float> d(m_positions.size(), kInf);
  if (from < 0) return d;
  using Item = std::pair<float, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> q;
  d[std::size_t(from)] = 0.f;
  q.emplace(0.f, from);
  while (!q.empty()) {
    const auto [dist, i] = q.top();
    q.pop();
    if (dist > d[std::size_t(i)]) continue;
    const Eigen::Vector2i c = m_cell_of[std::size_t(i)];
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int x = c.x() + dx, y = c.y() + dy;
        if ((dx == 0 && dy == 0) || x < 0 || y < 0 || x >= m_nx || y >= m_ny) continue;
        const int j = m_position_at[std::size_t(y) * m_nx + x];
        if (j < 0) continue;
        const float nd = dist + m_spacing * ((dx != 0 && dy != 0) ? float(M_SQRT2) : 1.f);
        if (nd < d[std::size_t(j)]) {
          d[std::size_t(j)] = nd;
          q.emplace(nd, j);
        }
      }
  }
  return d;
}

int OraclePlanner::nearestPosition(const Eigen::Vector2d& xy) const {
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < m_positions.size(); ++i) {
    const double d = (m_positions[i].cast<double>() - xy).squaredNorm();
    if (d < best_d) best_d = d, best = int(i);
  }
  return best;
}

double OraclePlanner::travelTime(const std::vector<float>& field, const Eigen::Vector2d& from_xy,
                                 double from_yaw, std::size_t c) const {
  const float len = field[c / std::size_t(m_headings)];
  if (!std::isfinite(len)) return std::numeric_limits<double>::infinity();
  const Eigen::Vector2d d = m_poses[c].head<2>() - from_xy;
  double turn = std::abs(mrpt::math::wrapToPi(m_poses[c].z() - from_yaw));
  if (d.norm() > 2.0 * m_spacing) {  // turn to the line to the view, drive, turn to its heading
    const double dir = std::atan2(d.y(), d.x());
    turn = std::abs(mrpt::math::wrapToPi(dir - from_yaw)) +
           std::abs(mrpt::math::wrapToPi(m_poses[c].z() - dir));
  }
  return len / m_params.speed_mps + turn / (m_params.turn_rate_degps * kRadPerDeg);
}

std::vector<int> OraclePlanner::greedyCover(const Eigen::Vector3d& start) const {
  const std::size_t n = m_poses.size();
  const std::uint64_t min_gain = std::uint64_t(m_params.oracle_min_view_samples);
  std::vector<std::uint32_t> left = m_left;
  // Coverable now: the uncovered members of targets some view not done sees.
  std::vector<std::uint8_t> offered(left.size(), 0);
  for (std::size_t c = 0; c < n; ++c)
    if (!m_done[c])
      for (const std::uint32_t t : m_sees[c]) offered[t] = 1;
  std::uint64_t coverable = 0;
  for (std::size_t t = 0; t < left.size(); ++t) coverable += offered[t] ? left[t] : 0;
  if (double(coverable) <= (1.0 - m_params.oracle_cover_fraction) * double(m_coverable_samples))
    return {};  // the map covers what the oracle can reach
  const double goal = m_params.oracle_cover_fraction * double(coverable);
  // Lazy greedy: a view's gain only falls as views are chosen, so the cached gain over this
  // step's travel time bounds its rate; exact gains are computed best bound first.
  std::vector<std::uint64_t> cached(n);
  for (std::size_t c = 0; c < n; ++c) cached[c] = m_done[c] ? 0 : gain(c);
  std::vector<int> chosen;
  std::vector<std::uint8_t> is_chosen(n, 0);
  int from = nearestPosition(start.head<2>());
  Eigen::Vector2d from_xy = start.head<2>();
  double from_yaw = start.z(), covered = 0;
  std::vector<std::pair<double, int>> order;
  while (covered < goal && int(chosen.size()) < m_params.oracle_max_views) {
    const std::vector<float> field = distanceField(from);
    order.clear();
    for (std::size_t c = 0; c < n; ++c) {
      if (is_chosen[c] || m_done[c] || cached[c] < min_gain) continue;
      const double tt = travelTime(field, from_xy, from_yaw, c);
      if (std::isfinite(tt))
        order.emplace_back(double(cached[c]) / (tt + m_params.oracle_goal_overhead_s), int(c));
    }
    // Best bound first, ties by index: the same inputs choose the same views.
    std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
      return a.first > b.first || (a.first == b.first && a.second < b.second);
    });
    int best = -1;
    double best_rate = -1;
    for (const auto& [bound, c] : order) {
      if (bound <= best_rate) break;
      std::uint64_t g = 0;
      for (const std::uint32_t t : m_sees[std::size_t(c)]) g += left[t];
      cached[std::size_t(c)] = g;
      if (g < min_gain) continue;
      const double rate = double(g) / (travelTime(field, from_xy, from_yaw, std::size_t(c)) +
                                       m_params.oracle_goal_overhead_s);
      if (rate > best_rate) best_rate = rate, best = c;
    }
    if (best < 0) break;
    chosen.push_back(best);
    is_chosen[std::size_t(best)] = 1;
    for (const std::uint32_t t : m_sees[std::size_t(best)]) covered += left[t], left[t] = 0;
    from = int(std::size_t(best) / std::size_t(m_headings));
    from_xy = m_poses[std::size_t(best)].head<2>();
    from_yaw = m_poses[std::size_t(best)].z();
  }
  return chosen;
}

std::vector<int> OraclePlanner::tourThrough(const Eigen::Vector3d& start,
                                            const std::vector<int>& views) const {
  const std::size_t k = views.size();
  if (k < 2) return views;
  // The views' weights: what each adds to the ones before it in the given (cover) order.
  exploration::TourProblem problem;
  problem.weight.resize(k);
  {
    std::vector<std::uint8_t> seen(m_left.size(), 0);
    for (std::size_t i = 0; i < k; ++i) {
      double g = 0;
      for (const std::uint32_t t : m_sees[std::size_t(views[i])])
        if (!seen[t]) seen[t] = 1, g += m_left[t];
      problem.weight[i] = g;
    }
  }
  // Travel times, not symmetric (the turns depend on the direction of travel), plus the goal's
  // overhead (approach and alignment: every goal costs it, whatever the order).
  const double overhead_s = m_params.oracle_tour_overhead_s;
  problem.start_time_s.resize(k);
  problem.time_s = Eigen::MatrixXd::Zero(Eigen::Index(k), Eigen::Index(k));
  for (std::size_t i = 0; i <= k; ++i) {
    const Eigen::Vector3d from = i == 0 ? start : m_poses[std::size_t(views[i - 1])];
    const std::vector<float> field = distanceField(nearestPosition(from.head<2>()));
    for (std::size_t j = 0; j < k; ++j) {
      const double tt = travelTime(field, from.head<2>(), from.z(), std::size_t(views[j]));
      const double cost = (std::isfinite(tt) ? tt : 1e6) + overhead_s;  // (one component)
      if (i == 0)
        problem.start_time_s[j] = cost;
      else if (i - 1 != j)
        problem.time_s(Eigen::Index(i - 1), Eigen::Index(j)) = cost;
    }
  }
  const std::vector<int> order = exploration::solveTour(problem);
  std::vector<int> tour;
  for (const int i : order) tour.push_back(views[std::size_t(i)]);
  return tour;
}

std::vector<Eigen::Vector2d> OraclePlanner::routeTo(const std::vector<float>& field,
                                                    const Eigen::Vector2d& robot_xy,
                                                    std::size_t c) const {
  exploration::ReachableCells reach;
  reach.size_x = m_nx, reach.size_y = m_ny;
  reach.distance_m.assign(std::size_t(m_nx) * m_ny, kInf);
  for (std::size_t i = 0; i < m_positions.size(); ++i)
    reach.distance_m[std::size_t(m_cell_of[i].y()) * m_nx + m_cell_of[i].x()] = field[i];
  const int from = nearestPosition(robot_xy);
  if (from < 0) return {};
  std::vector<Eigen::Vector2d> route;
  for (const Eigen::Vector2i& k : exploration::routeCorners(reach, m_cell_of[std::size_t(from)],
                                                            m_cell_of[c / std::size_t(m_headings)]))
    route.push_back((m_grid_org + m_spacing * k.cast<float>()).cast<double>());
  return route;
}

exploration::ViewCandidate OraclePlanner::candidate(std::size_t c, const std::vector<float>& field,
                                                    const Eigen::Vector3d& robot) const {
  exploration::ViewCandidate v;
  v.source = exploration::ViewCandidate::Source::Oracle;
  v.pose = m_poses[c];
  v.T_world_cam = exploration::cameraPoseOf(v.pose, m_T_base_cam);
  v.reachable = true;
  const float len = field[c / std::size_t(m_headings)];
  v.path_length_m = std::isfinite(len) ? double(len) : 0.0;
  v.travel_time_s = travelTime(field, robot.head<2>(), robot.z(), c);
  v.rotation_rad = (v.travel_time_s - v.path_length_m / m_params.speed_mps) *
                   (m_params.turn_rate_degps * kRadPerDeg);
  v.gain = double(gain(c));
  v.rate = v.gain / (v.travel_time_s + m_params.oracle_goal_overhead_s);
  return v;
}

exploration::Plan OraclePlanner::plan(const exploration::PlannerInputs& in) {
  if (in.store) updateCoverage(*in.store);
  // What a reached view saw is taken as done although the map may not count it yet (a surfel is
  // stable only after several views): otherwise the next cover hops back to views beside it.
  for (std::size_t t = 0; t < m_left.size(); ++t)
    if (m_reached_target[t]) m_left[t] = 0;
  const std::uint64_t min_gain = std::uint64_t(m_params.oracle_min_view_samples);
  // Views done, or whose samples the map has covered meanwhile, leave the tour.
  m_tour.erase(std::remove_if(m_tour.begin(), m_tour.end(),
                              [&](int c) {
                                return m_done[std::size_t(c)] || gain(std::size_t(c)) < min_gain;
                              }),
               m_tour.end());
  if (m_tour.empty()) m_tour = tourThrough(in.robot_pose, greedyCover(in.robot_pose));
  exploration::Plan p;
  const std::vector<float> field = distanceField(nearestPosition(in.robot_pose.head<2>()));
  for (const int c : m_tour) p.ranked.push_back(candidate(std::size_t(c), field, in.robot_pose));
  if (!m_tour.empty()) p.route = routeTo(field, in.robot_pose.head<2>(), std::size_t(m_tour[0]));
  return p;
}

void OraclePlanner::goalOutcome(const Eigen::Vector3d& goal_xyyaw, bool reached) {
  if (!reached) m_blacklist.add(goal_xyyaw);
  for (std::size_t c = 0; c < m_poses.size(); ++c) {
    const double d = (m_poses[c].head<2>() - goal_xyyaw.head<2>()).norm();
    const bool this_view =
        d < 1e-6 && std::abs(mrpt::math::wrapToPi(m_poses[c].z() - goal_xyyaw.z())) < 1e-6;
    if (reached ? this_view : d <= m_params.blacklist_radius_m) m_done[c] = 1;
    if (reached && this_view)
      for (const std::uint32_t t : m_sees[c]) m_reached_target[t] = 1;
  }
}

}  // namespace rasm::autonomy
