// The per-frame half of section III on analytic depth images: the edge map fires on depth edges
// and concave folds and not on flat or convex surfaces; connected components separate objects.
#include "rasm/segmentation/GeometricSegmenter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "rasm/core/Error.h"
#include "rasm/core/FrameProcessing.h"
#include "rasm/segmentation/kernels/EdgeKernels.h"

using namespace rasm;
using namespace rasm::segmentation;

namespace {

const CameraIntrinsics kK(525.0, 525.0, 319.5, 239.5, 640, 480);

/// Ray parameter t of the nearest hit along camera ray d (camera frame, d.z = 1, so t is the depth)
/// or +inf.
using Scene = std::function<double(const Eigen::Vector3d& d)>;

double plane(const Eigen::Vector3d& d, const Eigen::Vector3d& n, double offset) {
  // n . (t d) = offset
  const double nd = n.dot(d);
  if (std::abs(nd) < 1e-12) return INFINITY;
  const double t = offset / nd;
  return t > 0 ? t : INFINITY;
}

double box(const Eigen::Vector3d& d, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  double t0 = 0.0, t1 = INFINITY;
  for (int a = 0; a < 3; ++a) {
    double ta = lo[a] / d[a], tb = hi[a] / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1 && t0 > 0 ? t0 : INFINITY;
}

/// Vertical cylinder (axis along camera y) at (cx, cz), radius r.
double cylinder(const Eigen::Vector3d& d, double cx, double cz, double r) {
  const double a = d.x() * d.x() + d.z() * d.z(), b = -2 * (d.x() * cx + d.z() * cz),
               c = cx * cx + cz * cz - r * r;
  const double disc = b * b - 4 * a * c;
  if (disc < 0) return INFINITY;
  const double t = (-b - std::sqrt(disc)) / (2 * a);
  return t > 0 ? t : INFINITY;
}

struct Frame {
  Image<float> depth;
  Image<Vec3f> vertex, normal;
};

Frame render(const Scene& scene) {
  Frame f;
  f.depth.resize(kK.width, kK.height);
  for (int y = 0; y < kK.height; ++y)
    for (int x = 0; x < kK.width; ++x) {
      const double t = scene(Eigen::Vector3d((x - kK.cx) / kK.fx, (y - kK.cy) / kK.fy, 1.0));
      f.depth(x, y) = std::isfinite(t) && t < 6.0 ? float(t) : 0.0f;
    }
  computeVertexMap(f.depth, kK, f.vertex);
  computeNormalMap(f.vertex, f.normal);
  return f;
}

double minOf(double a, double b) {
  return std::min(a, b);
}

/// Fraction of edge pixels among the valid ones in a window.
double edgeFraction(const FrameSegments& s, int x0, int y0, int x1, int y1) {
  int e = 0, n = 0;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      if (s.edges(x, y) == kernels::kInvalid) continue;
      ++n;
      e += s.edges(x, y) == kernels::kEdge;
    }
  return n ? double(e) / n : 0.0;
}

}  // namespace

TEST(EdgeMap, FlatWallHasNoEdges) {
  const Frame f = render([](const Eigen::Vector3d& d) {
    return plane(d, Eigen::Vector3d(0.3, 0, 1).normalized(), 2.0);
  });
  GeometricSegmenter seg;
  const FrameSegments& s = seg.segment(f.vertex, f.normal);
  EXPECT_LT(edgeFraction(s, 5, 5, 634, 474), 0.001);
  EXPECT_EQ(s.count, 1);
}

TEST(EdgeMap, ConvexCylinderHasNoEdgesInside) {
  // A cylinder of radius 0.3 m at 1.5 m in front of a wall at 3 m: its silhouette is a depth edge,
  // its convex surface is not.
  const Frame f = render([](const Eigen::Vector3d& d) {
    return minOf(cylinder(d, 0.0, 1.5, 0.3), plane(d, Eigen::Vector3d(0, 0, 1), 3.0));
  });
  GeometricSegmenter seg;
  const FrameSegments& s = seg.segment(f.vertex, f.normal);
  // The cylinder spans |x| < 0.3 / 1.5 * 525 = 105 px around the centre; its inner 70%.
  EXPECT_LT(edgeFraction(s, 320 - 70, 100, 320 + 70, 380), 0.005);
  // The silhouette columns at about +/-105 px from the centre fire.
  EXPECT_GT(edgeFraction(s, 320 + 100, 200, 320 + 112, 280), 0.15);
  EXPECT_GE(s.count, 2) << "cylinder and wall are separate segments";
  EXPECT_NE(s.labels(320, 240), s.labels(40, 240));
}

TEST(EdgeMap, ConcaveCornerAndBoxOnTableFire) {
  // Room corner: wall z = 2.5 and side wall x = 0.6 meet in a concave fold at x = 0.6.
  const Frame corner = render([](const Eigen::Vector3d& d) {
    return minOf(plane(d, Eigen::Vector3d(0, 0, 1), 2.5), plane(d, Eigen::Vector3d(1, 0, 0), 0.6));
  });
  GeometricSegmenter seg;
  FrameSegments s = seg.segment(corner.vertex, corner.normal);
  const int fold_x = int(std::lround(kK.cx + 0.6 / 2.5 * kK.fx));  // 445
  EXPECT_GT(edgeFraction(s, fold_x - 2, 100, fold_x + 2, 380), 0.3) << "the concave fold";
  EXPECT_LT(edgeFraction(s, 100, 100, fold_x - 20, 380), 0.005) << "the wall beside it";
  EXPECT_NE(s.labels(200, 240), s.labels(600, 240));

  // A box (0.4 x 0.2 x 0.3 m) standing on a table top (plane y = 0.4 below the camera), seen from
  // 1.5 m: the box meets the table in a concave fold, its top edge is a depth edge to the table.
  const Frame table = render([](const Eigen::Vector3d& d) {
    return minOf(box(d, Eigen::Vector3d(-0.2, 0.2, 1.4), Eigen::Vector3d(0.2, 0.4, 1.7)),
                 plane(d, Eigen::Vector3d(0, -1, 0), -0.4));
  });
  s = seg.segment(table.vertex, table.normal);
  const int bottom_y = int(std::lround(kK.cy + 0.4 / 1.4 * kK.fy));  // the front-bottom edge
  EXPECT_GT(edgeFraction(s, 300, bottom_y - 2, 340, bottom_y + 2), 0.3);
  const std::uint32_t on_box = s.labels(320, int(kK.cy + 0.3 / 1.4 * kK.fy));
  const std::uint32_t on_table = s.labels(320, bottom_y + 30);
  EXPECT_NE(on_box, 0u);
  EXPECT_NE(on_table, 0u);
  EXPECT_NE(on_box, on_table);
}

TEST(Components, TwoBoxesSideBySideAreTwoLabels) {
  // Two boxes 4 cm apart in front of a wall.
  const Frame f = render([](const Eigen::Vector3d& d) {
    return minOf(minOf(box(d, Eigen::Vector3d(-0.42, -0.2, 1.5), Eigen::Vector3d(-0.02, 0.2, 1.9)),
                       box(d, Eigen::Vector3d(0.02, -0.2, 1.5), Eigen::Vector3d(0.42, 0.2, 1.9))),
                 plane(d, Eigen::Vector3d(0, 0, 1), 3.0));
  });
  GeometricSegmenter seg;
  const FrameSegments& s = seg.segment(f.vertex, f.normal);
  const std::uint32_t a = s.labels(int(kK.cx - 0.22 / 1.5 * kK.fx), 240);
  const std::uint32_t b = s.labels(int(kK.cx + 0.22 / 1.5 * kK.fx), 240);
  const std::uint32_t wall = s.labels(10, 10);
  EXPECT_NE(a, 0u);
  EXPECT_NE(b, 0u);
  EXPECT_NE(a, b);
  EXPECT_NE(a, wall);
  EXPECT_NE(b, wall);
  // Each box's front face is one segment: 0.4 x 0.4 m at 1.5 m ~ 140 x 140 px, less its border.
  EXPECT_GT(s.pixels[a], 100 * 100);
  EXPECT_GT(s.pixels[b], 100 * 100);
}

TEST(Components, SmallComponentsAreDropped) {
  TSegmentationParams p;
  p.min_component_px = 1000000;
  GeometricSegmenter seg(p);
  const Frame f =
      render([](const Eigen::Vector3d& d) { return plane(d, Eigen::Vector3d(0, 0, 1), 2.0); });
  const FrameSegments& s = seg.segment(f.vertex, f.normal);
  EXPECT_EQ(s.count, 0);
  EXPECT_EQ(s.dropped_components, 1);
  EXPECT_EQ(s.labels(320, 240), 0u);
}

namespace {
/// A wall's grey levels: 200 with a 60-grey rectangle (a sheet of paper on it: no depth) over
/// pixels [x0, x1) x [y0, y1), plus +-noise of a fixed pattern (texture).
Image<std::uint8_t> paperOnWall(int x0, int y0, int x1, int y1, int noise) {
  Image<std::uint8_t> g(kK.width, kK.height);
  for (int y = 0; y < kK.height; ++y)
    for (int x = 0; x < kK.width; ++x) {
      const int base = (x >= x0 && x < x1 && y >= y0 && y < y1) ? 60 : 200;
      const int n = noise ? ((x * 7919 + y * 104729) % (2 * noise + 1)) - noise : 0;
      g(x, y) = std::uint8_t(base + n);
    }
  return g;
}
}  // namespace

// Issue 41's thin objects: what lies flat on a surface (paper on a wall, a keyboard on a desk) has
// no depth edge and no fold; with colour edges its outline separates it, texture does not, and
// beyond colour_edge_max_depth_m the colour is not used.
TEST(Components, ColourEdgesSeparateWhatGeometryCannot) {
  const Frame f =
      render([](const Eigen::Vector3d& d) { return plane(d, Eigen::Vector3d(0, 0, 1), 2.0); });
  // 0.4 x 0.3 m of paper at 2 m: 105 x 79 px around the centre.
  const Image<std::uint8_t> grey = paperOnWall(268, 200, 373, 279, 10);
  TSegmentationParams p;
  p.level = 0;
  p.colour_edges = false;
  GeometricSegmenter plain(p);
  EXPECT_EQ(plain.segment(f.vertex, f.normal, 0, 0, &grey).count, 1) << "colour edges are off";
  p.colour_edges = true;
  GeometricSegmenter coloured(p);
  const FrameSegments& s = coloured.segment(f.vertex, f.normal, 0, 0, &grey);
  EXPECT_EQ(s.count, 2);
  const std::uint32_t paper = s.labels(320, 240), wall = s.labels(20, 20);
  EXPECT_NE(paper, 0u);
  EXPECT_NE(paper, wall);
  // The paper's segment is the paper: its area within the outline's pixel rings.
  EXPECT_NEAR(double(s.pixels[paper]), 105.0 * 79.0, 0.06 * 105 * 79);
  // Texture alone (+-10 grey levels) leaves the wall one segment.
  const Image<std::uint8_t> textured = paperOnWall(0, 0, 0, 0, 10);
  EXPECT_EQ(coloured.segment(f.vertex, f.normal, 0, 0, &textured).count, 1);
  // Beyond the depth limit the paper is not separated.
  p.colour_edge_max_depth_m = 1.5;
  GeometricSegmenter near_only(p);
  EXPECT_EQ(near_only.segment(f.vertex, f.normal, 0, 0, &grey).count, 1);
  // An intensity image of another size is named.
  Image<std::uint8_t> small(320, 240);
  EXPECT_THROW(coloured.segment(f.vertex, f.normal, 0, 0, &small), InputError);
}
