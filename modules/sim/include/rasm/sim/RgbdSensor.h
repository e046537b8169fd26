#pragma once
// Simulated RGB-D camera: a pinhole camera ray-cast into a RayScene on the CPU (Embree packets
// of 4x4 pixels, OpenMP over tile rows). Per frame it produces a rasm::RgbdFrame with
//  - colour: Lambertian + ambient shading of the procedural materials (BGR),
//  - depth_m: exact z with the Kinect v1 noise and missing-data model of
//    kernels/DepthSensorModel.h (noise = false gives the exact depth),
//  - gt_instance / gt_class: the instance and class id of the surface each pixel's ray hits
//    (ground truth, independent of depth dropouts), gt_T_world_cam.
// Colour is registered to depth (one camera). Output is deterministic for a given (seed, frame
// index) whatever the number of threads. One sensor renders one frame at a time (render() reuses
// scratch buffers): use one RgbdSensor per thread.

#include <mrpt/config/CLoadableOptions.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <string>

#include "rasm/core/CameraIntrinsics.h"
#include "rasm/core/Image.h"
#include "rasm/core/RgbdFrame.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/kernels/DepthSensorModel.h"

namespace rasm::sim {

/// INI section [sim_sensor] (keys as the member names).
struct TSensorParams : public mrpt::config::CLoadableOptions {
  /// rasm::CameraIntrinsics::preset name; the six values below override it when > 0.
  std::string camera = "kinect_v1";
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;

  double min_depth_m = 0.4;  ///< Kinect v1 operating range
  double max_depth_m = 4.5;
  /// Axial + lateral noise and disparity quantization; false = exact depth.
  bool noise = true;
  /// Projector-shadow and grazing-angle dropouts.
  bool dropouts = true;
  // Nguyen, Izadi & Lovell 2012 (see kernels/DepthSensorModel.h).
  double axial_sigma0_m = 0.0012;
  double axial_sigma_quad = 0.0019;
  double axial_z0_m = 0.4;
  double axial_sigma_angle = 0.0001;
  /// sigma_L in pixels of the `camera` preset's image; a render with another fx gets it scaled by
  /// fx / the preset's fx (the same angular noise), see depthModel().
  double lateral_sigma_px = 0.8;
  double lateral_sigma_angle = 0.035;
  // Disparity quantization (Kinect v1: 1/8 px at f = 580 px, b = 0.075 m); 0 subpixel = off.
  double disparity_focal_px = 580.0;
  double disparity_baseline_m = 0.075;
  double disparity_subpixel = 8.0;
  /// IR projector position along the camera x axis (m); 0 = no shadows.
  double projector_offset_m = 0.075;
  double grazing_max_deg = 80.0;
  /// Render gt_instance / gt_class.
  bool labels = true;
  /// 4x4 ray packets (rtcIntersect16); false = one rtcIntersect1 per pixel (for benchmarks).
  bool ray_packets = true;

  CameraIntrinsics intrinsics() const;
  /// The depth model the kernels run with these settings.
  DepthModelParams depthModel() const;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                        const std::string& section) const override;
  /// Throws InputError naming [section] key for out-of-range values.
  void validate(const std::string& section = "sim_sensor") const;
};

class RgbdSensor {
 public:
  RgbdSensor(const RayScene& scene, const TSensorParams& params);

  const CameraIntrinsics& intrinsics() const { return m_K; }
  const TSensorParams& params() const { return m_params; }

  /// Renders the view from T_world_cam (optical frame). Noise depends only on (seed,
  /// frame_index). `out` keeps its buffers between calls (no reallocation at steady state).
  void render(const Eigen::Isometry3d& T_world_cam, std::uint64_t seed, std::size_t frame_index,
              RgbdFrame& out) const;
  RgbdFrame render(const Eigen::Isometry3d& T_world_cam, std::uint64_t seed = 0,
                   std::size_t frame_index = 0) const;

  /// The key of the per-pixel counter RNG for a frame: first outputs of a std::mt19937 seeded
  /// with (seed, frame_index).
  static std::uint64_t frameKey(std::uint64_t seed, std::size_t frame_index);

  /// Wall-clock milliseconds of the stages of the last render() (for benchmarks).
  struct StageTimes {
    double cast_ms = 0;         ///< ray casting, shading, labels
    double shadow_ms = 0;       ///< projector shadows (ProjectorShadowRows)
    double depth_model_ms = 0;  ///< DepthMeasurementKernel, its normal variates included
  };
  const StageTimes& lastStageTimes() const { return m_times; }

 private:
  const RayScene& m_scene;
  TSensorParams m_params;
  CameraIntrinsics m_K;
  // Scratch images of the last render (exact depth, cos of the incidence angle, projector shadow).
  mutable Image<float> m_z, m_cos;
  mutable Image<std::uint8_t> m_shadow;
  mutable StageTimes m_times;
};

}  // namespace rasm::sim
