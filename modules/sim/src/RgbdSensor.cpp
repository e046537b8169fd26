#include "rasm/sim/RgbdSensor.h"

#include <mrpt/config/CConfigFileBase.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <sstream>

#include "ParamsWrite.h"
#include "RaySceneImpl.h"
#include "rasm/compute/Parallel.h"
#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/core/Validate.h"

namespace rasm::sim {

// ---- params -------------------------------------------------------------------------------------

CameraIntrinsics TSensorParams::intrinsics() const {
  CameraIntrinsics K = CameraIntrinsics::preset(camera);
  if (width > 0) K.width = width;
  if (height > 0) K.height = height;
  if (fx > 0) K.fx = fx;
  if (fy > 0) K.fy = fy;
  if (cx > 0) K.cx = cx;
  if (cy > 0) K.cy = cy;
  return K;
}

DepthModelParams TSensorParams::depthModel() const {
  DepthModelParams p;
  p.axial_noise = noise;
  p.lateral_noise = noise && lateral_sigma_px > 0;
  p.axial.sigma0_m = float(axial_sigma0_m);
  p.axial.sigma_quad = float(axial_sigma_quad);
  p.axial.z0_m = float(axial_z0_m);
  p.axial.sigma_angle = float(axial_sigma_angle);
  // Nguyen et al. measured sigma_L in pixels of the Kinect's 640x480 image: a render with another
  // focal length (e.g. 320x240 at fx 262.5) has the same angular noise in its own pixels, i.e.
  // sigma_L scaled by fx / the preset's fx, so that depth edges move by the same angle at every
  // resolution (docs/sim.md "RGB-D sensor").
  const double lateral_scale = intrinsics().fx / CameraIntrinsics::preset(camera).fx;
  p.lateral_px = float(lateral_sigma_px * lateral_scale);
  p.lateral_angle = float(lateral_sigma_angle * lateral_scale);
  p.disparity_fb = float(disparity_focal_px * disparity_baseline_m);
  p.disparity_subpixel = noise ? float(disparity_subpixel) : 0.f;
  p.min_depth_m = float(min_depth_m);
  p.max_depth_m = float(max_depth_m);
  p.max_incidence_rad = float(grazing_max_deg * M_PI / 180.0);
  return p;
}

void TSensorParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                       const std::string& s) {
  MRPT_LOAD_CONFIG_VAR_CS(camera, string);
  MRPT_LOAD_CONFIG_VAR_CS(width, int);
  MRPT_LOAD_CONFIG_VAR_CS(height, int);
  MRPT_LOAD_CONFIG_VAR_CS(fx, double);
  MRPT_LOAD_CONFIG_VAR_CS(fy, double);
  MRPT_LOAD_CONFIG_VAR_CS(cx, double);
  MRPT_LOAD_CONFIG_VAR_CS(cy, double);
  MRPT_LOAD_CONFIG_VAR_CS(min_depth_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_depth_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(noise, bool);
  MRPT_LOAD_CONFIG_VAR_CS(dropouts, bool);
  MRPT_LOAD_CONFIG_VAR_CS(axial_sigma0_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(axial_sigma_quad, double);
  MRPT_LOAD_CONFIG_VAR_CS(axial_z0_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(axial_sigma_angle, double);
  MRPT_LOAD_CONFIG_VAR_CS(lateral_sigma_px, double);
  MRPT_LOAD_CONFIG_VAR_CS(lateral_sigma_angle, double);
  MRPT_LOAD_CONFIG_VAR_CS(disparity_focal_px, double);
  MRPT_LOAD_CONFIG_VAR_CS(disparity_baseline_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(disparity_subpixel, double);
  MRPT_LOAD_CONFIG_VAR_CS(projector_offset_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(grazing_max_deg, double);
  MRPT_LOAD_CONFIG_VAR_CS(labels, bool);
  MRPT_LOAD_CONFIG_VAR_CS(ray_packets, bool);
  validate(s);
}

void TSensorParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  RASM_SIM_SAVE(camera, "CameraIntrinsics preset: kinect_v1, kinect_v2_depth, xtion, ...");
  RASM_SIM_SAVE(width, "override the preset when > 0 (pixels)");
  RASM_SIM_SAVE(height, "");
  RASM_SIM_SAVE(fx, "override the preset when > 0 (pixels)");
  RASM_SIM_SAVE(fy, "");
  RASM_SIM_SAVE(cx, "");
  RASM_SIM_SAVE(cy, "");
  RASM_SIM_SAVE(min_depth_m, "measured depth outside [min, max] is missing");
  RASM_SIM_SAVE(max_depth_m, "");
  RASM_SIM_SAVE(noise, "axial + lateral noise and disparity quantization; false = exact depth");
  RASM_SIM_SAVE(dropouts, "projector-shadow and grazing-angle missing data");
  RASM_SIM_SAVE(axial_sigma0_m,
                "Nguyen 2012 sigma_z: a + b (z - z0)^2 + c / sqrt(z) th^2/(pi/2-th)^2");
  RASM_SIM_SAVE(axial_sigma_quad, "b (1/m)");
  RASM_SIM_SAVE(axial_z0_m, "z0 (m)");
  RASM_SIM_SAVE(axial_sigma_angle, "c");
  RASM_SIM_SAVE(
      lateral_sigma_px,
      "Nguyen 2012 sigma_L at theta = 0 (px of the preset; scaled by fx / its fx); 0 = off");
  RASM_SIM_SAVE(lateral_sigma_angle, "angle term of sigma_L (px)");
  RASM_SIM_SAVE(disparity_focal_px, "quantization: depth step z^2 / (f b) / subpixel");
  RASM_SIM_SAVE(disparity_baseline_m, "");
  RASM_SIM_SAVE(disparity_subpixel, "disparity resolution 1/subpixel px; 0 = no quantization");
  RASM_SIM_SAVE(projector_offset_m, "IR projector along camera +x (m); 0 = no shadows");
  RASM_SIM_SAVE(grazing_max_deg, "incidence angles above this are missing");
  RASM_SIM_SAVE(labels, "render gt_instance / gt_class");
  RASM_SIM_SAVE(ray_packets, "4x4 Embree ray packets (faster) instead of single rays");
}

void TSensorParams::validate(const std::string& s) const {
  (void)CameraIntrinsics::preset(camera);  // throws on an unknown name
  requireInRange(width, 0, 16384, s, "width");
  requireInRange(height, 0, 16384, s, "height");
  requireInRange(min_depth_m, 0.0, 1e3, s, "min_depth_m");
  requireInRange(max_depth_m, min_depth_m, 1e4, s, "max_depth_m");
  requireInRange(axial_sigma0_m, 0.0, 1.0, s, "axial_sigma0_m");
  requireInRange(axial_sigma_quad, 0.0, 1.0, s, "axial_sigma_quad");
  requireInRange(axial_sigma_angle, 0.0, 1.0, s, "axial_sigma_angle");
  requireInRange(lateral_sigma_px, 0.0, 20.0, s, "lateral_sigma_px");
  requireInRange(lateral_sigma_angle, 0.0, 10.0, s, "lateral_sigma_angle");
  requireInRange(disparity_focal_px, 1.0, 1e5, s, "disparity_focal_px");
  requireInRange(disparity_baseline_m, 1e-4, 10.0, s, "disparity_baseline_m");
  requireInRange(disparity_subpixel, 0.0, 1024.0, s, "disparity_subpixel");
  requireInRange(projector_offset_m, -10.0, 10.0, s, "projector_offset_m");
  requireInRange(grazing_max_deg, 0.0, 90.0, s, "grazing_max_deg");
  if (!intrinsics().valid())
    throwInputError("[" + s + "] camera", "invalid intrinsics " + intrinsics().toString());
}

// ---- sensor -------------------------------------------------------------------------------------

namespace {

/// Everything one tile of the ray cast writes (plain views; one struct instead of many arguments).
struct CastTargets {
  ImageView<float> z;
  ImageView<float> cos_incidence;
  ImageView<Bgr8> colour;
  ImageView<std::uint16_t> instance;
  ImageView<std::uint16_t> cls;
  bool labels = true;
};

struct CastSetup {
  Mat3f R;  ///< R_world_cam
  Vec3f o;  ///< camera centre in the world
  PinholeF K;
  float inv_fx = 1.f, inv_fy = 1.f;
  const SurfaceMaterial* materials = nullptr;
  LightF light;
  Bgr8 background;
};

/// Writes one pixel from an Embree hit (geom == RTC_INVALID_GEOMETRY_ID: nothing hit).
__attribute__((always_inline)) inline void writePixel(const CastSetup& s, const CastTargets& t,
                                                      int x, int y, const Vec3f& d, unsigned geom,
                                                      float tfar, float ngx, float ngy, float ngz) {
  if (geom == RTC_INVALID_GEOMETRY_ID) {
    t.z(x, y) = 0.f;
    t.cos_incidence(x, y) = 1.f;
    t.colour(x, y) = s.background;
    if (t.labels) {
      t.instance(x, y) = 0;
      t.cls(x, y) = 0;
    }
    return;
  }
  // Unit normal facing the camera and the cosine of the incidence angle: one sqrt and one
  // division for both normalizations.
  Vec3f n(ngx, ngy, ngz);
  const float nd = n.dot(d);
  const float inv = 1.f / std::sqrt(n.squaredNorm() * d.squaredNorm());
  const float dn = std::sqrt(d.squaredNorm());
  n *= (nd > 0.f ? -inv : inv) * dn;
  const float c = std::abs(nd) * inv;  // cos of the incidence angle
  const SurfaceMaterial& m = s.materials[geom];
  t.z(x, y) = tfar;  // d has unit z in the camera frame, so the ray parameter is the depth
  t.cos_incidence(x, y) = c;
  t.colour(x, y) = toBgr8(shadeSurface(m, s.light, s.o + tfar * d, n));
  if (t.labels) {
    t.instance(x, y) = m.instance_id;
    t.cls(x, y) = m.class_id;
  }
}

/// Ray direction of pixel (x, y) in the world, with unit z in the camera frame (so the ray
/// parameter of a hit is its depth).
inline Vec3f pixelRay(const CastSetup& s, int x, int y) {
  return s.R * Vec3f((float(x) - s.K.cx) * s.inv_fx, (float(y) - s.K.cy) * s.inv_fy, 1.f);
}

void castPackets(RTCScene scene, const CastSetup& s, const CastTargets& t) {
  constexpr int T = 4;  // 4x4 pixel tiles = one RTCRayHit16 packet
  const int w = s.K.width, h = s.K.height;
  const int tiles_x = (w + T - 1) / T, tiles_y = (h + T - 1) / T;
#pragma omp parallel for schedule(dynamic, 1)
  for (int ty = 0; ty < tiles_y; ++ty) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) RTCRayHit16 rh;
    alignas(64) int valid[16];
    Vec3f dirs[16];
    for (int k = 0; k < 16; ++k) {  // what Embree does not modify is set once per thread
      rh.ray.org_x[k] = s.o.x();
      rh.ray.org_y[k] = s.o.y();
      rh.ray.org_z[k] = s.o.z();
      rh.ray.tnear[k] = 0.f;
      rh.ray.time[k] = 0.f;
      rh.ray.mask[k] = 0xFFFFFFFFu;
      rh.ray.id[k] = unsigned(k);
      rh.ray.flags[k] = 0;
    }
    for (int tx = 0; tx < tiles_x; ++tx) {
      for (int k = 0; k < 16; ++k) {
        const int x = tx * T + (k & 3), y = ty * T + (k >> 2);
        valid[k] = (x < w && y < h) ? -1 : 0;
        const Vec3f d = pixelRay(s, std::min(x, w - 1), std::min(y, h - 1));
        dirs[k] = d;
        rh.ray.dir_x[k] = d.x();
        rh.ray.dir_y[k] = d.y();
        rh.ray.dir_z[k] = d.z();
        rh.ray.tfar[k] = std::numeric_limits<float>::infinity();
        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, scene, &ctx, &rh);
      for (int k = 0; k < 16; ++k) {
        if (!valid[k]) continue;
        writePixel(s, t, tx * T + (k & 3), ty * T + (k >> 2), dirs[k], rh.hit.geomID[k],
                   rh.ray.tfar[k], rh.hit.Ng_x[k], rh.hit.Ng_y[k], rh.hit.Ng_z[k]);
      }
    }
  }
}

void castSingle(RTCScene scene, const CastSetup& s, const CastTargets& t) {
  const int w = s.K.width, h = s.K.height;
#pragma omp parallel for schedule(dynamic, 4)
  for (int y = 0; y < h; ++y) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    for (int x = 0; x < w; ++x) {
      const Vec3f d = pixelRay(s, x, y);
      RTCRayHit rh;
      initRayHit(rh, s.o, d, 0.f, std::numeric_limits<float>::infinity());
      rtcIntersect1(scene, &ctx, &rh);
      writePixel(s, t, x, y, d, rh.hit.geomID, rh.ray.tfar, rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    }
  }
}

}  // namespace

RgbdSensor::RgbdSensor(const RayScene& scene, const TSensorParams& params)
    : m_scene(scene), m_params(params), m_K(params.intrinsics()) {
  m_params.validate();
}

std::uint64_t RgbdSensor::frameKey(std::uint64_t seed, std::size_t frame_index) {
  std::seed_seq seq{std::uint32_t(seed), std::uint32_t(seed >> 32), std::uint32_t(frame_index),
                    std::uint32_t(std::uint64_t(frame_index) >> 32)};
  std::mt19937 gen(seq);
  const std::uint64_t hi = gen();
  return (hi << 32) | gen();
}

RgbdFrame RgbdSensor::render(const Eigen::Isometry3d& T_world_cam, std::uint64_t seed,
                             std::size_t frame_index) const {
  RgbdFrame f;
  render(T_world_cam, seed, frame_index, f);
  return f;
}

void RgbdSensor::render(const Eigen::Isometry3d& T_world_cam, std::uint64_t seed,
                        std::size_t frame_index, RgbdFrame& out) const {
  // A non-finite or far-away pose would abort the ray tracer: every pose is checked here, where
  // the rays start, whatever gave it (a trajectory file, the command line, a planner).
  const Eigen::Matrix4d& M = T_world_cam.matrix();
  if (!M.allFinite() || M.block<3, 1>(0, 3).cwiseAbs().maxCoeff() > kMaxCoordinate_m) {
    std::ostringstream s;
    s << "camera position [" << M.block<3, 1>(0, 3).transpose() << "]"
      << (M.allFinite() ? "" : " or rotation is not finite")
      << "; expected finite numbers within +-" << kMaxCoordinate_m << " m of the origin";
    throwInputError("frame " + std::to_string(frame_index) + " camera pose", s.str());
  }
  const RayScene::Impl& scene = m_scene.impl();
  const int w = m_K.width, h = m_K.height;
  out.intrinsics = m_K;
  out.index = frame_index;
  out.gt_T_world_cam = T_world_cam;
  out.depth_m.resize(w, h);
  out.colour.resize(w, h);
  m_z.resize(w, h);
  m_cos.resize(w, h);
  CastTargets targets{m_z.view(), m_cos.view(), out.colour.view(), {}, {}, m_params.labels};
  if (m_params.labels) {
    out.gt_instance.resize(w, h);
    out.gt_class.resize(w, h);
    targets.instance = out.gt_instance.view();
    targets.cls = out.gt_class.view();
  } else {
    out.gt_instance = Image<std::uint16_t>();
    out.gt_class = Image<std::uint16_t>();
  }

  CastSetup setup;
  setup.R = T_world_cam.linear().cast<float>();
  setup.o = T_world_cam.translation().cast<float>();
  setup.K = m_K.plain();
  setup.inv_fx = float(1.0 / m_K.fx);
  setup.inv_fy = float(1.0 / m_K.fy);
  setup.materials = scene.materials.data();
  setup.light.direction = scene.world.light.direction_world;
  setup.light.ambient = scene.world.light.ambient;
  setup.light.diffuse = scene.world.light.diffuse;
  setup.background = toBgr8(scene.world.background_rgb);
  using Clock = std::chrono::steady_clock;
  auto ms = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  const auto t0 = Clock::now();
  if (m_params.ray_packets)
    castPackets(scene.scene, setup, targets);
  else
    castSingle(scene.scene, setup, targets);

  const auto t1 = Clock::now();
  DepthMeasurementKernel k;
  k.z_exact = m_z.cview();
  k.cos_incidence = m_cos.cview();
  k.depth_out = out.depth_m.view();
  k.p = m_params.depthModel();
  k.dropouts = m_params.dropouts;
  k.rng.key = frameKey(seed, frame_index);
  if (m_params.dropouts && m_params.projector_offset_m != 0.0) {
    m_shadow.resize(w, h);
    compute::forEach1D(h, ProjectorShadowRows{m_z.cview(), m_shadow.view(),
                                              float(m_K.fx * m_params.projector_offset_m)});
    k.shadow = m_shadow.cview();
  }
  const auto t2 = Clock::now();
  compute::forEach1D(h, k);  // row version: vectorized noise draws
  const auto t3 = Clock::now();
  m_times.cast_ms = ms(t0, t1);
  m_times.shadow_ms = ms(t1, t2);
  m_times.depth_model_ms = ms(t2, t3);
}

}  // namespace rasm::sim
