#pragma once
// The per-frame half of section III: the edge map E_t of the frame's vertex and (bilateral-
// filtered) normal maps, its morphological clean-up, and the connected components of the
// non-edge pixels, which are the frame's segments L_t (EdgeKernels.h for the edge test).
//
//   GeometricSegmenter seg(params);
//   const FrameSegments& s = seg.segment(vertex_cam, normal_cam);   // s.labels = L_t
//
// With TSegmentationParams::colour_edges, the intensity's Canny edges join E_t where the pixel
// has depth within colour_edge_max_depth_m (surfaces that geometry cannot tell apart).

#include <cstdint>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "rasm/compute/Types.h"
#include "rasm/core/Image.h"
#include "rasm/segmentation/TSegmentationParams.h"

namespace rasm::segmentation {

/// L_t and what it was made from.
struct FrameSegments {
  Image<std::uint8_t> edges;    ///< E_t after the morphology (kernels::kInterior/kEdge/kInvalid),
                                ///< at the resolution of the input maps
  Image<std::uint32_t> labels;  ///< L_t at the output resolution: 1..count (edge pixels filled
                                ///< from the adjacent segment nearest in depth), 0 = invalid,
                                ///< unfilled edge or too small a component
  int count = 0;                ///< segments in L_t
  std::vector<int> pixels;      ///< pixels per label in `labels` (index = label; [0] unused)
  int dropped_components = 0;   ///< components below min_component_px
  // Milliseconds of the steps (report.json / frames.csv; tests never assert on them).
  double ms_normals = 0, ms_edges = 0, ms_components = 0;
};

class GeometricSegmenter {
 public:
  explicit GeometricSegmenter(const TSegmentationParams& params = {}) : m_params(params) {}
  const TSegmentationParams& params() const { return m_params; }
  void setParams(const TSegmentationParams& p) { m_params = p; }

  /// Segments one frame (V_t, N_t in the camera frame, the same size; invalid = x NaN), the
  /// labels upsampled (nearest) to out_width x out_height, an integer multiple of the maps' size
  /// (0 = the maps' size). Throws InputError when the sizes do not fit.
  /// `intensity` (optional, the maps' size, 8-bit grey): the frame's colour for the colour edges
  /// (TSegmentationParams::colour_edges); ignored when they are off.
  const FrameSegments& segment(const Image<Vec3f>& vertex_cam, const Image<Vec3f>& normal_cam,
                               int out_width = 0, int out_height = 0,
                               const Image<std::uint8_t>* intensity = nullptr);
  const FrameSegments& last() const { return m_out; }

 private:
  /// is_edge (255 = edge or invalid, the maps' size) |= the intensity's Canny edges with depth
  /// nearer than colour_edge_max_depth_m.
  void addColourEdges(const Image<std::uint8_t>& intensity, const Image<Vec3f>& vertex_cam,
                      cv::Mat& is_edge) const;
  TSegmentationParams m_params;
  Image<Vec3f> m_normal_filtered;
  FrameSegments m_out;
};

}  // namespace rasm::segmentation
