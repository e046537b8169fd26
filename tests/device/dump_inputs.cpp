// Writes the real inputs of the device check (DeviceData.h) from a 7-Scenes sequence: maps frames
// 0 .. N-1 with the product's Mapper (default parameters, as `rasm run
// ini/7scenes_redkitchen.ini`), then dumps, for frame N, what the CUDA launchers take as input: the
// frame (raw and filtered depth, colour, vertex and normal maps), the model the tracker aligns it
// to (rendered as the Mapper does), the surfel map before the frame is fused, the visible lists of
// both renders, and the parameters; frame N is then processed by the Mapper and its results
// recorded as the CPU reference (pose, counts). Run by scripts/device-prepare.sh.
//
//   dump_inputs <7-Scenes folder> <out folder> [--frame N] [--extra-frames K] [--extra-step S]

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "DeviceData.h"
#include "rasm/core/FrameProcessing.h"
#include "rasm/io/SevenScenesFrameSource.h"
#include "rasm/pipeline/Mapper.h"
#include "rasm/pipeline/stages/FusionStages.h"
#include "rasm/pipeline/stages/PreprocessStage.h"
#include "rasm/pipeline/stages/TrackingStage.h"
#include "rasm/surfel_map/SurfelRenderer.h"

using namespace rasm;
using device::ElemType;

namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

void setPose(device::Meta& m, const std::string& key, const Eigen::Isometry3d& T) {
  double v[16];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) v[r * 4 + c] = T.matrix()(r, c);
  m.setValues(key, v, 16);
}

void setK(device::Meta& m, const std::string& key, const CameraIntrinsics& K) {
  const double v[6] = {K.fx, K.fy, K.cx, K.cy, double(K.width), double(K.height)};
  m.setValues(key, v, 6);
}

/// Dense copy of a pitched image.
template <typename T>
void writeImage(const std::string& path, ElemType type, const Image<T>& im) {
  std::vector<T> dense(std::size_t(im.width()) * im.height());
  for (int y = 0; y < im.height(); ++y)
    for (int x = 0; x < im.width(); ++x) dense[std::size_t(y) * im.width() + x] = im(x, y);
  device::writeBlob(path, type, dense.data(), dense.size(), im.width(), im.height());
}

int countValid(const Image<Vec3f>& v) {
  int n = 0;
  for (int y = 0; y < v.height(); ++y)
    for (int x = 0; x < v.width(); ++x) n += v(x, y).x() == v(x, y).x();
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: %s <7-Scenes folder> <out folder> [--frame N] [--extra-frames K] "
                 "[--extra-step S]\n",
                 argv[0]);
    return 2;
  }
  const std::string folder = argv[1], out = argv[2];
  int frame_n = 80, extra = 2, step = 20;
  for (int i = 3; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    const int v = std::atoi(argv[i + 1]);
    if (a == "--frame")
      frame_n = v;
    else if (a == "--extra-frames")
      extra = v;
    else if (a == "--extra-step")
      step = v;
    else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  try {
    std::filesystem::create_directories(out);
    io::SevenScenesFrameSource src(folder);
    pipeline::Mapper mapper;  // defaults = ini/7scenes_redkitchen.ini ([mapper] max_depth_m 4)
    const pipeline::TMapperParams& mp = mapper.mapperParams();
    const tracking::TTrackingParams& tp = mapper.stage<pipeline::TrackingStage>().params();
    const fusion::TFusionParams& fp = mapper.stage<pipeline::FusionStage>().params();

    std::optional<RgbdFrame> f;
    double t_first = 0.0;  // the Mapper's surfel times are relative to the first frame
    for (int i = 0; i < frame_n; ++i) {
      f = src.next();
      if (!f) throw std::runtime_error("sequence ends before frame " + std::to_string(frame_n));
      if (i == 0) t_first = f->timestamp_s;
      const pipeline::FrameResult r = mapper.processFrame(*f);
      if (i % 20 == 0)
        std::fprintf(stderr, "frame %d: %d surfels, tracked %d\n", i, mapper.map().store().size(),
                     int(r.tracked));
    }
    f = src.next();
    if (!f) throw std::runtime_error("sequence ends before frame " + std::to_string(frame_n));
    const RgbdFrame frame = *f;
    const CameraIntrinsics& K = frame.intrinsics;

    // ---- what the Mapper's tracking of frame N sees (Mapper::processFrame / renderModel) ----
    const Eigen::Isometry3d T_model = mapper.pose();  // no odometry: the last good pose
    const Eigen::Isometry3d T_guess =
        mapper.stage<pipeline::TrackingStage>().tracker().predictPose();
    const maps::SurfelStore before = mapper.map().store();  // the map before frame N is fused

    // ---- the product's frame N: pose, fusion counts (CPU reference) and its preprocessing ----
    const pipeline::FrameResult r = mapper.processFrame(frame);
    if (!r.tracked || !r.fused) throw std::runtime_error("frame N was not tracked and fused");
    const std::vector<FrameLevel> pyr = mapper.lastContext().pyramid;
    const Image<float>& filtered = pyr[0].depth_m;  // level 0 holds the filtered depth

    maps::SurfelRenderer renderer;
    maps::RenderOptions ro;
    ro.min_depth_m = float(mp.min_depth_m);
    ro.max_depth_m = float(mp.max_depth_m) * 1.5f;
    ro.stable_only = tp.model_min_confidence <= 0;
    ro.min_confidence = float(tp.model_min_confidence);
    ro.outputs = maps::kRenderVertex | maps::kRenderNormal | maps::kRenderDepth;
    const CameraIntrinsics K_model = K.level(tp.model_level);
    maps::RenderedMaps model;
    maps::RenderStats rs;
    renderer.render(before, T_model, K_model, ro, model, &rs);
    bool all_surfels = false;
    if (rs.pixels_drawn < 0.3 * countValid(pyr[tp.model_level].normal)) {
      ro.stable_only = false;
      ro.min_confidence = 0.0f;
      renderer.render(before, T_model, K_model, ro, model, &rs);
      all_surfels = true;
    }
    std::vector<int> model_visible;
    renderer.collectVisible(before, T_model, K_model, ro, ro.max_splat_radius_px, model_visible);

    if (r.model_valid_pixels != int(rs.pixels_drawn))
      throw std::runtime_error("the dumped model differs from the Mapper's (" +
                               std::to_string(rs.pixels_drawn) + " vs " +
                               std::to_string(r.model_valid_pixels) + " pixels)");
    const Eigen::Isometry3d T_wc = r.T_world_cam;

    // ---- fusion's 4x index map of frame N (SurfelFusion::integrate) ----
    maps::RenderOptions ro4;
    ro4.min_depth_m = fp.min_depth_m;
    ro4.max_depth_m =
        fp.max_depth_m * (1.0f + fp.assoc_max_depth_diff_rel) + fp.assoc_max_depth_diff_m;
    ro4.splat = false;
    std::vector<int> fuse_visible;
    renderer.collectVisible(before, T_wc, K, ro4, 0.5f, fuse_visible);

    // ---- extra frames: more depth images for the per-pixel kernels ----
    std::vector<Image<float>> extra_depth;
    pipeline::PreprocessStage pre;  // the Mapper's preprocessing, alone
    pre.configure(mp);
    for (int k = 1; k <= extra; ++k) {
      std::optional<RgbdFrame> g;
      for (int s = 0; s < step && (g = src.next()); ++s) {
      }
      if (!g) break;
      pipeline::FrameContext c;
      c.frame = &*g;
      pre.process(c, mapper.map());
      extra_depth.push_back(c.pyramid[0].depth_m);
    }

    // ---- write ----
    const std::string d = out + "/";
    writeImage(d + "frame0_depth_raw.bin", ElemType::F32, frame.depth_m);
    writeImage(d + "frame0_depth.bin", ElemType::F32, filtered);
    writeImage(d + "frame0_colour.bin", ElemType::Bgr8, frame.colour);
    writeImage(d + "frame0_vertex.bin", ElemType::Vec3f, pyr[0].vertex);
    writeImage(d + "frame0_normal.bin", ElemType::Vec3f, pyr[0].normal);
    for (std::size_t k = 0; k < extra_depth.size(); ++k)
      writeImage(d + "frame" + std::to_string(k + 1) + "_depth.bin", ElemType::F32, extra_depth[k]);
    writeImage(d + "model_index.bin", ElemType::I32, model.index);
    writeImage(d + "model_vertex.bin", ElemType::Vec3f, model.vertex_world);
    writeImage(d + "model_normal.bin", ElemType::Vec3f, model.normal_world);
    device::writeBlob(d + "model_visible.bin", ElemType::I32, model_visible.data(),
                      model_visible.size());
    device::writeBlob(d + "fuse_visible.bin", ElemType::I32, fuse_visible.data(),
                      fuse_visible.size());
    const maps::SurfelArrays a = before.arrays();
    const std::uint64_t n = std::uint64_t(a.size);
    device::writeBlob(d + "map_pos_conf.bin", ElemType::Vec4f, a.pos_conf, n);
    device::writeBlob(d + "map_normal_radius.bin", ElemType::Vec4f, a.normal_radius, n);
    device::writeBlob(d + "map_colour_flags.bin", ElemType::U32, a.colour_flags, n);
    device::writeBlob(d + "map_t_last.bin", ElemType::F32, a.t_last, n);
    device::writeBlob(d + "map_basis.bin", ElemType::Vec3f, a.basis, n);
    device::writeBlob(d + "map_segment.bin", ElemType::U32, a.segment, n);
    device::writeBlob(d + "map_segment_w.bin", ElemType::F32, a.segment_w, n);
    device::writeBlob(d + "map_view_ic.bin", ElemType::U8, a.view_ic, n * a.n_view_bins);

    device::Meta m;
    m.set("sequence", folder);
    m.set("frame_index", double(frame_n));
    m.set("extra_frames", double(extra_depth.size()));
    m.set("extra_step", double(step));
    for (int l = 0; l < 3; ++l) setK(m, "K_level" + std::to_string(l), K.level(l));
    setPose(m, "T_world_model", T_model);
    setPose(m, "T_world_cam_guess", T_guess);
    setPose(m, "T_world_cam", T_wc);
    // [mapper]
    m.set("mapper.min_depth_m", mp.min_depth_m);
    m.set("mapper.max_depth_m", mp.max_depth_m);
    m.set("mapper.normal_max_jump_rel", mp.normal_max_jump_rel);
    m.set("mapper.pyramid_levels", double(mp.pyramid_levels));
    m.set("mapper.bilateral_filter", double(mp.bilateral_filter));
    m.set("mapper.bilateral_sigma_space_px", mp.bilateral_sigma_space_px);
    m.set("mapper.bilateral_sigma_depth_m", mp.bilateral_sigma_depth_m);
    // [tracking]
    m.set("tracking.num_levels", double(tp.num_levels));
    {
      double it[3], md[3], na[3];
      for (int l = 0; l < 3; ++l) {
        it[l] = tp.iterations[l];
        md[l] = tp.max_dist_m[l];
        na[l] = tp.max_normal_angle_deg[l];
      }
      m.setValues("tracking.iterations", it, 3);
      m.setValues("tracking.max_dist_m", md, 3);
      m.setValues("tracking.max_normal_angle_deg", na, 3);
    }
    m.set("tracking.level0_pixel_stride", double(tp.level0_pixel_stride));
    m.set("tracking.huber_delta_m", tp.huber_delta_m);
    m.set("tracking.depth_noise_weighting", double(tp.depth_noise_weighting));
    m.set("tracking.model_level", double(tp.model_level));
    m.set("tracking.convergence_translation_m", tp.convergence_translation_m);
    m.set("tracking.convergence_rotation_deg", tp.convergence_rotation_deg);
    // model render (Mapper::renderModel)
    m.set("model.min_depth_m", ro.min_depth_m);
    m.set("model.max_depth_m", ro.max_depth_m);
    m.set("model.stable_only", double(ro.stable_only));
    m.set("model.min_confidence", ro.min_confidence);
    m.set("model.max_splat_radius_px", ro.max_splat_radius_px);
    m.set("model.all_surfels", double(all_surfels));
    m.set("model.pixels_drawn", double(rs.pixels_drawn));
    // fusion: the kernels' plain parameters (SurfelFusion.cpp plainParams) and the 4x render
    const maps::SurfelStoreOptions& lay = before.options();
    m.set("fusion.sigma", fp.confidence_sigma);
    m.set("fusion.min_depth_m", fp.min_depth_m);
    m.set("fusion.max_depth_m", fp.max_depth_m);
    m.set("fusion.min_cos_incidence", std::cos(fp.max_incidence_deg * float(kDegToRad)));
    m.set("fusion.assoc_dz_abs_m", fp.assoc_max_depth_diff_m);
    m.set("fusion.assoc_dz_rel", fp.assoc_max_depth_diff_rel);
    m.set("fusion.min_cos_normal", std::cos(fp.assoc_max_normal_angle_deg * float(kDegToRad)));
    m.set("fusion.radius_update_ratio", fp.radius_update_ratio);
    m.set("fusion.neighbour_coverage_check", double(fp.neighbour_coverage_check));
    m.set("fusion.stable_confidence", fp.stable_confidence);
    m.set("fusion.max_confidence", fp.max_confidence);
    m.set("fusion.update_segments", double(fp.update_segments));
    m.set("fusion.update_view_bins", double(fp.update_view_bins && lay.nViewBins() > 0));
    m.set("fusion.ic_lambda1", fp.ic_lambda1);
    m.set("fusion.ic_d_min_m", fp.ic_d_min_m);
    m.set("fusion.index4x_min_depth_m", ro4.min_depth_m);
    m.set("fusion.index4x_max_depth_m", ro4.max_depth_m);
    m.set("fusion.now_map_s", before.toMapTime(frame.timestamp_s - t_first));
    // map layout
    m.set("map.surfels", double(a.size));
    m.set("map.n_view_bins", double(a.n_view_bins));
    m.set("map.view_bins_azimuth", double(lay.view_bins_azimuth));
    m.set("map.view_bins_elevation", double(lay.view_bins_elevation));
    m.set("map.block_size_m", lay.block_size_m);
    // the product's results for frame N (CPU, SSE launchers)
    m.set("product.icp_iterations", double(r.tracking.iterations));
    m.set("product.icp_inliers", double(r.tracking.inliers));
    m.set("product.fusion_valid_pixels", double(r.fusion.valid_pixels));
    m.set("product.fusion_associated", double(r.fusion.associated));
    m.set("product.fusion_fused", double(r.fusion.fused));
    m.set("product.fusion_covered", double(r.fusion.covered));
    m.set("product.fusion_became_stable", double(r.fusion.became_stable));
    m.set("product.fusion_added", double(r.fusion.added));
    m.set("product.fusion_resorted", double(r.fusion.resorted));
    m.write(d + "meta.txt", "rasm device-check inputs (tests/device/DeviceData.h), dump_inputs");
    std::fprintf(stderr, "frame %d: %d surfels, model %lld pixels (%zu visible), 4x %zu visible\n",
                 frame_n, a.size, rs.pixels_drawn, model_visible.size(), fuse_visible.size());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dump_inputs: %s\n", e.what());
    return 1;
  }
}
