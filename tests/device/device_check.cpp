// The device check (scripts/device-check.sh, docs/device-check.md). On real inputs dumped by
// dump_inputs (DeviceData.h) it runs every CUDA launcher of the kernels (modules/*/cuda/*.cu)
// against the same RASM_HD kernel body run by compute/'s CPU loops (OpenMP), times the launchers,
// their kernels on device-resident data and one track + fuse frame, and prints one JSON summary.
//
// Two builds of this file:
//  - CUDA (RASM_DEVICE_CHECK_CUDA, nvcc links the modules' cuda/*.cu and device_kernels.cu):
//    backend B = the CUDA launchers, compared with tolerances (see Tolerances below);
//  - dry run (host compiler only): backend B = the same CPU loops on one thread, compared
//    exactly (the CPU launchers are deterministic for any thread count). A CUDA build that finds
//    no device falls back to the same and reports why.
// Either way the CPU kernels are also compared with what the product computed for the same frame
// (its SSE launchers, dumped with the inputs).
//
//   device_check <data folder> [--reps N] [--json out.json] [--build-info TEXT]
//
// Exit status: 0 all checks passed; 1 a check failed; 2 bad input or an error (the JSON then
// has "error"); 3 a CUDA build found no device (the CPU checks ran and passed).

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "DeviceData.h"
#include "DeviceKernels.h"
#include "Json.h"
#include "rasm/compute/Parallel.h"
#include "rasm/core/CameraIntrinsics.h"
#include "rasm/core/FrameProcessing.h"
#include "rasm/core/Image.h"
#include "rasm/core/SurfelMath.h"
#include "rasm/core/kernels/FrameKernels.h"
#include "rasm/fusion/kernels/FusionKernels.h"
#include "rasm/surfel_map/SurfelRenderer.h"
#include "rasm/surfel_map/kernels/RenderKernels.h"
#include "rasm/tracking/IcpCuda.h"
#include "rasm/tracking/kernels/IcpKernels.h"

namespace rasm::device {
namespace {

namespace fk = fusion::kernels;
namespace mk = maps::kernels;
namespace tk = tracking::kernels;
using Clock = std::chrono::steady_clock;
using Vec6 = Eigen::Matrix<double, 6, 1>;
constexpr double kPi = 3.14159265358979323846;

// ---- inputs --------------------------------------------------------------------------------

template <typename T>
Image<T> loadImage(const std::string& path, ElemType type) {
  const Blob b = readBlob(path);
  const T* p = b.as<T>(type);
  Image<T> im(b.width, b.height);
  for (int y = 0; y < b.height; ++y)
    std::memcpy(static_cast<void*>(im.row(y)), p + std::size_t(y) * b.width, sizeof(T) * b.width);
  return im;
}

template <typename T>
std::vector<T> loadArray(const std::string& path, ElemType type) {
  const Blob b = readBlob(path);
  const T* p = b.as<T>(type);
  return std::vector<T>(p, p + b.count);
}

/// The surfel arrays the launchers read and write (SurfelArrays.h), owned.
struct HostMap {
  std::vector<Vec4f> pos, nrm;
  std::vector<std::uint32_t> cf, seg;
  std::vector<float> tl, segw;
  std::vector<Vec3f> basis;
  std::vector<std::uint8_t> view;
  int n_view_bins = 0;

  int size() const { return int(pos.size()); }
  maps::SurfelArrays arrays() {
    maps::SurfelArrays a;  // fields not listed stay null: the launchers do not read them
    a.pos_conf = pos.data();
    a.normal_radius = nrm.data();
    a.colour_flags = cf.data();
    a.t_last = tl.data();
    a.basis = basis.data();
    a.segment = seg.data();
    a.segment_w = segw.data();
    a.view_ic = view.data();
    a.size = size();
    a.n_view_bins = n_view_bins;
    return a;
  }
};

Eigen::Isometry3d pose(const Meta& m, const std::string& key) {
  const std::vector<double> v = m.values(key, 16);
  Eigen::Isometry3d T;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) T.matrix()(r, c) = v[r * 4 + c];
  return T;
}

CameraIntrinsics intrinsics(const Meta& m, const std::string& key) {
  const std::vector<double> v = m.values(key, 6);
  return CameraIntrinsics(v[0], v[1], v[2], v[3], int(v[4]), int(v[5]));
}

RigidF rigid(const Eigen::Isometry3d& T) {
  return RigidF::fromMatrix(T.matrix().cast<float>());
}

struct Inputs {
  Meta meta;
  std::vector<Image<float>> depth;  ///< level-0 depth of each frame (frame 0 first)
  Image<float> depth_raw;
  Image<Bgr8> colour;
  Image<Vec3f> vertex0, normal0;  ///< the product's level-0 maps of frame 0
  Image<std::int32_t> model_index;
  Image<Vec3f> model_vertex, model_normal;
  std::vector<int> model_visible, fuse_visible;
  HostMap map;
  CameraIntrinsics K[3];
  Eigen::Isometry3d T_world_model, T_guess, T_world_cam;
  std::size_t bytes = 0;

  static Inputs load(const std::string& dir) {
    Inputs in;
    const std::string d = dir + "/";
    in.meta = Meta::read(d + "meta.txt");
    const Meta& m = in.meta;
    const int frames = 1 + int(m.num("extra_frames"));
    for (int k = 0; k < frames; ++k)
      in.depth.push_back(
          loadImage<float>(d + "frame" + std::to_string(k) + "_depth.bin", ElemType::F32));
    in.depth_raw = loadImage<float>(d + "frame0_depth_raw.bin", ElemType::F32);
    in.colour = loadImage<Bgr8>(d + "frame0_colour.bin", ElemType::Bgr8);
    in.vertex0 = loadImage<Vec3f>(d + "frame0_vertex.bin", ElemType::Vec3f);
    in.normal0 = loadImage<Vec3f>(d + "frame0_normal.bin", ElemType::Vec3f);
    in.model_index = loadImage<std::int32_t>(d + "model_index.bin", ElemType::I32);
    in.model_vertex = loadImage<Vec3f>(d + "model_vertex.bin", ElemType::Vec3f);
    in.model_normal = loadImage<Vec3f>(d + "model_normal.bin", ElemType::Vec3f);
    in.model_visible = loadArray<int>(d + "model_visible.bin", ElemType::I32);
    in.fuse_visible = loadArray<int>(d + "fuse_visible.bin", ElemType::I32);
    HostMap& h = in.map;
    h.pos = loadArray<Vec4f>(d + "map_pos_conf.bin", ElemType::Vec4f);
    h.nrm = loadArray<Vec4f>(d + "map_normal_radius.bin", ElemType::Vec4f);
    h.cf = loadArray<std::uint32_t>(d + "map_colour_flags.bin", ElemType::U32);
    h.tl = loadArray<float>(d + "map_t_last.bin", ElemType::F32);
    h.basis = loadArray<Vec3f>(d + "map_basis.bin", ElemType::Vec3f);
    h.seg = loadArray<std::uint32_t>(d + "map_segment.bin", ElemType::U32);
    h.segw = loadArray<float>(d + "map_segment_w.bin", ElemType::F32);
    h.view = loadArray<std::uint8_t>(d + "map_view_ic.bin", ElemType::U8);
    h.n_view_bins = int(m.num("map.n_view_bins"));
    const std::size_t n = h.pos.size();
    if (h.nrm.size() != n || h.cf.size() != n || h.tl.size() != n || h.basis.size() != n ||
        h.seg.size() != n || h.segw.size() != n || h.view.size() != n * std::size_t(h.n_view_bins))
      throw std::runtime_error("map arrays of different lengths in " + dir);
    for (int l = 0; l < 3; ++l) in.K[l] = intrinsics(m, "K_level" + std::to_string(l));
    in.T_world_model = pose(m, "T_world_model");
    in.T_guess = pose(m, "T_world_cam_guess");
    in.T_world_cam = pose(m, "T_world_cam");
    in.bytes = n * (2 * sizeof(Vec4f) + 4 * 4 + sizeof(Vec3f) + std::size_t(h.n_view_bins));
    return in;
  }
};

// ---- backend B and timing -------------------------------------------------------------------

/// Runs the CPU loops on one thread while alive (dry run's backend B).
struct OneThread {
#ifdef _OPENMP
  int saved = omp_get_max_threads();
  OneThread() {
    omp_set_num_threads(1);
  }
  ~OneThread() {
    omp_set_num_threads(saved);
  }
#endif
};

bool g_cuda = false;  ///< backend B is the CUDA launchers (a CUDA build with a device)
int g_reps = 10;

template <typename F>
double medianWallMs(int reps, F f) {
  std::vector<double> ms;
  for (int r = 0; r < std::max(1, reps); ++r) {
    const auto t0 = Clock::now();
    f();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  std::nth_element(ms.begin(), ms.begin() + ms.size() / 2, ms.end());
  return ms[ms.size() / 2];
}

// ---- checks ----------------------------------------------------------------------------------

/// GPU-vs-CPU limits. The CUDA build compiles the kernels with nvcc's defaults, which contract
/// a * b + c into one fused multiply-add (--fmad=true); the CPU build (x86-64-v2) has no FMA. So
/// single float results differ in the last bits (projections, cross products, averages), a
/// decision taken on such a value (a pixel a surfel projects to, a gate met within rounding)
/// can flip for a few pixels in a million, and sums (ICP) are added in another order (per thread
/// in float, then in double per block on the GPU; in float over 64-pixel segments on the CPU).
/// Divisions and square roots are IEEE-rounded on both (nvcc's -prec-div/-prec-sqrt defaults).
/// The dry run compares the CPU with itself: every limit is 0.
struct Tolerances {
  bool exact = true;
  double operator()(double gpu_limit) const { return exact ? 0.0 : gpu_limit; }
};
Tolerances g_tol;

struct Check {
  std::string name, launcher, compared, tolerance;
  bool pass = true;
  JsonObject metrics, ms;
  std::vector<std::string> failed;

  Check(std::string name_, std::string launcher_, std::string compared_, std::string tolerance_)
      : name(std::move(name_)),
        launcher(std::move(launcher_)),
        compared(std::move(compared_)),
        tolerance(std::move(tolerance_)) {}

  /// Records value and fails the check when value > limit (or NaN).
  void limit(const std::string& what, double value, double max) {
    metrics.num(what, value);
    if (!(value <= max)) {
      pass = false;
      failed.push_back(what + " = " + jsonNumber(value) + " > " + jsonNumber(max));
    }
  }
  JsonObject json() const {
    JsonObject o;
    o.str("name", name).str("launcher", launcher).str("compared", compared);
    o.boolean("pass", pass).str("tolerance", tolerance).obj("metrics", metrics);
    if (!ms.empty()) o.obj("ms", ms);
    if (!failed.empty()) o.strs("failed", failed);
    return o;
  }
};

bool validV(const Vec3f& v) {
  return v.x() == v.x();
}

/// Differences of two maps with NaN-x invalid pixels: validity, the largest difference and the
/// pixels whose difference exceeds `off` (+ rel * |a|).
struct Vec3Diff {
  double off = 0, rel = 0;
  long long valid = 0, validity_mismatch = 0, off_count = 0;
  double max_abs = 0;
  Vec3Diff(double off_, double rel_) : off(off_), rel(rel_) {}
  void add(const Image<Vec3f>& a, const Image<Vec3f>& b) {
    for (int y = 0; y < a.height(); ++y)
      for (int x = 0; x < a.width(); ++x) {
        const bool va = validV(a(x, y)), vb = validV(b(x, y));
        valid += va;
        if (va != vb) {
          ++validity_mismatch;
        } else if (va) {
          const double d = (a(x, y) - b(x, y)).cwiseAbs().maxCoeff();
          max_abs = std::max(max_abs, d);
          off_count += d > off + rel * a(x, y).cwiseAbs().maxCoeff();
        }
      }
  }
  double frac(long long n) const { return double(n) / double(std::max(1LL, valid)); }
};

/// Differences of two packed depth/index buffers (RenderKernels.h).
struct PackedDiff {
  long long drawn_a = 0, drawn_b = 0, index_mismatch = 0, far_depth = 0, same_index = 0,
            depth_off = 0;
  double max_rel_depth_same_index = 0;
  void add(const Image<std::uint64_t>& a, const Image<std::uint64_t>& b) {
    for (int y = 0; y < a.height(); ++y)
      for (int x = 0; x < a.width(); ++x) {
        const std::uint64_t pa = a(x, y), pb = b(x, y);
        drawn_a += pa != mk::kEmptyPacked;
        drawn_b += pb != mk::kEmptyPacked;
        if (pa == mk::kEmptyPacked && pb == mk::kEmptyPacked) continue;
        const float da = mk::unpackDepth(pa), db = mk::unpackDepth(pb);
        if (mk::unpackIndex(pa) != mk::unpackIndex(pb)) {
          ++index_mismatch;
          if (!(std::fabs(da - db) <= 0.01f)) ++far_depth;  // (a pixel empty on one side counts)
        } else {
          ++same_index;
          const double r = std::fabs(da - db) / std::max(1e-3f, da);
          max_rel_depth_same_index = std::max(max_rel_depth_same_index, r);
          depth_off += r > 1e-5;
        }
      }
  }
  void report(Check& c) const {
    const double n = double(std::max<long long>(1, drawn_a));
    c.metrics.integer("pixels_drawn_cpu", drawn_a).integer("pixels_drawn_b", drawn_b);
    c.metrics.num("max_rel_depth_diff_same_index", max_rel_depth_same_index);
    c.limit("drawn_rel_diff", std::fabs(double(drawn_a - drawn_b)) / n, g_tol(1e-3));
    c.limit("index_mismatch_frac", double(index_mismatch) / n, g_tol(1e-3));
    c.limit("depth_gt_1cm_frac", double(far_depth) / n, g_tol(1e-3));
    c.limit("same_index_depth_off_frac", double(depth_off) / double(std::max(1LL, same_index)),
            g_tol(1e-3));
  }
};

Image<std::uint64_t> emptyPacked(int w, int h) {
  return Image<std::uint64_t>(w, h, mk::kEmptyPacked);
}

// ---- the kernels on the CPU (backend A), and backend B ---------------------------------------

struct FrameOpts {
  VertexMapOptions vo;
  float jump = 0.05f;
};

void vertexCpu(const Image<float>& d, const CameraIntrinsics& K, const FrameOpts& o,
               Image<Vec3f>& v) {
  v.resize(d.width(), d.height());
  compute::forEach2D(
      d.width(), d.height(),
      kernels::VertexMapKernel{d.cview(), v.view(), K.plain(), o.vo.min_depth_m, o.vo.max_depth_m});
}
void normalCpu(const Image<Vec3f>& v, float jump, Image<Vec3f>& n) {
  n.resize(v.width(), v.height());
  compute::forEach2D(v.width(), v.height(), kernels::NormalMapKernel{v.cview(), n.view(), jump});
}
void vertexB(const Image<float>& d, const CameraIntrinsics& K, const FrameOpts& o,
             Image<Vec3f>& v) {
  if (g_cuda) return cuda::computeVertexMap(d, K, v, o.vo);
  OneThread one;
  vertexCpu(d, K, o, v);
}
void normalB(const Image<Vec3f>& v, float jump, Image<Vec3f>& n) {
  if (g_cuda) return cuda::computeNormalMap(v, n, jump);
  OneThread one;
  normalCpu(v, jump, n);
}
void downsample(const Image<float>& in, Image<float>& out) {
  out.resize((in.width() + 1) / 2, (in.height() + 1) / 2);
  compute::forEach2D(out.width(), out.height(),
                     kernels::DepthDownsampleKernel{in.cview(), out.view(), 0.03f});
}

struct RenderSetup {
  maps::RenderOptions opt;
  RigidF T_cw;
  PinholeF K;
};

void splatCpu(const maps::SurfelArrays& a, const std::vector<int>& vis, const RenderSetup& r,
              Image<std::uint64_t>& packed) {
  packed = emptyPacked(r.K.width, r.K.height);
  if (r.opt.splat) {
    mk::SplatKernel k{a,
                      vis.data(),
                      r.T_cw,
                      r.K,
                      r.opt.min_depth_m,
                      r.opt.max_depth_m,
                      r.opt.max_splat_radius_px,
                      packed.view()};
    compute::forEach1D(int(vis.size()), k);
  } else {
    mk::PointKernel k{a, vis.data(),    r.T_cw, r.K, r.opt.min_depth_m, r.opt.max_depth_m,
                      1, packed.view(), nullptr};
    compute::forEach1D(int(vis.size()), k);
  }
}
void splatB(const maps::SurfelArrays& a, const std::vector<int>& vis, const RenderSetup& r,
            Image<std::uint64_t>& packed) {
  if (g_cuda) {
    packed.resize(r.K.width, r.K.height);
    return maps::cuda::splatPacked(a, vis, r.T_cw, r.K, r.opt, packed);
  }
  OneThread one;
  splatCpu(a, vis, r, packed);
}
void points4xCpu(const maps::SurfelArrays& a, const std::vector<int>& vis, const RenderSetup& r,
                 Image<std::uint64_t>& packed, std::vector<std::int64_t>& touched) {
  packed = emptyPacked(4 * r.K.width, 4 * r.K.height);
  touched.assign(vis.size(), -1);
  mk::PointKernel k{a, vis.data(),    r.T_cw,        r.K, r.opt.min_depth_m, r.opt.max_depth_m,
                    4, packed.view(), touched.data()};
  compute::forEach1D(int(vis.size()), k);
}
void points4xB(const maps::SurfelArrays& a, const std::vector<int>& vis, const RenderSetup& r,
               Image<std::uint64_t>& packed, std::vector<std::int64_t>& touched) {
  if (g_cuda) {
    packed.resize(4 * r.K.width, 4 * r.K.height);
    return maps::cuda::pointsPacked4x(a, vis, r.T_cw, r.K, r.opt, packed, touched);
  }
  OneThread one;
  points4xCpu(a, vis, r, packed, touched);
}

/// World-frame model maps of a splat render (ResolveKernel, on the CPU for both backends: the
/// CUDA path of SurfelRenderer::render resolves on the host too).
void resolve(const maps::SurfelArrays& a, const Image<std::uint64_t>& packed,
             const Eigen::Isometry3d& T_world_cam, const PinholeF& K, Image<std::int32_t>& index,
             Image<Vec3f>& vertex, Image<Vec3f>& normal) {
  const int w = packed.width(), h = packed.height();
  index.resize(w, h);
  vertex.resize(w, h);
  normal.resize(w, h);
  mk::ResolveKernel k;
  k.s = a;
  k.packed = packed.cview();
  k.T_world_cam = rigid(T_world_cam);
  k.K = K;
  k.splat = true;
  k.index = index.view();
  k.vertex_world = vertex.view();
  k.normal_world = normal.view();
  compute::forEach2D(w, h, k);
}

/// Model pyramid of the tracker (IcpTracker::buildModelPyramid): levels 1.. from level 0.
void modelPyramid(const Image<Vec3f>& v0, const Image<Vec3f>& n0,
                  const Eigen::Isometry3d& T_world_model, int levels, std::vector<Image<Vec3f>>& mv,
                  std::vector<Image<Vec3f>>& mn) {
  mv.resize(levels);
  mn.resize(levels);
  mv[0] = v0;
  mn[0] = n0;
  for (int l = 1; l < levels; ++l) {
    mv[l].resize((mv[l - 1].width() + 1) / 2, (mv[l - 1].height() + 1) / 2);
    mn[l].resize(mv[l].width(), mv[l].height());
    tk::ModelDownsampleKernel k;
    k.in_vertex = mv[l - 1].cview();
    k.in_normal = mn[l - 1].cview();
    k.out_vertex = mv[l].view();
    k.out_normal = mn[l].view();
    k.T_model_world = rigid(T_world_model.inverse());
    k.max_diff_m = 0.03f;
    compute::forEach2D(mv[l].width(), mv[l].height(), k);
  }
}

// ---- ICP (II-C) -------------------------------------------------------------------------------

struct IcpParams {
  int levels = 3, stride0 = 2, model_level = 0;
  int iterations[3] = {10, 5, 4};
  double max_dist[3] = {0.05, 0.15, 0.3}, normal_deg[3] = {45, 30, 30};
  double huber = 0, conv_t = 1e-4, conv_rot_deg = 0.01;
  bool noise_weighting = true;
};

struct Pyramids {
  std::vector<Image<Vec3f>> fv, fn;  ///< frame, camera frame
  std::vector<Image<Vec3f>> mv, mn;  ///< model, world frame
};

/// The kernel of frame level l at pose T, as IcpTracker::align sets it up.
tk::IcpReduceKernel icpKernel(const Pyramids& p, const IcpParams& P, const CameraIntrinsics* K,
                              int l, const Eigen::Isometry3d& T,
                              const Eigen::Isometry3d& T_world_model) {
  tk::IcpReduceKernel k;
  const int ml = std::max(0, l - P.model_level);
  k.frame_vertex = p.fv[l].cview();
  k.frame_normal = p.fn[l].cview();
  k.model_vertex = p.mv[ml].cview();
  k.model_normal = p.mn[ml].cview();
  k.K_model = K[ml].plain();
  k.max_dist_m = float(P.max_dist[l]);
  k.min_normal_cos = float(std::cos(P.normal_deg[l] * kPi / 180.0));
  k.huber_delta_m = float(P.huber);
  k.depth_noise_weighting = P.noise_weighting;
  k.stride = l == 0 ? P.stride0 : 1;
  k.T_world_cam = rigid(T);
  k.T_model_cam = rigid(T_world_model.inverse() * T);
  k.pivot_world = T.translation().cast<float>();
  return k;
}

/// One reduction backend: upload(level, k) once per level, reduce(level, k) per iteration.
struct IcpBackend {
  std::function<void(int, const tk::IcpReduceKernel&)> upload;
  std::function<tk::IcpAccumulator(int, const tk::IcpReduceKernel&)> reduce;
};

IcpBackend icpCpu() {
  return {[](int, const tk::IcpReduceKernel&) {},
          [](int, const tk::IcpReduceKernel& k) {
            return compute::reduce1D<tk::IcpAccumulator>(k.items(), k);
          }};
}
IcpBackend icpB(std::shared_ptr<tracking::cuda::IcpCudaReducer> r) {
  if (g_cuda)
    return {[r](int l, const tk::IcpReduceKernel& k) { r->upload(l, k); },
            [r](int l, const tk::IcpReduceKernel& k) { return r->reduce(l, k); }};
  return {[](int, const tk::IcpReduceKernel&) {},
          [](int, const tk::IcpReduceKernel& k) {
            OneThread one;
            return compute::reduce1D<tk::IcpAccumulator>(k.items(), k);
          }};
}

struct TrackResult {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  int iterations = 0;
  double inliers = 0;
};

/// Coarse-to-fine Gauss-Newton on the point-to-plane sums (IcpKernels.h): (J^T J) xi = -J^T r
/// by LDLT, T <- P exp(xi) P^-1 T about the pivot, a level stops once the step is below the
/// convergence limits. The product's IcpTracker adds scale balancing, degeneracy handling and
/// quality rules around the same sums; both backends here run this same solver.
TrackResult track(const Pyramids& p, const IcpParams& P, const CameraIntrinsics* K,
                  const Eigen::Isometry3d& guess, const Eigen::Isometry3d& T_world_model,
                  const IcpBackend& be) {
  TrackResult res;
  Eigen::Isometry3d T = guess;
  for (int l = P.levels - 1; l >= 0; --l) {
    be.upload(l, icpKernel(p, P, K, l, T, T_world_model));
    for (int it = 0; it < P.iterations[l]; ++it) {
      const tk::IcpAccumulator acc = be.reduce(l, icpKernel(p, P, K, l, T, T_world_model));
      ++res.iterations;
      if (l == 0) res.inliers = acc.inliers();
      if (acc.inliers() < 6) break;
      Eigen::Matrix<double, 6, 6> A;
      Vec6 b;
      int kk = tk::IcpAccumulator::kJtJ;
      for (int i = 0; i < 6; ++i)
        for (int j = i; j < 6; ++j) A(i, j) = A(j, i) = acc.s[kk++];
      for (int i = 0; i < 6; ++i) b(i) = acc.s[tk::IcpAccumulator::kJtr + i];
      const Vec6 xi = -A.ldlt().solve(b);
      if (!xi.allFinite()) break;
      Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
      const Eigen::Vector3d w = xi.tail<3>();
      if (w.norm() > 0)
        step.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
      step.translation() = xi.head<3>();
      Eigen::Isometry3d Pc = Eigen::Isometry3d::Identity();
      Pc.translation() = T.translation();
      T = Pc * step * Pc.inverse() * T;
      if (xi.head<3>().norm() < P.conv_t && w.norm() < P.conv_rot_deg * kPi / 180.0) break;
    }
  }
  res.T = T;
  return res;
}

double translationDiff(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.translation() - b.translation()).norm();
}
double rotationDiffDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / kPi;
}

// ---- fusion (II-B, II-D) ----------------------------------------------------------------------

struct FusionSetup {
  fk::FusionKernelParams prm;
  fk::FrameView frame;
  Image<float> weight;
  float now = 0;
};

FusionSetup fusionSetup(const Inputs& in) {
  const Meta& m = in.meta;
  FusionSetup f;
  fk::FusionKernelParams& p = f.prm;
  p.sigma = float(m.num("fusion.sigma"));
  p.min_depth_m = float(m.num("fusion.min_depth_m"));
  p.max_depth_m = float(m.num("fusion.max_depth_m"));
  p.min_cos_incidence = float(m.num("fusion.min_cos_incidence"));
  p.assoc_dz_abs_m = float(m.num("fusion.assoc_dz_abs_m"));
  p.assoc_dz_rel = float(m.num("fusion.assoc_dz_rel"));
  p.min_cos_normal = float(m.num("fusion.min_cos_normal"));
  p.radius_update_ratio = float(m.num("fusion.radius_update_ratio"));
  p.neighbour_coverage_check = m.num("fusion.neighbour_coverage_check") != 0;
  p.stable_confidence = float(m.num("fusion.stable_confidence"));
  p.max_confidence = float(m.num("fusion.max_confidence"));
  p.update_segments = m.num("fusion.update_segments") != 0;
  p.update_view_bins = m.num("fusion.update_view_bins") != 0;
  p.ic_lambda1 = float(m.num("fusion.ic_lambda1"));
  p.ic_d_min_m = float(m.num("fusion.ic_d_min_m"));
  p.n_azimuth = int(m.num("map.view_bins_azimuth"));
  p.n_elevation = int(m.num("map.view_bins_elevation"));
  p.inv_block_size = 1.0f / float(m.num("map.block_size_m"));
  f.now = float(m.num("fusion.now_map_s"));
  const CameraIntrinsics& K = in.K[0];
  const PinholeF Kp = K.plain();
  // w per pixel, tabulated as SurfelFusion::integrate does.
  f.weight.resize(K.width, K.height);
  compute::forEach2D(K.width, K.height, [&](int x, int y) {
    f.weight(x, y) = confidenceWeight(normalizedRadialDistance(float(x), float(y), Kp), p.sigma);
  });
  f.frame.colour = in.colour.cview();
  f.frame.vertex_cam = in.vertex0.cview();
  f.frame.normal_cam = in.normal0.cview();
  f.frame.weight = f.weight.cview();
  f.frame.K = Kp;
  f.frame.focal_px = float(0.5 * (std::fabs(K.fx) + std::fabs(K.fy)));
  return f;
}

struct FusionOut {
  Image<std::int32_t> pixel_surfel;
  Image<std::uint16_t> flags;
};

/// The kernels of the CUDA path of SurfelFusion::integrate on map `a` with the 4x index map.
struct FusionKernels {
  fk::AssociateKernel<fk::Map4xCandidates> a;
  fk::UpdateKernel u;
  fk::CoverageKernel<fk::Map4xCandidates> c;
};
FusionKernels fusionKernels(const FusionSetup& f, const Inputs& in, const maps::SurfelArrays& s,
                            const Image<std::uint64_t>& index4x,
                            const Eigen::Isometry3d& T_world_cam, FusionOut& out) {
  const int w = in.K[0].width, h = in.K[0].height;
  out.pixel_surfel.resize(w, h);
  out.flags.resize(w, h);
  const RigidF T_wc = rigid(T_world_cam), T_cw = rigid(T_world_cam.inverse());
  fk::Map4xCandidates cand;
  cand.index4x = index4x.cview();
  cand.s = s;
  cand.T_cam_world = T_cw;
  cand.width = w;
  cand.height = h;
  FusionKernels k;
  k.a.frame = f.frame;
  k.a.prm = f.prm;
  k.a.candidates = cand;
  k.a.s = s;
  k.a.T_world_cam = T_wc;
  k.a.pixel_surfel = out.pixel_surfel.view();
  k.a.flags = out.flags.view();
  k.u.frame = f.frame;
  k.u.prm = f.prm;
  k.u.s = s;
  k.u.T_world_cam = T_wc;
  k.u.T_cam_world = T_cw;
  k.u.now = f.now;
  k.u.pixel_surfel = out.pixel_surfel.cview();
  k.u.flags = out.flags.view();
  k.u.carve = false;  // as SurfelFusion on CUDA: carving is judged by the cleanup
  k.u.carve_test.depth_m = in.depth_raw.cview();
  k.u.carve_test.K = f.frame.K;
  k.c.frame = f.frame;
  k.c.prm = f.prm;
  k.c.candidates = cand;
  k.c.s = s;
  k.c.T_world_cam = T_wc;
  k.c.T_cam_world = T_cw;
  k.c.pixel_surfel = out.pixel_surfel.view();
  k.c.flags = out.flags.view();
  return k;
}

void fuseCpu(const FusionKernels& k) {
  const int w = k.a.pixel_surfel.width, h = k.a.pixel_surfel.height;
  compute::forEach2D(w, h, k.a);
  compute::forEach2D(w, h, k.u);
  if (k.c.prm.neighbour_coverage_check) compute::forEach2D(w, h, k.c);
}
void fuseB(const FusionKernels& k) {
  if (g_cuda) return fusion::cuda::associateUpdate(k.a, k.u, k.c);
  OneThread one;
  fuseCpu(k);
}

struct FusionCounts {
  long long valid = 0, associated = 0, fused = 0, covered = 0, became_stable = 0, added = 0;
  explicit FusionCounts(const Image<std::uint16_t>& f) {
    for (int y = 0; y < f.height(); ++y)
      for (int x = 0; x < f.width(); ++x) {
        const std::uint16_t b = f(x, y);
        valid += b != 0;
        associated += (b & fk::kPixAssociated) != 0;
        fused += (b & fk::kPixFused) != 0;
        covered += (b & fk::kPixCovered) != 0;
        became_stable += (b & fk::kPixBecameStable) != 0;
        added += (b & fk::kPixNew) != 0;
      }
  }
};

// ---- the checks ------------------------------------------------------------------------------

struct Context {
  Inputs in;
  FrameOpts fo;
  IcpParams icp;
  RenderSetup model, model_points, index4x;
  FusionSetup fusion;
  Pyramids pyr;  ///< the CPU kernels' frame pyramid (level 0: the product's) and model pyramid
  Image<std::uint64_t> packed4x_cpu;
  std::vector<Check> checks;
};

RenderSetup renderSetup(const Meta& m, const CameraIntrinsics& K,
                        const Eigen::Isometry3d& T_world_cam, bool model) {
  RenderSetup r;
  r.T_cw = rigid(T_world_cam.inverse());
  r.K = K.plain();
  if (model) {
    r.opt.min_depth_m = float(m.num("model.min_depth_m"));
    r.opt.max_depth_m = float(m.num("model.max_depth_m"));
    r.opt.max_splat_radius_px = float(m.num("model.max_splat_radius_px"));
  } else {
    r.opt.min_depth_m = float(m.num("fusion.index4x_min_depth_m"));
    r.opt.max_depth_m = float(m.num("fusion.index4x_max_depth_m"));
    r.opt.splat = false;
  }
  return r;
}

void checkFrameMaps(Context& ctx) {
  Check c{
      "frame_maps", "rasm::cuda::computeVertexMap, computeNormalMap (core/cuda/FrameKernels.cu)",
      "VertexMapKernel, NormalMapKernel: backend B vs compute::forEach2D, every frame, levels 0-2",
      ""};
  c.tolerance =
      g_tol.exact
          ? "exact"
          : "vertex: identical (IEEE division, no FMA in back-projection); normal: validity "
            "differs <= 1e-5 of pixels, > 1e-5 apart <= 1e-4 (cross products under FMA)";
  Vec3Diff dv(0, 0), dn(1e-5, 0);
  for (std::size_t f = 0; f < ctx.in.depth.size(); ++f) {
    Image<float> d = ctx.in.depth[f];
    for (int l = 0; l < 3; ++l) {
      if (l > 0) {
        Image<float> half;
        downsample(d, half);
        d = half;
      }
      Image<Vec3f> va, vb, na, nb;
      vertexCpu(d, ctx.in.K[l], ctx.fo, va);
      vertexB(d, ctx.in.K[l], ctx.fo, vb);
      normalCpu(va, ctx.fo.jump, na);
      normalB(va, ctx.fo.jump, nb);
      dv.add(va, vb);
      dn.add(na, nb);
    }
  }
  c.metrics.integer("vertex_valid", dv.valid).integer("normal_valid", dn.valid);
  c.metrics.num("normal_max_abs_diff", dn.max_abs);
  c.limit("vertex_validity_mismatch", double(dv.validity_mismatch), 0);
  c.limit("vertex_max_abs_diff_m", dv.max_abs, g_tol(2e-6));
  c.limit("normal_validity_mismatch_frac", dn.frac(dn.validity_mismatch), g_tol(1e-5));
  c.limit("normal_off_frac", dn.frac(dn.off_count), g_tol(1e-4));
  // Times at level 0 of frame 0.
  const Image<float>& d0 = ctx.in.depth[0];
  const CameraIntrinsics& K = ctx.in.K[0];
  Image<Vec3f> v, n;
  c.ms.num("vertex_cpu", medianWallMs(g_reps, [&] { vertexCpu(d0, K, ctx.fo, v); }));
  c.ms.num("vertex_b", medianWallMs(g_reps, [&] { vertexB(d0, K, ctx.fo, v); }));
  c.ms.num("normal_cpu", medianWallMs(g_reps, [&] { normalCpu(v, ctx.fo.jump, n); }));
  c.ms.num("normal_b", medianWallMs(g_reps, [&] { normalB(v, ctx.fo.jump, n); }));
#ifdef RASM_DEVICE_CHECK_CUDA
  if (g_cuda) {
    c.ms.num(
        "vertex_kernel",
        gpu::vertexMapMs(kernels::VertexMapKernel{d0.cview(), v.view(), K.plain(),
                                                  ctx.fo.vo.min_depth_m, ctx.fo.vo.max_depth_m},
                         g_reps));
    c.ms.num("normal_kernel",
             gpu::normalMapMs(kernels::NormalMapKernel{v.cview(), n.view(), ctx.fo.jump}, g_reps));
  }
#endif
  ctx.checks.push_back(c);

  // The CPU kernels against the product's SSE launchers (same frame, level 0).
  Check p{"frame_maps_vs_product", "(CPU only)",
          "VertexMapKernel, NormalMapKernel vs the product's level-0 maps (dumped)",
          "exact (the SSE launchers are bit-identical to the kernels)"};
  Vec3Diff pv(0, 0), pn(0, 0);
  Image<Vec3f> va, na;
  vertexCpu(ctx.in.depth[0], K, ctx.fo, va);
  normalCpu(va, ctx.fo.jump, na);
  pv.add(va, ctx.in.vertex0);
  pn.add(na, ctx.in.normal0);
  p.limit("vertex_validity_mismatch", double(pv.validity_mismatch), 0);
  p.limit("vertex_max_abs_diff_m", pv.max_abs, 0);
  p.limit("normal_validity_mismatch", double(pn.validity_mismatch), 0);
  p.limit("normal_max_abs_diff", pn.max_abs, 0);
  ctx.checks.push_back(p);
}

void checkRender(Context& ctx) {
  HostMap& map = ctx.in.map;
  const maps::SurfelArrays a = map.arrays();
  const std::vector<int>& vis = ctx.in.model_visible;
  for (const bool splat : {true, false}) {
    const RenderSetup& r = splat ? ctx.model : ctx.model_points;
    Check c{splat ? "render_splat" : "render_points",
            std::string("rasm::maps::cuda::splatPacked, ") + (splat ? "splat" : "points") +
                " (surfel_map/cuda/SurfelRender.cu)",
            std::string(splat ? "SplatKernel" : "PointKernel (1x)") + " over the model's " +
                std::to_string(vis.size()) +
                " visible surfels at T_world_model: packed depth/index, backend B vs "
                "compute::forEach1D",
            g_tol.exact ? "exact"
                        : "drawn pixels and winning surfel differ <= 1e-3; where the surfel "
                          "agrees, depth off by "
                          "> 1e-5 relative <= 1e-3 (projections and ray/disc depths under FMA)"};
    Image<std::uint64_t> pa, pb;
    splatCpu(a, vis, r, pa);
    splatB(a, vis, r, pb);
    PackedDiff d;
    d.add(pa, pb);
    d.report(c);
    c.ms.num("cpu", medianWallMs(g_reps, [&] { splatCpu(a, vis, r, pa); }));
    c.ms.num("b", medianWallMs(g_reps, [&] { splatB(a, vis, r, pb); }));
#ifdef RASM_DEVICE_CHECK_CUDA
    if (g_cuda) {
      if (splat)
        c.ms.num("kernel", gpu::splatMs(mk::SplatKernel{a, vis.data(), r.T_cw, r.K,
                                                        r.opt.min_depth_m, r.opt.max_depth_m,
                                                        r.opt.max_splat_radius_px, pa.view()},
                                        int(vis.size()), g_reps));
      else
        c.ms.num("kernel",
                 gpu::pointsMs(mk::PointKernel{a, vis.data(), r.T_cw, r.K, r.opt.min_depth_m,
                                               r.opt.max_depth_m, 1, pa.view(), nullptr},
                               int(vis.size()), g_reps));
    }
#endif
    ctx.checks.push_back(c);
    if (!splat) continue;

    // The splat kernel + resolve against the product's model render (its SSE splat path).
    Check p{"render_vs_product", "(CPU only)",
            "SplatKernel + ResolveKernel vs the model the product's tracker used (dumped index, "
            "vertex, normal maps)",
            "exact (the SSE splat path is bit-identical to the kernels)"};
    Image<std::int32_t> index;
    Image<Vec3f> vertex, normal;
    resolve(a, pa, ctx.in.T_world_model, r.K, index, vertex, normal);
    long long mismatch = 0, drawn = 0;
    for (int y = 0; y < index.height(); ++y)
      for (int x = 0; x < index.width(); ++x) {
        mismatch += index(x, y) != ctx.in.model_index(x, y);
        drawn += index(x, y) >= 0;
      }
    Vec3Diff dv(0, 0), dn(0, 0);
    dv.add(vertex, ctx.in.model_vertex);
    dn.add(normal, ctx.in.model_normal);
    p.metrics.integer("pixels_drawn", drawn);
    p.limit("pixels_drawn_vs_product",
            std::fabs(double(drawn) - ctx.in.meta.num("model.pixels_drawn")), 0);
    p.limit("index_mismatch", double(mismatch), 0);
    p.limit("vertex_validity_mismatch", double(dv.validity_mismatch), 0);
    p.limit("vertex_max_abs_diff_m", dv.max_abs, 0);
    p.limit("normal_max_abs_diff", dn.max_abs, 0);
    ctx.checks.push_back(p);
  }
}

void checkIndexMap4x(Context& ctx) {
  const maps::SurfelArrays a = ctx.in.map.arrays();
  const std::vector<int>& vis = ctx.in.fuse_visible;
  const RenderSetup& r = ctx.index4x;
  Check c{"index_map_4x", "rasm::maps::cuda::pointsPacked4x (surfel_map/cuda/SurfelRender.cu)",
          "PointKernel (4x) over fusion's " + std::to_string(vis.size()) +
              " visible surfels at T_world_cam: packed 4x map and touched sub-pixels",
          g_tol.exact ? "exact"
                      : "as render_points; touched sub-pixel differs for <= 1e-3 of the surfels"};
  std::vector<std::int64_t> ta, tb;
  Image<std::uint64_t> pb;
  points4xCpu(a, vis, r, ctx.packed4x_cpu, ta);
  points4xB(a, vis, r, pb, tb);
  PackedDiff d;
  d.add(ctx.packed4x_cpu, pb);
  d.report(c);
  long long touched_mismatch = ta.size() == tb.size() ? 0 : (long long)(vis.size());
  for (std::size_t i = 0; i < ta.size() && i < tb.size(); ++i) touched_mismatch += ta[i] != tb[i];
  c.limit("touched_mismatch_frac", double(touched_mismatch) / std::max<double>(1, vis.size()),
          g_tol(1e-3));
  Image<std::uint64_t> scratch;
  c.ms.num("cpu", medianWallMs(g_reps, [&] { points4xCpu(a, vis, r, scratch, ta); }));
  c.ms.num("b", medianWallMs(g_reps, [&] { points4xB(a, vis, r, pb, tb); }));
#ifdef RASM_DEVICE_CHECK_CUDA
  if (g_cuda)
    c.ms.num("kernel",
             gpu::pointsMs(mk::PointKernel{a, vis.data(), r.T_cw, r.K, r.opt.min_depth_m,
                                           r.opt.max_depth_m, 4, scratch.view(), ta.data()},
                           int(vis.size()), g_reps));
#endif
  ctx.checks.push_back(c);
}

void checkIcp(Context& ctx) {
  const Inputs& in = ctx.in;
  auto reducer = std::make_shared<tracking::cuda::IcpCudaReducer>();
  const IcpBackend cpu = icpCpu(), b = icpB(reducer);
  {
    Check c{
        "icp_reduce",
        "rasm::tracking::cuda::IcpCudaReducer::upload/reduce (tracking/cuda/IcpReduce.cu)",
        "IcpReduceKernel sums (33 entries) at the motion-model guess, levels 2, 1, 0 (stride " +
            std::to_string(ctx.icp.stride0) + " at 0)",
        g_tol.exact
            ? "exact"
            : "valid pixels identical; inliers within 1e-4 n + 2; entries within 1e-3 (1 + |s|)"};
    double max_rel = 0, inlier_diff = 0, valid_diff = 0;
    JsonObject per;
    for (int l = ctx.icp.levels - 1; l >= 0; --l) {
      const tk::IcpReduceKernel k =
          icpKernel(ctx.pyr, ctx.icp, in.K, l, in.T_guess, in.T_world_model);
      const tk::IcpAccumulator ra = cpu.reduce(l, k);
      b.upload(l, k);
      const tk::IcpAccumulator rb = b.reduce(l, k);
      for (int i = 0; i < tk::IcpAccumulator::kSize; ++i)
        max_rel = std::max(max_rel, std::fabs(ra.s[i] - rb.s[i]) / (1.0 + std::fabs(ra.s[i])));
      valid_diff = std::max(valid_diff, std::fabs(ra.valid() - rb.valid()));
      inlier_diff =
          std::max(inlier_diff, std::fabs(ra.inliers() - rb.inliers()) - 1e-4 * ra.inliers());
      per.integer("inliers_level" + std::to_string(l), (long long)ra.inliers());
    }
    c.metrics = per;
    c.limit("valid_diff", valid_diff, 0);
    c.limit("inliers_diff_minus_1e-4n", std::max(0.0, inlier_diff), g_tol(2));
    c.limit("max_rel_entry_diff", max_rel, g_tol(1e-3));
    const tk::IcpReduceKernel k0 =
        icpKernel(ctx.pyr, ctx.icp, in.K, 0, in.T_guess, in.T_world_model);
    c.ms.num("level0_cpu", medianWallMs(g_reps, [&] { cpu.reduce(0, k0); }));
    if (g_cuda) {
      c.ms.num("level0_upload_b", medianWallMs(g_reps, [&] { b.upload(0, k0); }));
      c.ms.num("level0_reduce_b",
               medianWallMs(g_reps, [&] { b.reduce(0, k0); }));  // images resident
    } else {
      c.ms.num("level0_b", medianWallMs(g_reps, [&] { b.reduce(0, k0); }));
    }
    ctx.checks.push_back(c);
  }
  {
    Check c{
        "icp_track", "rasm::tracking::cuda::IcpCudaReducer (tracking/cuda/IcpReduce.cu)",
        "coarse-to-fine Gauss-Newton from the guess with each backend's sums: final poses",
        g_tol.exact
            ? "exact"
            : "0.5 mm, 0.05 deg (both converge to the same minimum; the last step is < 0.1 mm)"};
    const TrackResult ta = track(ctx.pyr, ctx.icp, in.K, in.T_guess, in.T_world_model, cpu);
    const TrackResult tb = track(ctx.pyr, ctx.icp, in.K, in.T_guess, in.T_world_model, b);
    c.metrics.integer("iterations_cpu", ta.iterations).integer("iterations_b", tb.iterations);
    c.metrics.integer("inliers_cpu", (long long)ta.inliers)
        .integer("inliers_b", (long long)tb.inliers);
    c.limit("translation_diff_m", translationDiff(ta.T, tb.T), g_tol(5e-4));
    c.limit("rotation_diff_deg", rotationDiffDeg(ta.T, tb.T), g_tol(0.05));
    ctx.checks.push_back(c);

    // The same sums solved here against the product's tracker (its solver adds scale balancing and
    // degeneracy handling, so only the pose, within what the convergence limits allow).
    Check p{"icp_track_vs_product", "(CPU only)",
            "this Gauss-Newton on the CPU kernel's sums vs the product's pose",
            "1 mm, 0.1 deg (different solvers stopping at 0.1 mm / 0.01 deg steps)"};
    p.metrics.integer("iterations_product", (long long)in.meta.num("product.icp_iterations"));
    p.limit("translation_diff_m", translationDiff(ta.T, in.T_world_cam), 1e-3);
    p.limit("rotation_diff_deg", rotationDiffDeg(ta.T, in.T_world_cam), 0.1);
    p.metrics.num("guess_vs_product_m", translationDiff(in.T_guess, in.T_world_cam));
    ctx.checks.push_back(p);
  }
}

void checkFusion(Context& ctx) {
  const Inputs& in = ctx.in;
  HostMap ma = in.map, mb = in.map;
  FusionOut oa, ob;
  const FusionKernels ka =
      fusionKernels(ctx.fusion, in, ma.arrays(), ctx.packed4x_cpu, in.T_world_cam, oa);
  const FusionKernels kb =
      fusionKernels(ctx.fusion, in, mb.arrays(), ctx.packed4x_cpu, in.T_world_cam, ob);
  fuseCpu(ka);
  fuseB(kb);
  Check c{"fusion", "rasm::fusion::cuda::associateUpdate (fusion/cuda/FusionKernels.cu)",
          "AssociateKernel + UpdateKernel + CoverageKernel on the 4x map at T_world_cam, " +
              std::to_string(in.map.size()) + " surfels: per-pixel results and the surfel arrays",
          g_tol.exact ? "exact"
                      : "pixel results differ <= 1e-3 of valid pixels; of the surfels both update "
                        "from the same "
                        "pixel <= 1e-4 off (position, normal, radius 1e-5, confidence 1e-5 "
                        "relative, colour and view "
                        "bins 1 step, segment, time and flags exact)"};
  long long ps_mismatch = 0, flag_mismatch = 0;
  for (int y = 0; y < oa.flags.height(); ++y)
    for (int x = 0; x < oa.flags.width(); ++x) {
      ps_mismatch += oa.pixel_surfel(x, y) != ob.pixel_surfel(x, y);
      flag_mismatch += oa.flags(x, y) != ob.flags(x, y);
    }
  // Surfels updated by the same pixel on both backends: "off" when any attribute differs by more
  // than float rounding can explain (position, normal, radius 1e-5; confidence 1e-5 relative;
  // colour and view bins one quantisation step; segment and time exactly).
  double max_pos = 0, max_nrm = 0, max_conf_rel = 0;
  int max_colour = 0, max_view = 0;
  long long compared = 0, off = 0;
  for (int y = 0; y < oa.flags.height(); ++y)
    for (int x = 0; x < oa.flags.width(); ++x) {
      const int i = oa.pixel_surfel(x, y);
      if (i < 0 || i != ob.pixel_surfel(x, y)) continue;
      ++compared;
      const double dp = (ma.pos[i].head<3>() - mb.pos[i].head<3>()).cwiseAbs().maxCoeff();
      const double dn = (ma.nrm[i] - mb.nrm[i]).cwiseAbs().maxCoeff();
      const double dc = std::fabs(ma.pos[i].w() - mb.pos[i].w()) / std::max(1e-6f, ma.pos[i].w());
      int dcol = 0, dview = 0;
      for (int ch = 0; ch < 24; ch += 8)
        dcol =
            std::max(dcol, std::abs(int((ma.cf[i] >> ch) & 0xff) - int((mb.cf[i] >> ch) & 0xff)));
      for (int v = 0; v < ma.n_view_bins; ++v) {
        const std::size_t j = std::size_t(i) * ma.n_view_bins + v;
        dview = std::max(dview, std::abs(int(ma.view[j]) - int(mb.view[j])));
      }
      const bool exact_fields = ma.seg[i] == mb.seg[i] && ma.segw[i] == mb.segw[i] &&
                                ma.tl[i] == mb.tl[i] && (ma.cf[i] >> 24) == (mb.cf[i] >> 24);
      max_pos = std::max(max_pos, dp);
      max_nrm = std::max(max_nrm, dn);
      max_conf_rel = std::max(max_conf_rel, dc);
      max_colour = std::max(max_colour, dcol);
      max_view = std::max(max_view, dview);
      const double t = g_tol(1e-5);
      off += dp > t || dn > t || dc > t || dcol > g_tol(1) || dview > g_tol(1) || !exact_fields;
    }
  const FusionCounts ca(oa.flags), cb(ob.flags);
  const double nv = double(std::max(1LL, ca.valid));
  c.metrics.integer("valid_pixels", ca.valid)
      .integer("associated_cpu", ca.associated)
      .integer("associated_b", cb.associated);
  c.metrics.integer("covered_cpu", ca.covered)
      .integer("covered_b", cb.covered)
      .integer("surfels_compared", compared);
  c.metrics.num("max_position_diff_m", max_pos).num("max_normal_radius_diff", max_nrm);
  c.metrics.num("max_confidence_rel_diff", max_conf_rel).integer("max_colour_diff", max_colour);
  c.metrics.integer("max_view_bin_diff", max_view);
  c.limit("pixel_surfel_mismatch_frac", double(ps_mismatch) / nv, g_tol(1e-3));
  c.limit("flags_mismatch_frac", double(flag_mismatch) / nv, g_tol(1e-3));
  c.limit("surfels_off_frac", double(off) / double(std::max(1LL, compared)), g_tol(1e-4));
  // Times: each run starts from the dumped map (the restore is not timed).
  HostMap mt = in.map;
  FusionOut ot;
  const FusionKernels kt =
      fusionKernels(ctx.fusion, in, mt.arrays(), ctx.packed4x_cpu, in.T_world_cam, ot);
  const auto restore = [&] {
    std::copy(in.map.pos.begin(), in.map.pos.end(), mt.pos.begin());
    std::copy(in.map.nrm.begin(), in.map.nrm.end(), mt.nrm.begin());
    std::copy(in.map.cf.begin(), in.map.cf.end(), mt.cf.begin());
    std::copy(in.map.tl.begin(), in.map.tl.end(), mt.tl.begin());
    std::copy(in.map.basis.begin(), in.map.basis.end(), mt.basis.begin());
    std::copy(in.map.seg.begin(), in.map.seg.end(), mt.seg.begin());
    std::copy(in.map.segw.begin(), in.map.segw.end(), mt.segw.begin());
    std::copy(in.map.view.begin(), in.map.view.end(), mt.view.begin());
  };
  std::vector<double> tc, tbs;
  for (int r = 0; r < g_reps; ++r) {
    restore();
    tc.push_back(medianWallMs(1, [&] { fuseCpu(kt); }));
    restore();
    tbs.push_back(medianWallMs(1, [&] { fuseB(kt); }));
  }
  std::nth_element(tc.begin(), tc.begin() + tc.size() / 2, tc.end());
  std::nth_element(tbs.begin(), tbs.begin() + tbs.size() / 2, tbs.end());
  c.ms.num("cpu", tc[tc.size() / 2]).num("b", tbs[tbs.size() / 2]);
#ifdef RASM_DEVICE_CHECK_CUDA
  if (g_cuda) {
    restore();
    const gpu::FusionMs g = gpu::fusionMs(kt.a, kt.u, kt.c, g_reps);
    c.ms.num("associate_kernel", g.associate)
        .num("update_kernel", g.update)
        .num("coverage_kernel", g.coverage);
  }
#endif
  ctx.checks.push_back(c);

  // The CPU kernels (4x map candidates) against the product's CPU fusion (candidate lists, SSE).
  Check p{"fusion_vs_product", "(CPU only)",
          "counts of the kernels' association / update / coverage vs the product's FusionStats for "
          "the frame",
          "exact (both see the same candidates and gates)"};
  const Meta& m = in.meta;
  p.limit("valid_pixels_diff", std::fabs(double(ca.valid) - m.num("product.fusion_valid_pixels")),
          0);
  p.limit("associated_diff", std::fabs(double(ca.associated) - m.num("product.fusion_associated")),
          0);
  p.limit("fused_diff", std::fabs(double(ca.fused) - m.num("product.fusion_fused")), 0);
  p.limit("covered_diff", std::fabs(double(ca.covered) - m.num("product.fusion_covered")), 0);
  p.limit("became_stable_diff",
          std::fabs(double(ca.became_stable) - m.num("product.fusion_became_stable")), 0);
  p.limit("new_diff", std::fabs(double(ca.added) - m.num("product.fusion_added")), 0);
  ctx.checks.push_back(p);
}

// ---- one track + fuse frame -------------------------------------------------------------------

/// One frame of section II through one backend: frame pyramid (depth halving on the CPU), model
/// render at T_world_model (splat; resolve on the CPU), model pyramid (CPU), ICP from the guess,
/// 4x index map at the tracked pose, association / update / coverage. Not included: the
/// bilateral filter, the host-side culling (the visible lists come with the inputs), new surfels
/// and the cleanup, which have no CUDA launcher. Returns ms per step.
struct FrameRun {
  JsonObject ms;
  double total_ms = 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  long long associated = 0;
};
FrameRun frame(Context& ctx, bool cpu, HostMap& map, tracking::cuda::IcpCudaReducer* reducer) {
  FrameRun run;
  const Inputs& in = ctx.in;
  std::vector<std::pair<std::string, double>> ms;
  auto t = Clock::now();
  const auto lap = [&](const char* what) {
    const auto now = Clock::now();
    ms.emplace_back(what, std::chrono::duration<double, std::milli>(now - t).count());
    t = now;
  };
  Pyramids p;
  p.fv.resize(3);
  p.fn.resize(3);
  Image<float> d = in.depth[0];
  for (int l = 0; l < 3; ++l) {
    if (l > 0) {
      Image<float> half;
      downsample(d, half);
      d = half;
    }
    if (cpu) {
      vertexCpu(d, in.K[l], ctx.fo, p.fv[l]);
      normalCpu(p.fv[l], ctx.fo.jump, p.fn[l]);
    } else {
      vertexB(d, in.K[l], ctx.fo, p.fv[l]);
      normalB(p.fv[l], ctx.fo.jump, p.fn[l]);
    }
  }
  lap("frame_pyramid");
  const maps::SurfelArrays a = map.arrays();
  Image<std::uint64_t> packed;
  if (cpu)
    splatCpu(a, in.model_visible, ctx.model, packed);
  else
    splatB(a, in.model_visible, ctx.model, packed);
  Image<std::int32_t> index;
  Image<Vec3f> mv0, mn0;
  resolve(a, packed, in.T_world_model, ctx.model.K, index, mv0, mn0);
  lap("model_render");
  modelPyramid(mv0, mn0, in.T_world_model, ctx.icp.levels, p.mv, p.mn);
  lap("model_pyramid");
  IcpBackend be = icpCpu();
  if (!cpu) {
    std::shared_ptr<tracking::cuda::IcpCudaReducer> keep(reducer,
                                                         [](tracking::cuda::IcpCudaReducer*) {});
    be = icpB(keep);
  }
  const TrackResult tr = track(p, ctx.icp, in.K, in.T_guess, in.T_world_model, be);
  run.T = tr.T;
  lap("icp");
  RenderSetup r4 = ctx.index4x;
  r4.T_cw = rigid(tr.T.inverse());
  Image<std::uint64_t> packed4x;
  std::vector<std::int64_t> touched;
  if (cpu)
    points4xCpu(a, in.fuse_visible, r4, packed4x, touched);
  else
    points4xB(a, in.fuse_visible, r4, packed4x, touched);
  lap("index_map_4x");
  FusionSetup fs = ctx.fusion;
  fs.frame.vertex_cam = p.fv[0].cview();
  fs.frame.normal_cam = p.fn[0].cview();
  FusionOut out;
  const FusionKernels k = fusionKernels(fs, in, a, packed4x, tr.T, out);
  if (cpu)
    fuseCpu(k);
  else
    fuseB(k);
  lap("fusion");
  run.associated = FusionCounts(out.flags).associated;
  for (const auto& [name, v] : ms) {
    run.ms.num(name, v);
    run.total_ms += v;
  }
  run.ms.num("total", run.total_ms);
  return run;
}

JsonObject frameTimes(Context& ctx) {
  JsonObject o;
  o.str("steps",
        "frame pyramid (3 levels; halving on the CPU), model splat (+ CPU resolve), model pyramid "
        "(CPU), "
        "ICP from the guess (upload + reductions; solve on the host), 4x index map at the tracked "
        "pose, "
        "association + update + coverage. Not in it: bilateral filter, host culling (visible lists "
        "given), "
        "new surfels, cleanup. ms of the median run (by total)");
  tracking::cuda::IcpCudaReducer reducer;
  for (const bool cpu : {true, false}) {
    std::vector<FrameRun> runs;
    for (int r = 0; r < std::max(3, g_reps / 3) + 1; ++r) {
      HostMap map = ctx.in.map;  // every run fuses into the dumped map (copy not timed)
      FrameRun f = frame(ctx, cpu, map, &reducer);
      if (r > 0) runs.push_back(f);  // run 0 warms up (first CUDA launches, allocations)
    }
    std::sort(runs.begin(), runs.end(),
              [](const FrameRun& x, const FrameRun& y) { return x.total_ms < y.total_ms; });
    const FrameRun& med = runs[runs.size() / 2];
    JsonObject j = med.ms;
    j.num("pose_vs_product_m", translationDiff(med.T, ctx.in.T_world_cam));
    j.integer("associated", med.associated);
    o.obj(cpu ? "cpu_ms" : (g_cuda ? "cuda_launchers_ms" : "b_cpu_1_thread_ms"), j);
  }
  return o;
}

// ---- main ------------------------------------------------------------------------------------

int run(int argc, char** argv, JsonObject& out) {
  std::string dir = "device/data";
  std::string json_path, build_info;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--reps" && i + 1 < argc)
      g_reps = std::max(1, std::atoi(argv[++i]));
    else if (a == "--json" && i + 1 < argc)
      json_path = argv[++i];
    else if (a == "--build-info" && i + 1 < argc)
      build_info = argv[++i];
    else
      dir = a;
  }
  const auto t0 = Clock::now();
  out.str("check", "rasm device-check").integer("format", 1);
#ifdef RASM_DEVICE_CHECK_CUDA
  const gpu::Info gi = gpu::info();
  g_cuda = gi.available;
  out.str("build", "cuda");
  if (gi.available) {
    JsonObject g;
    g.str("name", gi.name)
        .str("compute_capability", std::to_string(gi.cc_major) + "." + std::to_string(gi.cc_minor));
    g.integer("sms", gi.sm_count).num("memory_gib", gi.memory_gib);
    g.integer("driver", gi.driver_version).integer("runtime", gi.runtime_version);
    out.obj("gpu", g);
  } else {
    out.str("gpu", "skipped: " + gi.reason);
  }
#else
  out.str("build", "cpu");
  out.str("gpu", "skipped: dry run (built with the host compiler, no CUDA)");
#endif
  if (!build_info.empty()) out.str("build_info", build_info);
  g_tol.exact = !g_cuda;
  out.str("backend_b",
          g_cuda ? "CUDA launchers" : "the same CPU loops on 1 thread (exact comparison)");
  out.integer("cpu_threads", compute::maxThreads()).integer("reps", g_reps);
  out.str("tolerances",
          g_tol.exact
              ? "exact: backend B runs the same CPU code"
              : "GPU vs CPU: nvcc contracts a*b+c into FMA, the x86-64-v2 host does not, and "
                "sums are added in another order; each check states its limits");

  Context ctx;
  ctx.in = Inputs::load(dir);
  const Meta& m = ctx.in.meta;
  ctx.fo.vo.min_depth_m = float(m.num("mapper.min_depth_m"));
  ctx.fo.vo.max_depth_m = float(m.num("mapper.max_depth_m"));
  ctx.fo.jump = float(m.num("mapper.normal_max_jump_rel"));
  IcpParams& P = ctx.icp;
  P.levels = int(m.num("tracking.num_levels"));
  P.stride0 = int(m.num("tracking.level0_pixel_stride"));
  P.model_level = int(m.num("tracking.model_level"));
  const std::vector<double> it = m.values("tracking.iterations", 3),
                            md = m.values("tracking.max_dist_m", 3),
                            na = m.values("tracking.max_normal_angle_deg", 3);
  for (int l = 0; l < 3; ++l) {
    P.iterations[l] = int(it[l]);
    P.max_dist[l] = md[l];
    P.normal_deg[l] = na[l];
  }
  P.huber = m.num("tracking.huber_delta_m");
  P.noise_weighting = m.num("tracking.depth_noise_weighting") != 0;
  P.conv_t = m.num("tracking.convergence_translation_m");
  P.conv_rot_deg = m.num("tracking.convergence_rotation_deg");
  if (P.model_level != 0 || P.levels != 3)
    throw std::runtime_error("inputs need [tracking] model_level 0, 3 levels");
  ctx.model = renderSetup(m, ctx.in.K[0], ctx.in.T_world_model, true);
  ctx.model_points = ctx.model;
  ctx.model_points.opt.splat = false;
  ctx.index4x = renderSetup(m, ctx.in.K[0], ctx.in.T_world_cam, false);
  ctx.fusion = fusionSetup(ctx.in);
  // ICP inputs: the product's level-0 frame maps, the kernels' coarser levels; the model pyramid
  // from the product's model render.
  ctx.pyr.fv.resize(3);
  ctx.pyr.fn.resize(3);
  ctx.pyr.fv[0] = ctx.in.vertex0;
  ctx.pyr.fn[0] = ctx.in.normal0;
  Image<float> d = ctx.in.depth[0];
  for (int l = 1; l < 3; ++l) {
    Image<float> half;
    downsample(d, half);
    d = half;
    vertexCpu(d, ctx.in.K[l], ctx.fo, ctx.pyr.fv[l]);
    normalCpu(ctx.pyr.fv[l], ctx.fo.jump, ctx.pyr.fn[l]);
  }
  modelPyramid(ctx.in.model_vertex, ctx.in.model_normal, ctx.in.T_world_model, P.levels, ctx.pyr.mv,
               ctx.pyr.mn);

  JsonObject inputs;
  inputs.str("folder", dir)
      .str("sequence", m.str("sequence"))
      .integer("frame", (long long)m.num("frame_index"));
  if (m.has("dump_commit")) inputs.str("dump_commit", m.str("dump_commit"));
  inputs.integer("frames", (long long)ctx.in.depth.size()).integer("surfels", ctx.in.map.size());
  inputs.integer("model_visible", (long long)ctx.in.model_visible.size());
  inputs.integer("fuse_visible", (long long)ctx.in.fuse_visible.size());
  inputs.num("map_mib", double(ctx.in.bytes) / (1024.0 * 1024.0));
  out.obj("inputs", inputs);

  // A launcher that throws (a CUDA error) fails its check; the others still run.
  const auto guarded = [&](const char* name, void (*f)(Context&)) {
    try {
      f(ctx);
    } catch (const std::exception& e) {
      Check c(name, "", "", "");
      c.pass = false;
      c.failed.push_back(std::string("error: ") + e.what());
      ctx.checks.push_back(c);
    }
  };
  guarded("frame_maps", checkFrameMaps);
  guarded("render", checkRender);
  guarded("index_map_4x", checkIndexMap4x);
  guarded("icp", checkIcp);
  guarded("fusion", checkFusion);
  JsonObject fr;
  try {
    fr = frameTimes(ctx);
  } catch (const std::exception& e) {
    fr.str("error", e.what());
    Check c("frame", "", "", "");
    c.pass = false;
    c.failed.push_back(std::string("error: ") + e.what());
    ctx.checks.push_back(c);
  }

  std::vector<JsonObject> cj;
  std::vector<std::string> failed;
  for (const Check& c : ctx.checks) {
    cj.push_back(c.json());
    if (!c.pass) failed.push_back(c.name);
  }
  out.arr("checks", cj).obj("frame", fr);
  out.boolean("pass", failed.empty()).strs("failed", failed);
  out.num("wall_s", std::chrono::duration<double>(Clock::now() - t0).count());
  if (!json_path.empty()) {
    std::ofstream(json_path) << out.dump(1) << "\n";
  }
  if (!failed.empty()) return 1;
#ifdef RASM_DEVICE_CHECK_CUDA
  if (!g_cuda) return 3;
#endif
  return 0;
}

}  // namespace
}  // namespace rasm::device

int main(int argc, char** argv) {
  rasm::device::JsonObject out;
  int rc = 2;
  std::string json_path;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--json") json_path = argv[i + 1];
  try {
    rc = rasm::device::run(argc, argv, out);
  } catch (const std::exception& e) {
    out.boolean("pass", false).str("error", e.what());
    if (!json_path.empty()) std::ofstream(json_path) << out.dump(1) << "\n";
  }
  std::printf("%s\n", out.dump(1).c_str());
  return rc;
}
