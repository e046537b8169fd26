#pragma once
// Host API of the per-frame preprocessing of II-A: vertex/normal maps and depth pyramids, on the
// CPU (OpenMP, the reference) or through the CUDA launcher of the same kernels.

#include <vector>

#include "rasm/compute/Parallel.h"
#include "rasm/core/CameraIntrinsics.h"
#include "rasm/core/Image.h"

namespace rasm {

struct VertexMapOptions {
  float min_depth_m = 0.1f;
  float max_depth_m = 10.0f;
};

void computeVertexMap(const Image<float>& depth_m, const CameraIntrinsics& K, Image<Vec3f>& vertex,
                      const VertexMapOptions& opt = {},
                      compute::Backend backend = compute::Backend::Cpu);
void computeNormalMap(const Image<Vec3f>& vertex, Image<Vec3f>& normal, float max_jump_rel = 0.05f,
                      compute::Backend backend = compute::Backend::Cpu);
void downsampleDepth(const Image<float>& in, Image<float>& out, float max_diff_m = 0.03f);
/// Edge-preserving bilateral filter of depth (kernels::BilateralDepthKernel's filter): circular
/// window of `radius` 0..3 pixels (std::invalid_argument otherwise), invalid pixels (<= 0, NaN)
/// stay 0 and do not contribute. `in` and `out` must differ.
void bilateralFilterDepth(const Image<float>& in, Image<float>& out, int radius = 2,
                          float sigma_space_px = 4.5f, float sigma_depth_m = 0.03f);

/// One pyramid level: depth, intrinsics, vertex and normal maps in the camera frame.
struct FrameLevel {
  CameraIntrinsics K;
  Image<float> depth_m;
  Image<Vec3f> vertex;
  Image<Vec3f> normal;
};

/// Levels 0 (full) .. n-1 (each half the previous), as used coarse to fine by ICP (II-C).
void buildFramePyramid(const Image<float>& depth_m, const CameraIntrinsics& K, int levels,
                       std::vector<FrameLevel>& pyramid, const VertexMapOptions& opt = {});

namespace cuda {
/// CUDA launchers of VertexMapKernel / NormalMapKernel (src/../cuda/FrameKernels.cu). They throw
/// std::runtime_error when built without CUDA or when no device is present.
void computeVertexMap(const Image<float>& depth_m, const CameraIntrinsics& K, Image<Vec3f>& vertex,
                      const VertexMapOptions& opt);
void computeNormalMap(const Image<Vec3f>& vertex, Image<Vec3f>& normal, float max_jump_rel);
}  // namespace cuda

}  // namespace rasm
