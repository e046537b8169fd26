#pragma once
// Surfel map fusion of one RGB-D frame at a known pose (II-B, II-D, with the segment weights of
// III and the view-information bins / basis of V-B), in four public passes that run in this order
// for a frame (fuse() runs them all; the Mapper runs 1 in one stage, the rest in a later one, so
// label propagation (III) reads the index map at T_t before the surfels are updated):
//   1. renderIndexMap: the 4x point index map of the map at T_world_cam (SurfelRenderer, II-D; on
//   the CPU
//      as compact per-pixel candidate lists, renderCandidates4x);
//   2. updateSurfels: per pixel (parallel), pick the most similar candidate in the pixel's 4x4
//   sub-pixel block
//      (depth along the ray and normal angle gate it; cost = normalised ray distance + normal
//      angle + radius ratio); then, in a second pass (race-free: each surfel is a candidate of one
//      pixel only), update it by confidence-weighted averaging (Keller et al. 2013), accumulate w,
//      update t_last, the stability flag, the segment weight (L^p), the basis b <- -n x (n x b)
//      and the view bins;
//   3. addSurfels: pixels without a match become new surfels (II-B), appended in row-major pixel
//   order through
//      a per-row count + prefix sum (deterministic);
//   4. cleanup: merge redundant surfels of the view (Keller et al. 2013), carve free space,
//      remove unstable surfels past their age / idle limits.
// Per frame the cost is O(pixels + surfels in view): nothing scans the whole map (pruning keeps a
// schedule of the unstable surfels, PruneSchedule.h).
// Works on the MRPT-free SurfelStore; CSurfelMap::store() gives it.

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "rasm/compute/ImageView.h"
#include "rasm/compute/Parallel.h"
#include "rasm/core/CameraIntrinsics.h"
#include "rasm/core/Image.h"
#include "rasm/core/RgbdFrame.h"
#include "rasm/fusion/PruneSchedule.h"
#include "rasm/fusion/TFusionParams.h"
#include "rasm/fusion/ViewInfoThresholds.h"
#include "rasm/fusion/kernels/FusionKernels.h"
#include "rasm/surfel_map/SurfelRenderer.h"
#include "rasm/surfel_map/SurfelStore.h"

namespace rasm::fusion {

/// One frame as fusion needs it. All images have the intrinsics' size; views stay owned by the
/// caller. vertex_cam / normal_cam are V_t, N_t of II-A in the CAMERA frame (computeVertexMap /
/// computeNormalMap of core; invalid = x NaN). colour may be empty (surfels get grey).
struct FusionInput {
  ImageView<const float> depth_m;
  ImageView<const Bgr8> colour;
  ImageView<const Vec3f> vertex_cam;
  ImageView<const Vec3f> normal_cam;
  CameraIntrinsics K;
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();  ///< optical frame
  double timestamp_s = 0.0;
  /// Propagated segment labels L^p (III), 0 = none; empty = segments are not updated.
  ImageView<const std::uint32_t> labels;
};

/// FusionInput over an RgbdFrame and its camera-frame vertex/normal maps (views, no copies).
FusionInput makeFusionInput(const RgbdFrame& frame, const Image<Vec3f>& vertex_cam,
                            const Image<Vec3f>& normal_cam, const Eigen::Isometry3d& T_world_cam,
                            const Image<std::uint32_t>* labels = nullptr);

struct FusionStats {
  int valid_pixels = 0;  ///< pixels with valid vertex + normal within the depth range
  int associated = 0;    ///< pixels matched to an existing surfel (confidence accumulated)
  int fused = 0;         ///< of those, geometry averaged (radius rule passed)
  int added = 0;         ///< new surfels (II-B)
  int covered = 0;       ///< no own candidate, a neighbour's surfel covers its ray: not added
  int became_stable = 0;
  int relabelled = 0;         ///< surfels whose segment changed from one label to another (III)
  int relabelled_stable = 0;  ///< of those, stable surfels (label stability of III)
  int removed_unstable = 0;   ///< old unstable surfels removed
  int removed_carved = 0;     ///< free-space violators removed
  int demoted_carved = 0;     ///< stable free-space violators that lost confidence
  int merged = 0;             ///< redundant surfels merged into another one (and removed)
  bool resorted = false;      ///< the store was re-sorted by block first (every index changed)
  int map_size = 0;           ///< after the frame
  maps::RenderStats render;   ///< of the 4x index map render
  // Wall-clock milliseconds of the stages (for report.json; tests never assert on them).
  double ms_resort = 0;     ///< SurfelStore::sortByBlock, when resorted
  double ms_index_map = 0;  ///< 4x point index map (II-D)
  double ms_update = 0;     ///< association + update
  double ms_add = 0;        ///< new surfels + spatial index upkeep
  double ms_cleanup = 0;    ///< carving + pruning + compaction
};

/// The 4x point index map of II-D at the frame's pose, as either backend keeps it (one view for
/// both): the candidates of frame pixel (x, y) are the surfels whose projection rounds to it (the
/// nearest of each of its 4x4 sub-pixels), with their depth along the camera's z axis. Valid from
/// SurfelFusion::renderIndexMap until that frame's cleanup (or any other change of the map).
struct IndexMapView {
  const maps::PointCandidates4x* lists = nullptr;  ///< CPU backend: compact per-pixel lists
  const maps::IndexMap4x* packed = nullptr;        ///< CUDA backend: the packed 4x map

  bool valid() const { return lists || packed; }
  int width() const { return lists ? lists->width : packed ? packed->width : 0; }
  int height() const { return lists ? lists->height : packed ? packed->height : 0; }
  /// Calls f(surfel index, depth z in m) for each candidate of frame pixel (x, y).
  template <typename F>
  void forEachCandidate(int x, int y, F&& f) const {
    if (lists) {
      const std::size_t p = std::size_t(y) * std::size_t(lists->width) + std::size_t(x);
      const maps::kernels::CameraPoint* e = lists->entries.data() + lists->first[p];
      for (int k = 0, n = lists->count[p]; k < n; ++k) f(int(e[k].index), e[k].pc.z());
    } else if (packed) {
      for (int sy = 4 * y; sy < 4 * y + 4; ++sy)
        for (int sx = 4 * x; sx < 4 * x + 4; ++sx) {
          const std::uint64_t v = packed->packed(sx, sy);
          const int i = maps::kernels::unpackIndex(v);
          if (i >= 0) f(i, maps::kernels::unpackDepth(v));
        }
    }
  }
};

class SurfelFusion {
 public:
  explicit SurfelFusion(const TFusionParams& params = {},
                        compute::Backend backend = compute::Backend::Cpu);

  const TFusionParams& params() const { return m_params; }
  void setParams(const TFusionParams& p) { m_params = p; }
  compute::Backend backend() const { return m_backend; }
  void setBackend(compute::Backend b);

  /// Integrate (steps 1-3) then cleanup (step 4). Throws InputError when image sizes do not
  /// match the intrinsics.
  FusionStats fuse(maps::SurfelStore& map, const FusionInput& in);

  /// Passes 1-3 only.
  FusionStats integrate(maps::SurfelStore& map, const FusionInput& in);

  /// Pass 1: validates `in` (InputError on sizes that do not match the intrinsics), re-sorts the
  /// store when due, renders the 4x point index map at in.T_world_cam and returns it.
  IndexMapView renderIndexMap(maps::SurfelStore& map, const FusionInput& in, FusionStats& stats);
  /// Pass 2: association and update of the matched surfels (confidence, geometry, segment weight
  /// with in.labels, view bins). Needs pass 1 of the same frame just before (std::logic_error
  /// otherwise); in may differ from pass 1's in its labels only.
  void updateSurfels(maps::SurfelStore& map, const FusionInput& in, FusionStats& stats);
  /// Pass 3: the unmatched pixels become new surfels; spatial index and pruning schedule upkeep.
  void addSurfels(maps::SurfelStore& map, const FusionInput& in, FusionStats& stats);
  /// The index map of the current frame (invalid view outside passes 1-3).
  IndexMapView indexMap() const;
  /// Pass 4, at the pose/time of `in` (carving uses its depth); adds to `stats`. Carving and
  /// merging need passes 1-3 of the same frame just before; without them only pruning runs.
  void cleanup(maps::SurfelStore& map, const FusionInput& in, FusionStats& stats);

  /// Surfel that pixel (x, y) of the last frame updated or created, -1 none. Kept valid across
  /// the cleanup's compaction (removed -> -1, moved -> new index); invalid after any later change
  /// of the map by someone else.
  const Image<std::int32_t>& pixelSurfels() const { return m_pixel_surfel; }
  /// The 4x point index map candidates of the last frame (before its updates and cleanup): CPU
  /// backend lastCandidates(), CUDA backend lastIndexMap() (the other one is empty).
  const maps::PointCandidates4x& lastCandidates() const { return m_candidates; }
  const maps::IndexMap4x& lastIndexMap() const { return m_index4x; }

 private:
  bool cpu() const { return m_backend == compute::Backend::Cpu; }
  /// What passes 2 and 3 derive from the params and the frame.
  struct FrameSetup {
    kernels::FusionKernelParams prm;
    kernels::FrameView fv;
    RigidF T_wc, T_cw;
    float now = 0.0f;  ///< map time of the frame
  };
  FrameSetup setUpFrame(const maps::SurfelStore& map, const FusionInput& in);
  enum class Pass { None, Rendered, Updated, Added };
  void requirePass(Pass expected, const char* pass) const;
  /// Whether m_schedule describes `map` (only fusion changed it since fusion last looked).
  bool scheduleValid(const maps::SurfelStore& map) const;
  void scheduleSeen(const maps::SurfelStore& map);
  /// Redundant-surfel merging over the per-pixel candidate lists of the last integrate(): the
  /// losers go to `removed`, (loser, kept) pairs to m_merged, re-binned survivors to the index.
  void mergeCpu(maps::SurfelStore& map, std::vector<int>& removed);
  /// Pass 2's counters of row y of m_flags (statistics, new surfels, re-binned and newly stable
  /// surfels), into this thread's slots.
  void tallyRow(const maps::SurfelArrays& arr, int y);
  /// Pass 2 on the CPU: association, update and neighbour coverage in row bands through the SSE
  /// launchers (FusionCpu.h), each row tallied once final.
  void associateUpdateCpu(const kernels::AssociateKernel<kernels::ListCandidates>& ak,
                          const kernels::UpdateKernel& uk,
                          const kernels::CoverageKernel<kernels::ListCandidates>& ck,
                          const maps::SurfelArrays& arr);
  /// Keeps pixelSurfels() valid after the cleanup removed `removed` and moved `moved` (from, to)
  /// of a map that had `old_size` surfels: removed -> -1, moved -> new index, merged -> the
  /// surfel it was merged into.
  void remapPixelSurfels(const std::vector<int>& removed,
                         const std::vector<std::pair<int, int>>& moved, int old_size);
  /// Free-space carving (CarveTest), the CPU path's traversal: the verdicts the update pass
  /// recorded for the surfels it updated, the candidate lists' centres for the others.
  void carveCpu(const maps::SurfelStore& map, const FusionInput& in, std::vector<int>& removed,
                std::vector<int>& demoted);
  /// The same carving as CarveKernel over every visible surfel on its current state: the CUDA
  /// path's, and the CPU's with its fusion kernels alone ([compute] simd_off = fusion), so that
  /// the two traversals can be compared (SurfelFusion.CarvingTraversalsAgree).
  void carveVisible(maps::SurfelStore& map, const FusionInput& in, std::vector<int>& removed,
                    std::vector<int>& demoted);

  TFusionParams m_params;
  compute::Backend m_backend;
  maps::SurfelRenderer m_renderer;
  maps::PointCandidates4x m_candidates;  ///< CPU backend
  maps::IndexMap4x m_index4x;            ///< CUDA backend
  maps::RenderOptions m_index_options;   ///< of the last index map render
  Image<std::int32_t> m_pixel_surfel;    ///< per pixel: matched surfel / -2 new / -1 none
  Image<std::uint16_t> m_flags;          ///< per pixel: kernels::PixelFlag bits
  Image<float> m_weight;  ///< II-B confidence weight per pixel for m_weight_K / m_weight_sigma
  CameraIntrinsics m_weight_K;
  float m_weight_sigma = -1.0f;
  ViewInfoThresholds m_ic;     ///< the CPU update's view-bin skip for the current IC parameters
  bool m_index_fresh = false;  ///< the last index map matches the map (integrate, no removal since)
  Pass m_pass = Pass::None;    ///< the last pass of the current frame
  std::vector<int> m_row_offset;
  std::vector<std::array<int, 7>> m_counts;  ///< per thread: pass 2's pixel counts for pass 3
  std::vector<std::vector<int>> m_thread_lists;
  std::vector<int> m_removed, m_demoted;
  std::vector<int> m_visible;  ///< carveVisible's list on the CPU (the candidate lists' surfels)
  std::vector<std::pair<int, int>> m_moved;
  std::vector<std::pair<int, int>> m_merged;  ///< (loser, kept) of the last mergeCpu
  std::uint64_t m_merge_round = 0;            ///< merging frames so far (row phase)
  std::vector<std::int32_t> m_remap_table;
  std::vector<std::uint64_t> m_remap_bits;       ///< per surfel index, all zero between frames
  std::vector<std::vector<int>> m_stable_lists;  ///< per thread: surfels that became stable
  std::vector<int> m_stable_changed;             ///< scratch: surfels whose stable flag changed
  // Pruning schedule and what it was built for.
  PruneSchedule m_schedule;
  const maps::SurfelStore* m_schedule_map = nullptr;
  std::uint64_t m_schedule_generation = 0;
  std::vector<int> m_due_now;  ///< surfels added by integrate() that are already due for pruning
};

}  // namespace rasm::fusion
