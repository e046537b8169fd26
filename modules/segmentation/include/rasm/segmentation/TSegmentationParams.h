#pragma once
// [segmentation]: the incremental geometric segmentation of section III (Tateno, Tombari & Navab,
// IROS 2015, with the paper's three changes). Defaults and how they were measured:
// docs/segmentation.md.

#include <mrpt/config/CLoadableOptions.h>

namespace rasm::segmentation {

struct TSegmentationParams : mrpt::config::CLoadableOptions {
  bool enabled = true;  ///< false: no segmentation stage work (surfels keep segment 0)

  /// Pyramid level the edge map and components are computed at (0 = full resolution, 1 = half):
  /// at level 1 the averaged depth gives normals quiet enough for the concavity test on
  /// Kinect-class noise, and it costs a quarter. L_t is upsampled to full resolution for label
  /// propagation and fusion.
  int level = 1;

  // ---- edge map E_t (III): E = Phi < delta_Phi || Gamma > delta_Gamma ----
  /// delta_Phi: concavity threshold on n_i . n (cos of the largest concave fold angle that still
  /// joins two surfaces; 0.95 ~ 18 deg).
  double concavity_threshold = 0.95;
  /// A neighbour is concave only when it lies in front of the tangent plane by more than
  /// concave_margin_per_z2 * z^2 (m; the depth noise scale), else it counts as convex.
  double concave_margin_per_z2 = 0.003;
  /// delta_Gamma(z) = depth_jump_m + depth_jump_per_z2 * z^2 (m): the largest point-to-plane
  /// distance to a neighbour that is not a depth edge; the z^2 term follows the depth noise of a
  /// Kinect-class sensor.
  double depth_jump_m = 0.01;
  double depth_jump_per_z2 = 0.01;
  /// The neighbourhood: the 8 pixels around, plus the first valid pixel in each cardinal direction
  /// up to this many pixels away (the paper's extension over holes).
  int neighbour_reach_px = 4;
  /// Distance of the 8 neighbours (px at the segmentation level; 1 = adjacent, Tateno's): a fold
  /// measured over 2 px stands out of the depth noise twice as far.
  int neighbour_step_px = 3;
  /// Bilateral filter of the normal map before the edge test (OpenCV bilateralFilter; the paper's
  /// first change): window diameter (px, 0 = off), range sigma (on normal components) and space
  /// sigma (px).
  int normal_filter_diameter_px = 5;
  double normal_filter_sigma = 0.2;
  double normal_filter_sigma_space_px = 2.0;
  /// Morphology of the edge map (3x3 cross; iterations, 0 = off), the paper's third change:
  /// closing bridges gaps in edge lines; opening removes speckle but also edges thinner than the
  /// element (which then no longer separate segments), so it is off by default.
  int morphology_close_iterations = 1;
  int morphology_open_iterations = 0;
  /// Colour edges (not in Tateno et al.; issue 41's thin objects): where depth and normals are
  /// flat, an object lying on another (a keyboard on a desk, books side by side) is separated
  /// only by its colour. Canny (OpenCV) on the frame's intensity at the segmentation level with
  /// hysteresis thresholds colour_edge_low / colour_edge_high (8-bit grey levels per Sobel 3x3
  /// gradient), kept only within colour_edge_max_depth_m (beyond, one pixel spans several cm
  /// and texture aliases into edges). Hand-held, on three simulated rooms and four nobody had
  /// looked at, the object list's precision rose on five of six and PQ stayed level or rose; on
  /// the exploring robot's runs the objects named right fell (the quick panel's eight, summed
  /// 2.46 -> 2.25) or stayed level (the default at 640x480), so it is off by default: turn it on
  /// for hand-held work. 40 / 100 split real textures too often (docs/segmentation.md "Colour
  /// edges").
  bool colour_edges = false;
  double colour_edge_low = 70.0;
  double colour_edge_high = 160.0;
  double colour_edge_max_depth_m = 2.5;

  // ---- connected components -> L_t ----
  /// Components smaller than this (pixels at 640x480, whatever the level; scaled with the image
  /// area) get label 0.
  int min_component_px = 200;
  /// Edge pixels with depth take the label of the adjacent segment nearest in depth (within
  /// delta_Gamma), this many pixel rings deep (at the segmentation level; 0 = edges stay 0): an
  /// object's border surfels then belong to it.
  int edge_fill_iterations = 3;

  // ---- label propagation -> L^p (III) ----
  /// A current segment takes the map label that covers the largest fraction of its pixels that
  /// have a map label, when that fraction is at least this and at least min_overlap_px pixels
  /// overlap; otherwise it gets a new label.
  double propagation_min_overlap = 0.3;
  int propagation_min_overlap_px = 50;
  /// A current segment whose best map label is mostly in another current segment of the frame
  /// (it holds less than this share of that label's pixels in view) and that lies within
  /// merge_max_depth_m gets a new label instead (0 = off): the map had joined it to its neighbour
  /// (an object first fused into the table's label from afar) and a near view separates them.
  /// Off by default: at 0.3 it recovered 2 / 1 / 0 more objects on office / cluttered_lab /
  /// office_robot_loop, but PQ fell by 0.005-0.015 (fragments of furniture) and label changes
  /// rose 2.5x (docs/segmentation.md, "Range-gated merging and the split rule").
  double split_max_share = 0.0;
  /// ... and when it has at least this many pixels with a map label (full-resolution pixels):
  /// smaller segments are mostly fragments of a surface, which would each mint a label.
  int split_min_px = 1500;
  /// A rendered surfel counts for a pixel when its depth is within this of the measurement
  /// (m, plus the relative part times z): the surfel fusion would associate.
  double render_depth_gate_m = 0.05;
  /// L^r and Pi are evaluated on every n-th pixel in x and y (2: a quarter of the pixels, as
  /// fine as L_t at level 1); pixel thresholds stay in full-resolution pixels.
  int propagation_step_px = 2;
  double render_depth_gate_rel = 0.03;

  // ---- merging with Psi (III) ----
  /// Map labels that fall into one current segment, each with at least this fraction of its
  /// labelled pixels, gain merge confidence.
  double merge_min_fraction = 0.15;
  /// ... and lie, on average over those pixels, no further than this (m; 0 = any range): beyond
  /// it the edge test's noise margins (which grow with z^2) hide the folds and steps between
  /// objects, so one current segment over two map labels is no evidence that they are one.
  double merge_max_depth_m = 2.5;
  /// Merge when Psi exceeds this (frames of evidence, net of the frames that contradict it).
  int merge_threshold = 8;
  /// Remap labels to fill unused ids (and refresh the segment statistics) every n frames.
  int remap_every_n_frames = 30;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

}  // namespace rasm::segmentation
