#pragma once
// TUM fr3/cabinet keyframes (../shared/data/tum/fr3_cabinet_keyframes, README there): the
// ground-truth cabinet cuboid projected into each keyframe with its ground-truth pose, for the
// zero-shot classifier's real-data check (ZeroShot_unittest.cpp, bench_zero_shot --tum-cabinet).
// truth_objects.txt: "x y z yaw half_x half_y half_z" (world frame, z up, metres, radians);
// truth_cam_poses.txt row k: "timestamp tx ty tz qx qy qz qw" (T_world_cam, optical frame);
// images raw_imgs/NNNN_rgb_raw.jpg; freiburg3 intrinsics fx 535.4 fy 539.2 cx 320.1 cy 247.6.

#include <Eigen/Geometry>
#include <algorithm>
#include <fstream>
#include <opencv2/core/types.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace rasm::test {

struct CabinetKeyframe {
  std::string image_path;
  cv::Rect box;        ///< the projected cuboid's bounding box, clipped to the 640 x 480 image
  double visible = 0;  ///< fraction of the unclipped projected box inside the image
};

/// Keyframes whose projected cuboid lies entirely in front of the camera; empty when the folder
/// or its files are missing.
inline std::vector<CabinetKeyframe> loadCabinetKeyframes(const std::string& dir) {
  std::ifstream objects(dir + "/truth_objects.txt"), poses(dir + "/truth_cam_poses.txt");
  std::vector<CabinetKeyframe> out;
  double c[3], yaw, half[3];
  if (!(objects >> c[0] >> c[1] >> c[2] >> yaw >> half[0] >> half[1] >> half[2])) return out;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Vector3d> corners;
  for (int k = 0; k < 8; ++k)
    corners.push_back(Eigen::Vector3d(c[0], c[1], c[2]) +
                      R * Eigen::Vector3d((k & 1 ? 1 : -1) * half[0], (k & 2 ? 1 : -1) * half[1],
                                          (k & 4 ? 1 : -1) * half[2]));
  const double fx = 535.4, fy = 539.2, cx = 320.1, cy = 247.6;
  std::string line;
  for (int index = 0; std::getline(poses, line); ++index) {
    std::istringstream s(line);
    double t, p[3], q[4];
    if (!(s >> t >> p[0] >> p[1] >> p[2] >> q[0] >> q[1] >> q[2] >> q[3])) continue;
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
    T_world_cam.linear() =
        Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized().toRotationMatrix();
    T_world_cam.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
    double u0 = 1e9, v0 = 1e9, u1 = -1e9, v1 = -1e9;
    bool in_front = true;
    for (const auto& w : corners) {
      const Eigen::Vector3d pc = T_world_cam.inverse() * w;
      in_front = in_front && pc.z() > 0.1;
      const double u = fx * pc.x() / pc.z() + cx, v = fy * pc.y() / pc.z() + cy;
      u0 = std::min(u0, u), v0 = std::min(v0, v), u1 = std::max(u1, u), v1 = std::max(v1, v);
    }
    if (!in_front) continue;
    std::string number = std::to_string(index);
    number.insert(0, number.size() < 4 ? 4 - number.size() : 0, '0');
    CabinetKeyframe k;
    k.image_path = dir + "/raw_imgs/" + number + "_rgb_raw.jpg";
    const cv::Rect full{cv::Point(int(u0), int(v0)), cv::Point(int(u1), int(v1))};
    k.box = full & cv::Rect(0, 0, 640, 480);
    k.visible = full.area() > 0 ? double(k.box.area()) / full.area() : 0.0;
    out.push_back(k);
  }
  return out;
}

}  // namespace rasm::test
