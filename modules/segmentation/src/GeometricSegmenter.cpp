#include "rasm/segmentation/GeometricSegmenter.h"

#include <chrono>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "rasm/compute/Parallel.h"
#include "rasm/core/Error.h"
#include "rasm/core/Timing.h"
#include "rasm/segmentation/kernels/EdgeKernels.h"

namespace rasm::segmentation {

namespace {

template <typename T>
cv::Mat matOf(Image<T>& im, int type) {
  return cv::Mat(im.height(), im.width(), type, im.data(), im.pitchBytes());
}

/// The paper's first change: the normal map bilateral-filtered before the edge test (invalid
/// normals enter as 0 and stay invalid; filtered normals are renormalised).
void filterNormals(const Image<Vec3f>& in, Image<Vec3f>& out, const TSegmentationParams& p) {
  const int w = in.width(), h = in.height();
  out.resize(w, h);
  if (p.normal_filter_diameter_px <= 0) {
    out = in;
    return;
  }
  Image<Vec3f> zeroed(w, h);
  compute::forEach1D(h, [&](int y) {
    const Vec3f* a = in.row(y);
    Vec3f* b = zeroed.row(y);
    for (int x = 0; x < w; ++x) b[x] = std::isnan(a[x].x()) ? Vec3f::Zero() : a[x];
  });
  cv::Mat src = matOf(zeroed, CV_32FC3), dst = matOf(out, CV_32FC3);
  cv::bilateralFilter(src, dst, p.normal_filter_diameter_px, p.normal_filter_sigma,
                      p.normal_filter_sigma_space_px);
  compute::forEach1D(h, [&](int y) {
    const Vec3f* a = in.row(y);
    Vec3f* b = out.row(y);
    for (int x = 0; x < w; ++x) {
      const float n = b[x].norm();
      b[x] = (std::isnan(a[x].x()) || n < 1e-6f) ? a[x] : Vec3f(b[x] / n);
    }
  });
}
/// Valid edge pixels take the label of the adjacent labelled pixel nearest in depth (within the
/// depth-jump gate), edge_fill_iterations times: surfels on an object's border then belong to it
/// rather than to no segment, and a depth edge's far side never takes the near side's label.
void fillEdges(cv::Mat& labels, const Image<Vec3f>& vertex, const TSegmentationParams& p) {
  const int w = labels.cols, h = labels.rows;
  cv::Mat next;
  for (int it = 0; it < p.edge_fill_iterations; ++it) {
    labels.copyTo(next);
    int filled = 0;
    for (int y = 0; y < h; ++y) {
      const Vec3f* v = vertex.row(y);
      int* out = next.ptr<int>(y);
      for (int x = 0; x < w; ++x) {
        if (out[x] != 0 || std::isnan(v[x].x())) continue;
        const float z = v[x].z();
        const float gate = float(p.depth_jump_m + p.depth_jump_per_z2 * z * z);
        float best = gate;
        int label = 0;
        const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
        for (int k = 0; k < 4; ++k) {
          const int xi = x + dx[k], yi = y + dy[k];
          if (xi < 0 || yi < 0 || xi >= w || yi >= h) continue;
          const int l = labels.ptr<int>(yi)[xi];
          if (!l) continue;
          const float d = std::fabs(vertex(xi, yi).z() - z);
          if (d < best) {
            best = d;
            label = l;
          }
        }
        if (label) {
          out[x] = label;
          ++filled;
        }
      }
    }
    std::swap(labels, next);
    if (!filled) break;
  }
}

}  // namespace

void GeometricSegmenter::addColourEdges(const Image<std::uint8_t>& intensity,
                                        const Image<Vec3f>& vertex_cam, cv::Mat& is_edge) const {
  if (!intensity.sameSize(vertex_cam))
    throwInputError("GeometricSegmenter intensity",
                    std::to_string(intensity.width()) + "x" + std::to_string(intensity.height()) +
                        ", expected the maps' " + std::to_string(vertex_cam.width()) + "x" +
                        std::to_string(vertex_cam.height()));
  const cv::Mat grey(intensity.height(), intensity.width(), CV_8UC1,
                     const_cast<std::uint8_t*>(intensity.data()), intensity.pitchBytes());
  cv::Mat canny;
  cv::Canny(grey, canny, m_params.colour_edge_low, m_params.colour_edge_high, 3, true);
  const float max_z = float(m_params.colour_edge_max_depth_m);
  compute::forEach1D(canny.rows, [&](int y) {
    const std::uint8_t* c = canny.ptr<std::uint8_t>(y);
    const Vec3f* v = vertex_cam.row(y);
    std::uint8_t* e = is_edge.ptr<std::uint8_t>(y);
    for (int x = 0; x < canny.cols; ++x)
      if (c[x] && v[x].z() < max_z) e[x] = 255;  // (NaN depth: already invalid)
  });
}

const FrameSegments& GeometricSegmenter::segment(const Image<Vec3f>& vertex_cam,
                                                 const Image<Vec3f>& normal_cam, int out_width,
                                                 int out_height,
                                                 const Image<std::uint8_t>* intensity) {
  const int w = vertex_cam.width(), h = vertex_cam.height();
  const int ow = out_width > 0 ? out_width : w, oh = out_height > 0 ? out_height : h;
  const int scale = w > 0 ? ow / w : 1;
  if (w <= 0 || h <= 0 || scale < 1 || ow != scale * w || oh != scale * h)
    throwInputError("GeometricSegmenter output size",
                    std::to_string(ow) + "x" + std::to_string(oh) +
                        " is not an integer multiple of the maps' " + std::to_string(w) + "x" +
                        std::to_string(h));
  if (!normal_cam.sameSize(vertex_cam))
    throwInputError("GeometricSegmenter input",
                    "normal map is " + std::to_string(normal_cam.width()) + "x" +
                        std::to_string(normal_cam.height()) + ", vertex map " + std::to_string(w) +
                        "x" + std::to_string(h));
  FrameSegments& o = m_out;
  auto t = Clock::now();
  filterNormals(normal_cam, m_normal_filtered, m_params);
  o.ms_normals = msSince(t);

  t = Clock::now();
  o.edges.resize(w, h);
  kernels::EdgeKernel k;
  k.vertex = vertex_cam.cview();
  k.normal = m_normal_filtered.cview();
  k.edge = o.edges.view();
  k.prm.min_concavity = float(m_params.concavity_threshold);
  k.prm.gamma_abs_m = float(m_params.depth_jump_m);
  k.prm.gamma_per_z2 = float(m_params.depth_jump_per_z2);
  k.prm.concave_margin_per_z2 = float(m_params.concave_margin_per_z2);
  k.prm.step = m_params.neighbour_step_px;
  k.prm.reach = std::max(m_params.neighbour_reach_px, m_params.neighbour_step_px);
  compute::forEach2D(w, h, k);
  // Morphology on the edge pixels (the paper's third change): closing bridges gaps in edge lines
  // (a one-pixel gap would join two segments), opening removes speckle but also edges thinner
  // than the element, so it is off by default (docs/segmentation.md).
  cv::Mat edges = matOf(o.edges, CV_8UC1);
  cv::Mat is_edge = edges != kernels::kInterior;  // 255 for edge or invalid
  if (m_params.colour_edges && intensity) addColourEdges(*intensity, vertex_cam, is_edge);
  const cv::Mat element = cv::getStructuringElement(cv::MORPH_CROSS, cv::Size(3, 3));
  if (m_params.morphology_close_iterations > 0)
    cv::morphologyEx(is_edge, is_edge, cv::MORPH_CLOSE, element, cv::Point(-1, -1),
                     m_params.morphology_close_iterations);
  if (m_params.morphology_open_iterations > 0)
    cv::morphologyEx(is_edge, is_edge, cv::MORPH_OPEN, element, cv::Point(-1, -1),
                     m_params.morphology_open_iterations);
  // Invalid pixels stay out of every segment whatever the morphology did.
  cv::Mat interior = (is_edge == 0) & (edges != kernels::kInvalid);
  edges.setTo(kernels::kEdge, (interior == 0) & (edges != kernels::kInvalid));
  edges.setTo(kernels::kInterior, interior);
  o.ms_edges = msSince(t);

  // Connected components of the interior (4-connected: a diagonal step does not cross an edge).
  t = Clock::now();
  cv::Mat cc_labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(interior, cc_labels, stats, centroids, 4, CV_32S);
  // Minimum size at 640x480, scaled with the image area.
  const int min_px =
      std::max(1, int(std::lround(m_params.min_component_px * (double(w) * h) / (640.0 * 480.0))));
  const int area_scale = scale * scale;
  std::vector<std::uint32_t> relabel(std::size_t(std::max(n, 1)), 0u);
  o.dropped_components = 0;
  std::uint32_t next = 1;
  for (int c = 1; c < n; ++c) {
    const int area = stats.at<int>(c, cv::CC_STAT_AREA);
    if (area < min_px) {
      ++o.dropped_components;
      continue;
    }
    relabel[c] = next++;
  }
  o.count = int(next) - 1;
  for (int y = 0; y < h; ++y) {
    int* a = cc_labels.ptr<int>(y);
    for (int x = 0; x < w; ++x) a[x] = int(relabel[a[x]]);
  }
  fillEdges(cc_labels, vertex_cam, m_params);
  o.labels.resize(ow, oh);
  compute::forEach1D(oh, [&](int y) {
    const int* a = cc_labels.ptr<int>(y / scale);
    std::uint32_t* b = o.labels.row(y);
    for (int x = 0; x < ow; ++x) b[x] = std::uint32_t(a[x / scale]);
  });
  o.pixels.assign(std::size_t(o.count) + 1, 0);
  for (int y = 0; y < h; ++y) {
    const int* a = cc_labels.ptr<int>(y);
    for (int x = 0; x < w; ++x) o.pixels[std::size_t(a[x])] += area_scale;
  }
  o.pixels[0] = 0;
  o.ms_components = msSince(t);
  return o;
}

}  // namespace rasm::segmentation
