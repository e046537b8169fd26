#include "rasm/exploration/GoalBlacklist.h"

#include <algorithm>

#include "rasm/core/Error.h"

namespace rasm::exploration {

GoalBlacklist::GoalBlacklist(double radius_m, int max_age_plans)
    : m_radius(radius_m), m_max_age(max_age_plans) {
  if (!(radius_m >= 0.0)) throwInputError("goal blacklist radius", "must be >= 0");
  if (max_age_plans < 0) throwInputError("goal blacklist max age", "must be >= 0 (0 = permanent)");
}

void GoalBlacklist::add(const Eigen::Vector3d& goal_xyyaw) {
  m_entries.push_back({goal_xyyaw.head<2>(), m_ticks});
}

bool GoalBlacklist::contains(const Eigen::Vector3d& pose_xyyaw) const {
  const Eigen::Vector2d xy = pose_xyyaw.head<2>();
  return std::any_of(m_entries.begin(), m_entries.end(),
                     [&](const Entry& e) { return (e.xy - xy).norm() <= m_radius; });
}

void GoalBlacklist::tick() {
  ++m_ticks;
  if (m_max_age == 0) return;
  m_entries.erase(std::remove_if(m_entries.begin(), m_entries.end(),
                                 [&](const Entry& e) { return m_ticks - e.added_at >= m_max_age; }),
                  m_entries.end());
}

}  // namespace rasm::exploration
