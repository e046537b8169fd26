#pragma once
// Goals not to offer again ("blacklisting" of goals the navigation failed to reach; the
// frontier baseline also lists the frontiers it has visited). A candidate is blacklisted when its
// base (x, y) lies within radius_m of a listed goal; headings are ignored (a failed goal is a
// place the robot cannot get to, whichever way it faces).
// Age: with max_age_plans = 0 (what the planners use) entries are permanent for the run: the
// planners cannot tell whether the map change that would make a failed goal reachable has
// happened, and a goal retried forever is the failure blacklisting exists to stop. With
// max_age_plans = n > 0 an entry is dropped after n calls of tick() (planners tick once per plan),
// for a caller that wants failed places retried once the map has grown.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rasm::exploration {

class GoalBlacklist {
 public:
  explicit GoalBlacklist(double radius_m = 0.5, int max_age_plans = 0);

  /// Lists a goal (x, y, yaw); its age starts at 0.
  void add(const Eigen::Vector3d& goal_xyyaw);
  /// Whether pose's (x, y) is within radius_m of a listed goal (inclusive).
  bool contains(const Eigen::Vector3d& pose_xyyaw) const;
  std::size_t size() const { return m_entries.size(); }
  void clear() { m_entries.clear(); }
  /// One plan has passed: with max_age_plans > 0, entries added max_age_plans ticks ago or more
  /// are dropped.
  void tick();

  double radius() const { return m_radius; }
  int maxAgePlans() const { return m_max_age; }

 private:
  struct Entry {
    Eigen::Vector2d xy;
    std::int64_t added_at = 0;
  };
  double m_radius;
  int m_max_age;
  std::int64_t m_ticks = 0;
  std::vector<Entry> m_entries;
};

}  // namespace rasm::exploration
