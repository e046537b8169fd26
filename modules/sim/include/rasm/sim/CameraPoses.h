#pragma once
// Camera poses in the world (z up) as optical-frame T_world_cam (x right, y down, z forward).

#include <Eigen/Geometry>

namespace rasm::sim {

/// Camera at `eye` heading `yaw_deg` (about world z, 0 = +x), `pitch_deg` (positive = looking
/// up) and `roll_deg` (about the viewing direction, positive = clockwise as seen by the camera).
Eigen::Isometry3d cameraPoseFromHeading(const Eigen::Vector3d& eye, double yaw_deg,
                                        double pitch_deg, double roll_deg = 0.0);

/// Camera at `eye` looking at `target`, image up towards world +z (no roll). Throws
/// std::invalid_argument when target == eye or the view is exactly vertical.
Eigen::Isometry3d cameraPoseLookingAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target);

/// Planar robot pose (x, y, yaw) as a 3-D pose of its base frame (x forward, y left, z up; z = 0).
Eigen::Isometry3d basePose(double x, double y, double yaw_rad);

}  // namespace rasm::sim
