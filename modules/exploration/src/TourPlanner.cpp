// "ig": the global planner (ExplorationPlanners.h TourIgPlanner; the tour: ViewTour.h).
#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "rasm/exploration/ExplorationPlanners.h"
#include "rasm/exploration/PlanningGrid.h"
#include "rasm/exploration/ViewTour.h"

namespace rasm::exploration {

namespace {
TExplorationParams withFrontierViews(TExplorationParams params) {
  params.frontier_candidates = true;
  return params;
}
}  // namespace

TourIgPlanner::TourIgPlanner(const TExplorationParams& params)
    : IgPlanner(withFrontierViews(params)) {}

std::vector<int> clusterViews(const std::vector<ViewCandidate>& views,
                              const std::vector<double>& gains, double radius_m, int max_clusters,
                              double min_gain_fraction) {
  std::vector<int> order(views.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&gains](int a, int b) {
    return gains[std::size_t(a)] > gains[std::size_t(b)];
  });
  std::vector<int> heads;
  if (order.empty()) return heads;
  const double floor_gain = min_gain_fraction * gains[std::size_t(order.front())];
  for (const int i : order) {
    const ViewCandidate& v = views[std::size_t(i)];
    const double gain = gains[std::size_t(i)];
    if (gain <= 0.0 || gain < floor_gain || int(heads.size()) >= max_clusters) break;
    const bool joins = std::any_of(heads.begin(), heads.end(), [&](int h) {
      return (views[std::size_t(h)].pose.head<2>() - v.pose.head<2>()).norm() <= radius_m;
    });
    if (!joins) heads.push_back(i);
  }
  return heads;
}

Eigen::MatrixXd legTimes(const mrpt::maps::COccupancyGridMap2D& grid,
                         const std::vector<ViewCandidate>& views,
                         const TExplorationParams& params) {
  const int n = int(views.size());
  const double turn_rate = params.turn_rate_degps * M_PI / 180.0;
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d& a = views[std::size_t(i)].pose;
    const ReachableCells reach = reachableCells(grid, a, params.footprint_radius_m);
    for (int j = 0; j < n; ++j) {
      if (i == j) continue;
      const Eigen::Vector3d& b = views[std::size_t(j)].pose;
      const Eigen::Vector2d d = b.head<2>() - a.head<2>();
      const double straight = d.norm();
      double path = reach.distance(grid.x2idx(b.x()), grid.y2idx(b.y()));
      // Both views are reachable from the robot, so from each other; the grid's 8-connected
      // Dijkstra can still miss a cell that PlannerSimple2D reached: twice the straight line.
      if (!std::isfinite(path)) path = 2.0 * straight;
      double turn = std::abs(mrpt::math::wrapToPi(b.z() - a.z()));
      if (straight > grid.getResolution()) {  // turn to the leg's bearing, drive, turn to b's yaw
        const double bearing = std::atan2(d.y(), d.x());
        turn = std::abs(mrpt::math::wrapToPi(bearing - a.z())) +
               std::abs(mrpt::math::wrapToPi(b.z() - bearing));
      }
      t(i, j) = path / params.speed_mps + turn / turn_rate;
    }
  }
  return t;
}

double TourIgPlanner::objectWeight(const OccupancyOctree& octree) {
  const double entropy = octree.entropy();
  if (m_first_entropy_nats < 0.0) m_first_entropy_nats = entropy;
  if (!(m_first_entropy_nats > 0.0)) return 1.0;
  return std::clamp(1.0 - entropy / m_first_entropy_nats, 0.0, 1.0);
}

double TourIgPlanner::revisitDiscount(const Eigen::Vector3d& pose) const {
  int visits = 0;
  for (const Eigen::Vector3d& t : m_taken)
    visits += (t.head<2>() - pose.head<2>()).norm() <= m_params.tour_revisit_radius_m;
  return std::pow(m_params.tour_revisit_discount, double(visits));
}

double knownFraction(const mrpt::maps::COccupancyGridMap2D& grid, const Eigen::Vector2d& at,
                     double radius_m) {
  const double res = grid.getResolution();
  const int r = int(std::ceil(radius_m / res));
  const int cx = grid.x2idx(at.x()), cy = grid.y2idx(at.y());
  int cells = 0, known = 0;
  for (int iy = cy - r; iy <= cy + r; ++iy)
    for (int ix = cx - r; ix <= cx + r; ++ix) {
      if (std::hypot(grid.idx2x(ix) - at.x(), grid.idx2y(iy) - at.y()) > radius_m) continue;
      ++cells;  // (outside the grid: outside the workspace, never known)
      if (ix < 0 || iy < 0 || ix >= int(grid.getSizeX()) || iy >= int(grid.getSizeY())) continue;
      known += !unknownCell(grid.getCell(ix, iy));
    }
  return cells > 0 ? double(known) / cells : 0.0;
}

double TourIgPlanner::tourWeight(const ViewCandidate& v, const Plan& plan,
                                 const TExplorationParams& tour_params) const {
  const bool frontier = v.source == ViewCandidate::Source::Frontier;
  double dH = v.entropy_reduction;
  if (frontier) dH = std::max(dH, m_params.tour_behind_fraction * v.entropy_behind);
  double w = informationGain(tour_params, dH, v.information, plan.best_entropy_reduction,
                             plan.best_information);
  if (v.source == ViewCandidate::Source::Object && m_params.tour_object_context_radius_m > 0.0)
    w *= knownFraction(plan.grid, v.target_xy, m_params.tour_object_context_radius_m);
  // A frontier view looks into unknown space wherever the robot has been (the doorway of a room
  // beside the hallway views it took): the revisit discount is for known regions.
  return (frontier && !m_params.tour_revisit_frontiers ? 1.0 : revisitDiscount(v.pose)) * w;
}

Plan TourIgPlanner::plan(const PlannerInputs& in) {
  Plan plan = IgPlanner::plan(in);
  // The tour's weights: IG with the object term scaled by how far the map's entropy has fallen.
  TExplorationParams tour_params = m_params;
  tour_params.w_ic *= objectWeight(*in.octree);
  std::vector<double> gains;
  for (const ViewCandidate& v : plan.ranked) gains.push_back(tourWeight(v, plan, tour_params));
  const std::vector<int> heads =
      clusterViews(plan.ranked, gains, m_params.tour_cluster_radius_m, m_params.tour_max_clusters,
                   m_params.tour_min_gain_fraction);
  if (heads.empty()) return plan;
  std::vector<ViewCandidate> head_views;
  TourProblem tour;
  for (const int h : heads) {
    const ViewCandidate& v = plan.ranked[std::size_t(h)];
    head_views.push_back(v);
    tour.start_time_s.push_back(v.travel_time_s);
    tour.weight.push_back(gains[std::size_t(h)]);
  }
  tour.time_s = legTimes(plan.grid, head_views, m_params);
  const std::vector<int> order = solveTour(tour);
  std::vector<ViewCandidate> ranked;
  std::vector<char> is_head(plan.ranked.size(), 0);
  for (const int k : order) {
    ranked.push_back(head_views[std::size_t(k)]);
    plan.tour_weights.push_back(tour.weight[std::size_t(k)]);
  }
  for (const int h : heads) is_head[std::size_t(h)] = 1;
  for (std::size_t i = 0; i < plan.ranked.size(); ++i)
    if (!is_head[i]) ranked.push_back(plan.ranked[i]);
  plan.ranked = std::move(ranked);
  plan.tour_clusters = heads.size();
  return plan;
}

}  // namespace rasm::exploration
