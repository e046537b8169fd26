#pragma once
// The INI text that configures mrpt::nav::CReactiveNavigationSystem from TNavigationParams and the
// robot footprint (internal to navigation/).

#include <Eigen/Core>
#include <string>
#include <vector>

#include "rasm/navigation/TNavigationParams.h"

namespace rasm::navigation {

/// Footprint polygon grown radially by `margin_m` (each vertex moved away from the origin).
std::vector<Eigen::Vector2f> growFootprint(const std::vector<Eigen::Vector2f>& footprint,
                                           double margin_m);

/// Sections CAbstractNavigator ... CReactiveNavigationSystem after
/// /usr/share/mrpt/config_files/navigation-ptgs/reactive2d_config.ini.
std::string reactiveConfigText(const TNavigationParams& p,
                               const std::vector<Eigen::Vector2f>& footprint);

}  // namespace rasm::navigation
