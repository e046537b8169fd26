#pragma once
// Rendering the surfel map from a camera pose (II-A "simple surfel splatting (forward projection
// and depth culling)") and the 4x super-sampled point index map of map fusion (II-D).
//
// Pipeline of one render, all O(B + S_in) (VoxelBlockIndex.h):
//   1. cull spatial-index blocks against the camera frustum (grown by the largest splat radius);
//   2. collect the surfels of the visited blocks that pass the filters (stable only, confidence,
//      time window, depth range) and whose footprint reaches the image;
//   3. splat: every surfel draws a disc of its radius in its own plane; each pixel of the disc's
//      projected bounding box whose ray hits the disc competes with depth = camera z of the
//      ray/disc intersection. The depth test is a 64-bit atomic min of (depth bits << 32 | index):
//      race-free on CUDA and deterministic (ties go to the lower index). The CPU launcher gets the
//      same result without atomics: one parallel pass over the visited blocks' members projects
//      them and computes their footprints (SSE, four surfels at a time, the kernel's float
//      operations per lane) and bins the footprints by row band, then each thread
//      depth-tests whole bands with plain min writes, four pixels per SSE operation (a locked
//      compare-exchange per pixel serialised the memory accesses). Either way the result does
//      not depend on thread count or scheduling;
//   4. resolve: per pixel, the winning surfel's attributes are written to the requested outputs
//      (on the CPU per band, right after its depth test).
//
// Frames and conventions: T_world_cam maps optical camera coordinates (x right, y down, z forward)
// to world. Rendered vertex and normal maps are in the WORLD frame (as in ElasticFusion, what the
// tracker of II-C consumes); depth is the camera-frame z. In splat mode the vertex is the
// ray/disc intersection (so a plane renders at its exact depth); in point mode it is the surfel
// centre. Invalid pixels: index -1, depth 0, vertex/normal x = NaN, segment 0.

#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <vector>

#include "rasm/compute/Parallel.h"
#include "rasm/core/CameraIntrinsics.h"
#include "rasm/core/Image.h"
#include "rasm/surfel_map/SurfelStore.h"
#include "rasm/surfel_map/kernels/RenderKernels.h"

namespace rasm::maps {

enum RenderOutput : unsigned {
  kRenderDepth = 1u << 0,
  kRenderVertex = 1u << 1,
  kRenderNormal = 1u << 2,
  kRenderColour = 1u << 3,
  kRenderConfidence = 1u << 4,
  kRenderSegment = 1u << 5,
  kRenderAll = 0x3fu,
};

struct RenderOptions {
  float min_depth_m = 0.1f;
  float max_depth_m = 10.0f;
  bool stable_only = false;  ///< II-C: ICP renders only stable surfels
  float min_confidence = 0.0f;
  /// Render only surfels fused at or after now_s - time_window_s (absolute seconds), as in
  /// ElasticFusion's active-model window. Infinite window (default) = no time filter.
  double time_window_s = std::numeric_limits<double>::infinity();
  double now_s = 0.0;
  /// Render only surfels created (t_init) at or after created_after_s and before
  /// created_before_s (absolute s): the map an earlier pass made and the map made recently, that
  /// a loop closure registers the frame against. NaN (default) = no bound.
  double created_after_s = std::numeric_limits<double>::quiet_NaN();
  double created_before_s = std::numeric_limits<double>::quiet_NaN();
  bool cull_back_faces = false;  ///< drop surfels whose normal faces away from the camera
  /// true: discs of the surfel radius; false: one pixel (the rounded projection) per surfel.
  bool splat = true;
  /// Projected splat radius clamp in pixels: bounds the cost of surfels very close to the camera.
  float max_splat_radius_px = 12.0f;
  unsigned outputs = kRenderAll;  ///< RenderOutput bits; the index map is always produced
};

/// Model maps predicted from the map at a pose (II-A: C^r, D^r, V^r, N^r, L^r and I^r).
struct RenderedMaps {
  Image<std::int32_t> index;     ///< I^r: surfel index, -1 none
  Image<float> depth_m;          ///< D^r: camera-frame z (m), 0 none
  Image<Vec3f> vertex_world;     ///< V^r: WORLD frame, x = NaN none
  Image<Vec3f> normal_world;     ///< N^r: WORLD frame unit normal, x = NaN none
  Image<Bgr8> colour;            ///< C^r: B,G,R; black none
  Image<float> confidence;       ///< w of the surfel, 0 none
  Image<std::uint32_t> segment;  ///< L^r: segment label, 0 none
};

/// What a render touched, for tests of the culling (counts, not time) and for reports.
struct RenderStats {
  int blocks_total = 0;    ///< non-empty blocks in the map
  int blocks_visited = 0;  ///< blocks that passed frustum culling
  long long surfels_tested =
      0;  ///< members of the visited blocks (their stable ones with stable_only)
  long long surfels_drawn = 0;  ///< surfels that passed all tests and were splatted / projected
  long long pixels_drawn =
      0;  ///< pixels of render() a surfel won (index >= 0); not set by the 4x renders
};

/// 4x super-sampled point index map of II-D: every surfel in view is projected as a POINT into a
/// (4 W) x (4 H) grid, keeping the nearest per sub-pixel. Sub-pixel (sx, sy) covers the continuous
/// image area [sx/4 - 0.5, (sx+1)/4 - 0.5) x [...], so the 4x4 block of frame pixel (x, y) is
/// sub-pixels [4x, 4x+3] x [4y, 4y+3] and holds exactly the surfels whose projection rounds to
/// (x, y): each surfel is a candidate of one frame pixel only (fusion updates are race-free).
struct IndexMap4x {
  static constexpr int kScale = 4;
  int width = 0, height = 0;          ///< of the frame; packed is 4*width x 4*height
  Image<std::uint64_t> packed;        ///< (float depth bits << 32) | surfel index; ~0 = empty
  std::vector<int> visible;           ///< surfels projected by the last render (any order)
  std::vector<std::int64_t> touched;  ///< sub-pixels written by the last render (sparse clear)

  /// Surfel index at sub-pixel (sx, sy), -1 none.
  std::int32_t index(int sx, int sy) const {
    const std::uint64_t v = packed(sx, sy);
    return v == ~std::uint64_t(0) ? -1 : std::int32_t(std::uint32_t(v));
  }
};

/// The 4x point index map of II-D in compact form, for the CPU fusion path: for every frame pixel
/// the same candidates as IndexMap4x (the nearest surfel of each of its 16 sub-pixels), stored as
/// one contiguous list per pixel together with the camera-frame centre the projection computed.
/// Memory is O(surfels in view), not O(16 W H): nothing has to be cleared between frames, and a
/// pixel's candidates are read sequentially.
struct PointCandidates4x {
  int width = 0, height = 0;
  /// Per pixel p = y * width + x: entries[first[p], first[p] + count[p]) are its candidates; the
  /// rest of its range, up to first[p + 1], are surfels projecting there that another surfel of
  /// the same sub-pixel hides.
  std::vector<std::uint32_t> first;
  std::vector<std::uint8_t> count;
  std::vector<kernels::CameraPoint> entries;
  /// Surfels that passed the render filters but project outside the 4x grid or depth range.
  /// entries + others = every visible surfel (collectVisible's set: free-space carving's input).
  std::vector<kernels::CameraPoint> others;

  std::size_t numVisible() const { return entries.size() + others.size(); }
};

class SurfelRenderer {
 public:
  explicit SurfelRenderer(compute::Backend backend = compute::Backend::Cpu) : backend_(backend) {}
  void setBackend(compute::Backend b) { backend_ = b; }
  compute::Backend backend() const { return backend_; }

  /// Splat (opt.splat) or point rendering of the model maps at T_world_cam (II-A).
  void render(const SurfelStore& map, const Eigen::Isometry3d& T_world_cam,
              const CameraIntrinsics& K, const RenderOptions& opt, RenderedMaps& out,
              RenderStats* stats = nullptr);

  /// The 4x point index map used by fusion (II-D). opt.splat and opt.outputs are ignored.
  void renderIndexMap4x(const SurfelStore& map, const Eigen::Isometry3d& T_world_cam,
                        const CameraIntrinsics& K, const RenderOptions& opt, IndexMap4x& out,
                        RenderStats* stats = nullptr);

  /// The same candidates as renderIndexMap4x in compact per-pixel lists (CPU only; the backend is
  /// ignored). opt.splat and opt.outputs are ignored.
  void renderCandidates4x(const SurfelStore& map, const Eigen::Isometry3d& T_world_cam,
                          const CameraIntrinsics& K, const RenderOptions& opt,
                          PointCandidates4x& out, RenderStats* stats = nullptr);

  /// Surfels of the frustum-culled blocks that pass the filters of `opt` and whose centre projects
  /// within `margin_px` of the image, in increasing block id then member order.
  void collectVisible(const SurfelStore& map, const Eigen::Isometry3d& T_world_cam,
                      const CameraIntrinsics& K, const RenderOptions& opt, float margin_px,
                      std::vector<int>& visible, RenderStats* stats = nullptr) const;

 private:
  /// Frustum-culled blocks and the per-surfel filters of a render (shared set-up).
  struct Culling;
  void cull(const SurfelStore& map, const Eigen::Isometry3d& T_world_cam, const CameraIntrinsics& K,
            const RenderOptions& opt, float margin_px, Culling& c) const;
  void splatCpu(const SurfelStore& map, const Eigen::Isometry3d& T_world_cam,
                const CameraIntrinsics& K, const RenderOptions& opt, RenderedMaps& out,
                RenderStats* stats);

  compute::Backend backend_;
  std::vector<int> visible_;
  Image<std::uint64_t> packed_;
  mutable std::vector<std::vector<int>> per_block_;  ///< collectVisible scratch (not thread safe)
  std::vector<std::int64_t> ids_;
  std::vector<std::uint64_t> values_;
  // CPU splat: footprints per (thread, row band). 4x candidates: per (thread, image row) the
  // projected points with their sub-pixel, and per thread the points outside the grid.
  std::vector<std::vector<kernels::SplatFootprint>> band_fp_;
  struct RowPoint {
    kernels::CameraPoint p;
    std::uint16_t column;  ///< frame pixel column
    std::uint8_t sub;      ///< sub-pixel in the 4x4 block, row-major
  };
  std::vector<std::vector<RowPoint>> row_points_;
  /// Row y of renderCandidates4x's third step: its projected surfels (row_points_ of the `team`
  /// threads) counting-sorted by column into out.entries[b, e), each pixel's candidates (the
  /// nearest surfel of each of its sub-pixels) first; out.first and out.count of the row. `col`
  /// (width + 1) and `sorted` are the calling thread's scratch.
  void sortCandidateRow(int y, int team, std::uint32_t b, std::uint32_t e,
                        std::vector<std::uint32_t>& col, std::vector<RowPoint>& sorted,
                        PointCandidates4x& out) const;
  std::vector<std::vector<kernels::CameraPoint>> others_;
  std::vector<std::vector<std::uint32_t>> column_counts_;
  std::vector<std::vector<RowPoint>> row_scratch_;
};

namespace cuda {
/// CUDA launchers of the splat / point kernels (cuda/SurfelRender.cu). They take the visible list
/// computed on the host, copy the arrays the kernels read to the device, and return the whole
/// packed depth/index buffer (`packed` keeps its size: W x H, or 4W x 4H for the 4x map).
/// opt.splat = false renders points. Throw std::runtime_error when built without CUDA or without a
/// device. Reference launchers: the map is not resident on the device, so transfers dominate.
void splatPacked(const SurfelArrays& arrays, const std::vector<int>& visible,
                 const RigidF& T_cam_world, const PinholeF& K, const RenderOptions& opt,
                 Image<std::uint64_t>& packed);
void pointsPacked4x(const SurfelArrays& arrays, const std::vector<int>& visible,
                    const RigidF& T_cam_world, const PinholeF& K, const RenderOptions& opt,
                    Image<std::uint64_t>& packed4x, std::vector<std::int64_t>& touched);
}  // namespace cuda

}  // namespace rasm::maps
