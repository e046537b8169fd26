#pragma once
// The edge map E_t of section III (Tateno et al. 2015, with the paper's extended neighbourhood),
// one frame pixel per call, written once for both backends (plain header: compute/ and Eigen).
//
// For a pixel u with vertex v and unit normal n (camera frame; normals face the camera, n . v < 0)
// and each neighbour u_i with v_i, n_i:
//   Gamma(u) = max_i |(v_i - v) . n|                        maximum point-to-plane distance
//   Phi_i(u) = 1 if (v_i - v) . n <= m(z) (v_i lies behind the tangent plane: convex, or within
//              the noise margin m(z) in front of it), else n_i . n
//   Phi(u)   = min_i Phi_i(u)                                concavity
//   E(u)     = Phi(u) < delta_Phi || Gamma(u) > delta_Gamma(z)
// (The paper's case test reads "> 0" for its own normal orientation; with normals facing the
// camera, a neighbour in front of the tangent plane is the concave case.)
// Neighbourhood: the 8 pixels at distance `step` (1 = adjacent) that are valid, and in each
// cardinal direction the first valid pixel beyond an invalid one, up to `reach` pixels away (the
// paper's extension: holes of missing depth do not hide an edge). delta_Gamma(z) = gamma_abs_m +
// gamma_per_z2 * z^2 grows with the depth noise. Invalid pixels (no vertex or normal) are edges:
// they belong to no segment.

#include <cstdint>

#include "rasm/compute/ImageView.h"
#include "rasm/compute/Types.h"

namespace rasm::segmentation::kernels {

struct EdgeParams {
  float min_concavity = 0.95f;  ///< delta_Phi
  float gamma_abs_m = 0.01f;
  float gamma_per_z2 = 0.01f;
  /// A neighbour counts as concave only when it lies in front of the tangent plane by more than
  /// concave_margin_per_z2 * z^2 (m): depth noise and quantization, which grow with z^2, put half
  /// of the neighbours of a flat surface slightly in front of it.
  float concave_margin_per_z2 = 0.0f;
  /// Distance (px) of the 8 neighbours: > 1 measures folds over a longer baseline, where a real
  /// fold's offset from the tangent plane grows with the distance and the noise does not.
  int step = 1;
  int reach = 4;
};

/// Edge pixel values.
enum : std::uint8_t { kInterior = 0, kEdge = 1, kInvalid = 2 };

struct EdgeKernel {
  ImageView<const Vec3f> vertex;  ///< V_t, camera frame (invalid: x = NaN)
  ImageView<const Vec3f> normal;  ///< N_t (filtered), unit, camera frame (invalid: x = NaN)
  ImageView<std::uint8_t> edge;   ///< out: kInterior / kEdge / kInvalid
  ImageView<float> gamma;         ///< optional out: Gamma(u) (empty = not written)
  ImageView<float> phi;           ///< optional out: Phi(u)
  EdgeParams prm;

  RASM_HD_INLINE static bool valid(const Vec3f& v) { return v.x() == v.x(); }

  RASM_HD_INLINE void accumulate(const Vec3f& v, const Vec3f& n, int xi, int yi, float margin,
                                 float& g, float& p) const {
    const Vec3f vi = vertex(xi, yi), ni = normal(xi, yi);
    const float d = (vi - v).dot(n);
    const float ad = d < 0.0f ? -d : d;
    if (ad > g) g = ad;
    const float pi = d <= margin ? 1.0f : ni.dot(n);
    if (pi < p) p = pi;
  }

  RASM_HD_INLINE void operator()(int x, int y) const {
    const Vec3f v = vertex(x, y), n = normal(x, y);
    if (!valid(v) || !valid(n)) {
      edge(x, y) = kInvalid;
      if (!gamma.empty()) gamma(x, y) = 0.0f;
      if (!phi.empty()) phi(x, y) = 1.0f;
      return;
    }
    float g = 0.0f, p = 1.0f;
    const float margin = prm.concave_margin_per_z2 * v.z() * v.z();
    // The 8 neighbours at distance step; away from the border no bounds checks.
    const int st = prm.step, far = st > prm.reach ? st : prm.reach;
    const bool inner = x >= far && y >= far && x < vertex.width - far && y < vertex.height - far;
    for (int dy = -st; dy <= st; dy += st)
      for (int dx = -st; dx <= st; dx += st) {
        if (dx == 0 && dy == 0) continue;
        const int xi = x + dx, yi = y + dy;
        if (!inner && !vertex.inside(xi, yi)) continue;
        if (valid(vertex(xi, yi)) && valid(normal(xi, yi))) accumulate(v, n, xi, yi, margin, g, p);
      }
    // Cardinal directions: the first valid pixel beyond an invalid adjacent one.
    const int cdx[4] = {1, -1, 0, 0}, cdy[4] = {0, 0, 1, -1};
    for (int k = 0; k < 4; ++k) {
      const int ax = x + st * cdx[k], ay = y + st * cdy[k];
      if ((!inner && !vertex.inside(ax, ay)) || (valid(vertex(ax, ay)) && valid(normal(ax, ay))))
        continue;
      for (int r = st + 1; r <= prm.reach; ++r) {
        const int xi = x + r * cdx[k], yi = y + r * cdy[k];
        if (!inner && !vertex.inside(xi, yi)) break;
        if (valid(vertex(xi, yi)) && valid(normal(xi, yi))) {
          accumulate(v, n, xi, yi, margin, g, p);
          break;
        }
      }
    }
    const float z = v.z();
    const bool e = p < prm.min_concavity || g > prm.gamma_abs_m + prm.gamma_per_z2 * z * z;
    edge(x, y) = e ? kEdge : kInterior;
    if (!gamma.empty()) gamma(x, y) = g;
    if (!phi.empty()) phi(x, y) = p;
  }
};

}  // namespace rasm::segmentation::kernels
