#include "rasm/sim/SurfaceCoverage.h"
#include "rasm/core/Angles.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "RaySceneImpl.h"
#include "rasm/core/CameraIntrinsics.h"
#include "rasm/models/ClassVocabulary.h"
#include "rasm/sim/OccupancyRaster.h"
#include "rasm/sim/SimulatedDiffDriveRobot.h"

namespace rasm::sim {

namespace {

using V3 = Eigen::Vector3f;

/// Lattice samples of one triangle (see the header); small triangles carry their area.
void sampleTriangle(const V3& a, const V3& b, const V3& c, float s, int object, float& carry,
                    std::vector<SurfaceCoverage::Sample>& out) {
  const V3 e0 = b - a, e1 = c - a;
  const V3 cr = e0.cross(e1);
  const float twice_area = cr.norm();
  const float L = e0.norm();
  if (!(twice_area > 0.f) || !(L > 0.f) || !std::isfinite(twice_area)) return;  // degenerate
  const float area = 0.5f * twice_area;
  const V3 n = cr / twice_area;
  const V3 u = e0 / L;
  const V3 w = n.cross(u);                     // in-plane, towards c
  const float cx = e1.dot(u), cy = e1.dot(w);  // c in (u, w); a = (0, 0), b = (L, 0)
  const std::size_t first = out.size();
  for (int j = 0;; ++j) {
    const float y = (float(j) + 0.5f) * s;
    if (y >= cy) break;
    const float t = y / cy;
    const float xl = cx * t, xr = L + (cx - L) * t;
    const int k0 = int(std::ceil(xl / s - 0.5f)), k1 = int(std::floor(xr / s - 0.5f));
    for (int k = k0; k <= k1; ++k) {
      const float x = (float(k) + 0.5f) * s;
      if (x < xl || x > xr) continue;
      SurfaceCoverage::Sample smp;
      smp.position = a + x * u + y * w;
      smp.normal = n;
      smp.object = object;
      out.push_back(smp);
    }
  }
  const std::size_t count = out.size() - first;
  if (count > 0) {
    for (std::size_t i = first; i < out.size(); ++i) out[i].area_m2 = area / float(count);
    return;
  }
  carry += area;
  if (carry >= s * s) {
    SurfaceCoverage::Sample smp;
    smp.position = (a + b + c) / 3.f;
    smp.normal = n;
    smp.object = object;
    smp.area_m2 = carry;
    out.push_back(smp);
    carry = 0.f;
  }
}

/// Robot positions: free grid cells of the largest 8-connected free component.
std::vector<Eigen::Vector2f> freePositions(const World& world, const CoverageOptions& o) {
  const Eigen::AlignedBox3f b = world.bounds();
  if (b.isEmpty()) return {};
  const float sp = float(o.position_spacing_m);
  const int nx = std::max(1, int(std::floor((b.max().x() - b.min().x()) / sp)));
  const int ny = std::max(1, int(std::floor((b.max().y() - b.min().y()) / sp)));
  // Centre the grid in the bounds.
  const Eigen::Vector2f org(b.min().x() + 0.5f * ((b.max().x() - b.min().x()) - sp * (nx - 1)),
                            b.min().y() + 0.5f * ((b.max().y() - b.min().y()) - sp * (ny - 1)));
  const OccupancyRaster raster(world, float(o.robot_z_min_m), float(o.robot_z_max_m),
                               float(o.raster_cell_m));
  std::vector<std::uint8_t> free(std::size_t(nx) * ny, 0);
#pragma omp parallel for schedule(static)
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix)
      free[std::size_t(iy) * nx + ix] = !raster.collidesDisc(
          org + sp * Eigen::Vector2f(float(ix), float(iy)), float(o.robot_radius_m));
  // Largest 8-connected component (the first found wins a tie).
  std::vector<int> label(free.size(), -1);
  int best = -1;
  std::size_t best_size = 0;
  std::vector<int> stack;
  for (std::size_t s = 0; s < free.size(); ++s) {
    if (!free[s] || label[s] >= 0) continue;
    const int l = int(s);
    std::size_t size = 0;
    stack.assign(1, int(s));
    label[s] = l;
    while (!stack.empty()) {
      const int c = stack.back();
      stack.pop_back();
      ++size;
      const int cx = c % nx, cy = c / nx;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = cx + dx, y = cy + dy;
          if (x < 0 || y < 0 || x >= nx || y >= ny) continue;
          const std::size_t k = std::size_t(y) * nx + x;
          if (free[k] && label[k] < 0) {
            label[k] = l;
            stack.push_back(int(k));
          }
        }
    }
    if (size > best_size) best_size = size, best = l;
  }
  std::vector<Eigen::Vector2f> out;
  for (std::size_t s = 0; s < free.size(); ++s)
    if (best >= 0 && label[s] == best)
      out.push_back(org + sp * Eigen::Vector2f(float(s % nx), float(s / nx)));
  return out;
}

/// Robot positions on a grid for ring-ordered lookups around a point.
struct PositionGrid {
  Eigen::Vector2f org = Eigen::Vector2f::Zero();
  float cell = 0.25f;
  int nx = 0, ny = 0;
  std::vector<std::vector<Eigen::Vector2f>> cells;

  PositionGrid(const std::vector<Eigen::Vector2f>& pts, float cell_m) : cell(cell_m) {
    if (pts.empty()) return;
    Eigen::Vector2f lo = pts[0], hi = pts[0];
    for (const auto& p : pts) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    org = lo - Eigen::Vector2f::Constant(0.5f * cell);
    nx = int(std::floor((hi.x() - org.x()) / cell)) + 1;
    ny = int(std::floor((hi.y() - org.y()) / cell)) + 1;
    cells.resize(std::size_t(nx) * ny);
    for (const auto& p : pts) {
      const int ix = std::clamp(int(std::floor((p.x() - org.x()) / cell)), 0, nx - 1);
      const int iy = std::clamp(int(std::floor((p.y() - org.y()) / cell)), 0, ny - 1);
      cells[std::size_t(iy) * nx + ix].push_back(p);
    }
  }
};

struct Visibility {
  const RayScene::Impl& scene;
  const CoverageOptions& o;
  const PositionGrid& grid;
  float tan_up = 0.f, tan_down = 0.f;  ///< tan of the elevation limits (pitch +/- fov / 2)
  float cos_inc = 0.f;
  float cos_pitch = 1.f, sin_pitch = 0.f;
  float cos_half_fov = 1.f;  ///< cos(vertical fov / 2)

  /// Whether the sample (p, n) is seen from some robot position.
  bool observable(const V3& p, const V3& n) const {
    if (grid.cells.empty()) return false;
    const float h = float(o.camera_height_m), fwd = float(o.camera_forward_m);
    const float rmin = float(o.min_range_m), rmax = float(o.max_range_m);
    const float dz = p.z() - h;
    // Within the field of view the depth is at least cos(fov / 2) x the distance.
    const float dmax = rmax / cos_half_fov;
    if (std::abs(dz) > dmax) return false;
    // Horizontal camera-to-sample distance allowed by the range and the elevation limits.
    float dh_max = std::sqrt(std::max(0.f, dmax * dmax - dz * dz));
    float dh_min = 0.f;
    const float elev_lo = float(std::atan(tan_down)), elev_hi = float(std::atan(tan_up));
    if (dz > 0.f) {
      if (elev_hi <= 0.f) return false;
      dh_min = dz / tan_up;
      if (elev_lo > 0.f) dh_max = std::min(dh_max, dz / tan_down);
    } else if (dz < 0.f) {
      if (elev_lo >= 0.f) return false;
      dh_min = -dz / -tan_down;
      if (elev_hi < 0.f) dh_max = std::min(dh_max, -dz / -tan_up);
    }
    if (dh_min > dh_max) return false;
    // Robot positions lie within [dh_min + fwd, dh_max + fwd] (horizontally) of the sample:
    // Chebyshev rings of grid cells from the sample's cell outwards, nearest first.
    const float base_max = dh_max + fwd + 1e-4f;
    const float base_min = std::max(0.f, dh_min + fwd - 1e-4f);
    const Eigen::Vector2f q = p.head<2>();
    const int cx = int(std::floor((q.x() - grid.org.x()) / grid.cell));
    const int cy = int(std::floor((q.y() - grid.org.y()) / grid.cell));
    const int rmax_cells = int(std::ceil(base_max / grid.cell)) + 1;
    // Ring r holds positions within (r - 1) cell .. (r + 1) sqrt(2) cell of the sample.
    const int rmin_cells = std::max(0, int(std::floor(base_min / (1.4143f * grid.cell))) - 1);

    // Packet of up to 8 rays from the sample towards candidate cameras.
    RTCRay8 rays;
    alignas(32) int valid[8];  // Embree wants the mask aligned like the packet
    int k = 0;
    RTCIntersectContext ctx;
    const auto flush = [&]() -> bool {
      if (k == 0) return false;
      for (int i = k; i < 8; ++i) valid[i] = 0;
      rtcInitIntersectContext(&ctx);
      rtcOccluded8(valid, scene.scene, &ctx, &rays);
      bool seen = false;
      for (int i = 0; i < k; ++i) seen = seen || rays.tfar[i] >= 0.f;
      k = 0;
      return seen;
    };
    constexpr float kEps = 1e-3f;
    for (int r = rmin_cells; r <= rmax_cells; ++r) {
      for (int iy = cy - r; iy <= cy + r; ++iy) {
        if (iy < 0 || iy >= grid.ny) continue;
        const bool edge_row = (iy == cy - r || iy == cy + r);
        for (int ix = cx - r; ix <= cx + r; ix += (edge_row || r == 0) ? 1 : 2 * r) {
          if (ix < 0 || ix >= grid.nx) continue;
          for (const Eigen::Vector2f& b : grid.cells[std::size_t(iy) * grid.nx + ix]) {
            const Eigen::Vector2f d2 = q - b;
            const float bd = d2.norm();
            if (bd < base_min || bd > base_max || bd <= fwd) continue;
            const Eigen::Vector2f cam2 = b + (fwd / bd) * d2;
            const float dh = bd - fwd;
            // Depth along the optical axis (the camera faces the sample's azimuth).
            const float depth = dh * cos_pitch + dz * sin_pitch;
            if (depth < rmin || depth > rmax) continue;
            const float d = std::sqrt(dh * dh + dz * dz);
            // Elevation within the field of view: dz / dh in [tan_down, tan_up].
            if (dz > tan_up * dh || dz < tan_down * dh) continue;
            const V3 cam(cam2.x(), cam2.y(), h);
            const V3 v = (cam - p) / d;
            if (std::abs(v.dot(n)) < cos_inc) continue;
            valid[k] = -1;
            rays.org_x[k] = p.x();
            rays.org_y[k] = p.y();
            rays.org_z[k] = p.z();
            rays.dir_x[k] = v.x();
            rays.dir_y[k] = v.y();
            rays.dir_z[k] = v.z();
            rays.tnear[k] = kEps;
            rays.tfar[k] = d - kEps;
            rays.time[k] = 0.f;
            rays.mask[k] = 0xFFFFFFFFu;
            rays.id[k] = unsigned(k);
            rays.flags[k] = 0;
            if (++k == 8 && flush()) return true;
          }
        }
      }
    }
    return flush();
  }
};

}  // namespace

CoverageOptions coverageOptionsForRobot(const TRobotParams& robot, const CameraIntrinsics& K,
                                        double max_range_m) {
  CoverageOptions o;
  o.camera_height_m = robot.camera_height_m;
  o.camera_pitch_deg = robot.camera_pitch_deg;
  o.camera_forward_m = robot.camera_x_m;
  const double up = std::atan((K.cy + 0.5) / K.fy);
  const double down = std::atan((double(K.height) - 0.5 - K.cy) / K.fy);
  // Symmetric field of view about the optical axis (cy is the image's middle in every preset).
  o.vertical_fov_deg = (up + down) / kRadPerDeg;
  if (robot.footprint_radius_m > 0) {
    o.robot_radius_m = robot.footprint_radius_m;
  } else {
    double r = 0;
    for (const Eigen::Vector2f& v : robot.footprintPolygon()) r = std::max(r, double(v.norm()));
    o.robot_radius_m = r;
  }
  o.robot_z_min_m = robot.ground_clearance_m;
  o.robot_z_max_m = robot.height_m;
  o.raster_cell_m = robot.collision_cell_m;
  o.max_range_m = max_range_m;
  return o;
}

SurfaceCoverage::SurfaceCoverage(const World& world, const RayScene& scene,
                                 const CoverageOptions& opts)
    : m_opts(opts) {
  if (!(opts.sample_spacing_m > 0) || !(opts.max_dist_m > 0) || !(opts.position_spacing_m > 0) ||
      !(opts.raster_cell_m > 0) || !(opts.max_range_m > 0) || !(opts.vertical_fov_deg > 0) ||
      !(opts.vertical_fov_deg < 180))
    throw std::invalid_argument(
        "SurfaceCoverage: sample_spacing_m, max_dist_m, position_spacing_m, raster_cell_m, "
        "max_range_m > 0 and 0 < vertical_fov_deg < 180 expected");
  if (scene.world().objects.size() != world.objects.size())
    throw std::invalid_argument("SurfaceCoverage: the scene is not built from this world");
  m_num_objects = world.objects.size();
  m_is_structure.resize(m_num_objects);

  sampleSurfaces(world);
  markObservable(world, scene);
  indexObservableSamples();
}

void SurfaceCoverage::sampleSurfaces(const World& world) {
  const float s = float(m_opts.sample_spacing_m);
  for (std::size_t oi = 0; oi < world.objects.size(); ++oi) {
    const WorldObject& obj = world.objects[oi];
    m_is_structure[oi] = models::isStructureClass(obj.class_id);
    const models::TriangleMesh m = obj.worldMesh();
    float carry = 0.f;
    V3 last_centroid = V3::Zero(), last_normal = V3::UnitZ();
    for (const Eigen::Vector3i& t : m.triangles) {
      const V3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
      const float before = carry;
      const std::size_t n0 = m_samples.size();
      sampleTriangle(a, b, c, s, int(oi), carry, m_samples);
      if (m_samples.size() == n0 && carry > before) {
        last_centroid = (a + b + c) / 3.f;
        const V3 cr = (b - a).cross(c - a);
        last_normal = cr.normalized();
      }
    }
    if (carry > 0.f) {
      Sample smp;
      smp.position = last_centroid;
      smp.normal = last_normal;
      smp.object = int(oi);
      smp.area_m2 = carry;
      m_samples.push_back(smp);
    }
  }
}

void SurfaceCoverage::markObservable(const World& world, const RayScene& scene) {
  m_positions = freePositions(world, m_opts);
  const PositionGrid grid(m_positions, float(m_opts.position_spacing_m));
  Visibility vis{scene.impl(), m_opts, grid};
  const double pitch = m_opts.camera_pitch_deg * kRadPerDeg,
               half = 0.5 * m_opts.vertical_fov_deg * kRadPerDeg;
  vis.tan_up = float(std::tan(std::clamp(pitch + half, -M_PI / 2 + 1e-6, M_PI / 2 - 1e-6)));
  vis.tan_down = float(std::tan(std::clamp(pitch - half, -M_PI / 2 + 1e-6, M_PI / 2 - 1e-6)));
  vis.cos_inc = float(std::cos(std::clamp(m_opts.max_incidence_deg, 0.0, 90.0) * kRadPerDeg));
  vis.cos_pitch = float(std::cos(pitch));
  vis.sin_pitch = float(std::sin(pitch));
  vis.cos_half_fov = float(std::cos(half));
  const long long N = (long long)m_samples.size();
#pragma omp parallel for schedule(dynamic, 256)
  for (long long i = 0; i < N; ++i) {
    Sample& smp = m_samples[std::size_t(i)];
    smp.observable = vis.observable(smp.position, smp.normal);
  }
}

void SurfaceCoverage::indexObservableSamples() {
  m_cell = float(2.0 * m_opts.max_dist_m);
  Eigen::AlignedBox3f box;
  for (const Sample& smp : m_samples)
    if (smp.observable) box.extend(smp.position);
  if (box.isEmpty()) return;
  m_grid_origin = (box.min() / m_cell).array().floor().matrix() * m_cell - V3::Constant(m_cell);
  m_grid_dims = (((box.max() - m_grid_origin) / m_cell).array().floor() + 2.f).cast<int>();
  const std::uint64_t nx = std::uint64_t(m_grid_dims.x()), ny = std::uint64_t(m_grid_dims.y());
  const std::uint64_t total = nx * ny * std::uint64_t(m_grid_dims.z());
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
  for (std::size_t i = 0; i < m_samples.size(); ++i) {
    if (!m_samples[i].observable) continue;
    const Eigen::Vector3i c = ((m_samples[i].position - m_grid_origin) / m_cell)
                                  .array()
                                  .floor()
                                  .cast<int>()
                                  .max(0)
                                  .min(m_grid_dims.array() - 1);
    keyed.emplace_back(
        (std::uint64_t(c.z()) * ny + std::uint64_t(c.y())) * nx + std::uint64_t(c.x()),
        std::uint32_t(i));
  }
  m_observable = keyed.size();
  std::sort(keyed.begin(), keyed.end());
  m_cell_bits.assign(std::size_t((total + 63) / 64), 0);
  m_sorted_pos.resize(keyed.size());
  m_sorted_idx.resize(keyed.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    m_sorted_idx[i] = keyed[i].second;
    m_sorted_pos[i] = m_samples[keyed[i].second].position;
    if (i == 0 || keyed[i].first != keyed[i - 1].first) {
      m_cell_start.push_back(std::uint32_t(i));
      m_cell_bits[std::size_t(keyed[i].first >> 6)] |= std::uint64_t(1) << (keyed[i].first & 63);
    }
  }
  m_cell_start.push_back(std::uint32_t(keyed.size()));
  m_cell_rank.resize(m_cell_bits.size());
  std::uint32_t count = 0;
  for (std::size_t w = 0; w < m_cell_bits.size(); ++w) {
    m_cell_rank[w] = count;
    count += std::uint32_t(__builtin_popcountll(m_cell_bits[w]));
  }
}

SurfaceCoverage::Result SurfaceCoverage::evaluate(
    const std::vector<Eigen::Vector3f>& map_points,
    std::vector<std::uint8_t>* covered_samples) const {
  std::vector<std::uint8_t> covered(m_sorted_pos.size(), 0);
  const float r = float(m_opts.max_dist_m), r2 = r * r, inv = 1.f / m_cell;
  const long long N = (long long)map_points.size();
  if (!m_sorted_pos.empty() && N > 0) {
#pragma omp parallel
    {
      // Per-thread marks, OR-ed together: the same result for any thread count.
      std::vector<std::uint8_t> mine(m_sorted_pos.size(), 0);
      int last_block[6] = {-1, -1, -1, -1, -1, -1};
      std::pair<std::uint32_t, std::uint32_t> ranges[8];
      int nr = 0;
      const int dx = m_grid_dims.x(), dy = m_grid_dims.y(), dz = m_grid_dims.z();
#pragma omp for schedule(static, 8192) nowait
      for (long long i = 0; i < N; ++i) {
        const V3& p = map_points[std::size_t(i)];
        if (!p.allFinite()) continue;
        // The cells the ball of radius r around p reaches (2 per axis: cells are 2 r wide).
        const V3 q = (p - m_grid_origin) * inv;
        const float rc = r * inv;
        const float lo_f[3] = {std::floor(q.x() - rc), std::floor(q.y() - rc),
                               std::floor(q.z() - rc)};
        const float hi_f[3] = {std::floor(q.x() + rc), std::floor(q.y() + rc),
                               std::floor(q.z() + rc)};
        if (hi_f[0] < 0.f || hi_f[1] < 0.f || hi_f[2] < 0.f || lo_f[0] >= float(dx) ||
            lo_f[1] >= float(dy) || lo_f[2] >= float(dz))
          continue;  // outside the samples' cells
        const int block[6] = {std::max(0, int(lo_f[0])),      std::max(0, int(lo_f[1])),
                              std::max(0, int(lo_f[2])),      std::min(dx - 1, int(hi_f[0])),
                              std::min(dy - 1, int(hi_f[1])), std::min(dz - 1, int(hi_f[2]))};
        // Consecutive map points often share their block of cells: reuse its lookups.
        if (!std::equal(block, block + 6, last_block)) {
          std::copy(block, block + 6, last_block);
          nr = 0;
          for (int z = block[2]; z <= block[5]; ++z)
            for (int y = block[1]; y <= block[4]; ++y)
              for (int x = block[0]; x <= block[3]; ++x) {
                const std::uint64_t c =
                    (std::uint64_t(z) * std::uint64_t(dy) + std::uint64_t(y)) * std::uint64_t(dx) +
                    std::uint64_t(x);
                const std::uint64_t word = m_cell_bits[std::size_t(c >> 6)];
                const std::uint64_t bit = std::uint64_t(1) << (c & 63);
                if (!(word & bit)) continue;
                const std::uint32_t k = m_cell_rank[std::size_t(c >> 6)] +
                                        std::uint32_t(__builtin_popcountll(word & (bit - 1)));
                ranges[nr++] = {m_cell_start[k], m_cell_start[k + 1]};
              }
        }
        for (int k = 0; k < nr; ++k)
          for (std::uint32_t j = ranges[k].first; j < ranges[k].second; ++j)
            if ((m_sorted_pos[j] - p).squaredNorm() <= r2) mine[j] = 1;
      }
#pragma omp critical(rasm_sim_surface_coverage)
      for (std::size_t j = 0; j < mine.size(); ++j) covered[j] |= mine[j];
    }
  }

  Result res;
  res.samples = m_samples.size();
  res.observable = m_observable;
  std::vector<double> obs_area(m_num_objects, 0.0), cov_area(m_num_objects, 0.0);
  // Sums in sample order: fixed, whatever the thread count.
  std::vector<std::uint8_t> cov_by_sample(m_samples.size(), 0);
  for (std::size_t j = 0; j < covered.size(); ++j) cov_by_sample[m_sorted_idx[j]] = covered[j];
  double obs_s = 0, cov_s = 0, obs_f = 0, cov_f = 0;
  for (std::size_t i = 0; i < m_samples.size(); ++i) {
    const Sample& smp = m_samples[i];
    if (!smp.observable) continue;
    const double a = smp.area_m2;
    const bool c = cov_by_sample[i] != 0;
    obs_area[std::size_t(smp.object)] += a;
    const bool st = m_is_structure[std::size_t(smp.object)];
    (st ? obs_s : obs_f) += a;
    if (c) {
      ++res.covered;
      cov_area[std::size_t(smp.object)] += a;
      (st ? cov_s : cov_f) += a;
    }
  }
  res.observable_area_m2 = obs_s + obs_f;
  res.covered_area_m2 = cov_s + cov_f;
  const auto ratio = [](double c, double o) { return o > 0 ? c / o : 0.0; };
  res.fraction = ratio(res.covered_area_m2, res.observable_area_m2);
  res.structure = ratio(cov_s, obs_s);
  res.furniture_and_objects = ratio(cov_f, obs_f);
  if (covered_samples) covered_samples->swap(cov_by_sample);
  res.per_object.resize(m_num_objects);
  for (std::size_t k = 0; k < m_num_objects; ++k)
    res.per_object[k] = obs_area[k] > 0 ? cov_area[k] / obs_area[k] : -1.0;
  return res;
}

}  // namespace rasm::sim
