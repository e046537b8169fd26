#include "rasm/sim/OccupancyRaster.h"

#include <algorithm>
#include <cmath>

namespace rasm::sim {

namespace {

/// Sutherland-Hodgman clip of a polygon against z >= lo (sign = +1) or z <= hi (sign = -1).
std::vector<Eigen::Vector3f> clipZ(const std::vector<Eigen::Vector3f>& in, float bound,
                                   float sign) {
  std::vector<Eigen::Vector3f> out;
  const int n = int(in.size());
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3f& a = in[i];
    const Eigen::Vector3f& b = in[(i + 1) % n];
    const float da = sign * (a.z() - bound), db = sign * (b.z() - bound);
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

bool insidePolygon(const std::vector<Eigen::Vector2f>& poly, const Eigen::Vector2f& p) {
  bool in = false;
  const int n = int(poly.size());
  for (int i = 0, j = n - 1; i < n; j = i++) {
    const Eigen::Vector2f& a = poly[i];
    const Eigen::Vector2f& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      in = !in;
  }
  return in;
}

}  // namespace

OccupancyRaster::OccupancyRaster(const World& world, float z_min, float z_max, float cell)
    : m_cell(cell) {
  const Eigen::AlignedBox3f b = world.bounds();
  const float margin = 1.0f;
  m_origin = b.min().head<2>() - Eigen::Vector2f::Constant(margin);
  m_w = int(std::ceil((b.max().x() - b.min().x() + 2 * margin) / cell)) + 1;
  m_h = int(std::ceil((b.max().y() - b.min().y() + 2 * margin) / cell)) + 1;
  m_occ.assign(std::size_t(m_w) * m_h, 0);
  for (const WorldObject& o : world.objects) {
    const Eigen::Affine3f T = o.worldFromObjectScaled();
    for (const auto& t : o.mesh.triangles) {
      std::vector<Eigen::Vector3f> poly{T * o.mesh.vertices[t[0]], T * o.mesh.vertices[t[1]],
                                        T * o.mesh.vertices[t[2]]};
      poly = clipZ(poly, z_min, 1.f);
      if (poly.empty()) continue;
      poly = clipZ(poly, z_max, -1.f);
      if (poly.empty()) continue;
      std::vector<Eigen::Vector2f> p2;
      for (const auto& v : poly) p2.push_back(v.head<2>());
      markPolygon(p2);
    }
  }
}

void OccupancyRaster::markSegment(const Eigen::Vector2f& a, const Eigen::Vector2f& b) {
  const float len = (b - a).norm();
  const int n = std::max(1, int(std::ceil(len / (0.25f * m_cell))));
  for (int i = 0; i <= n; ++i) {
    const Eigen::Vector2f p = a + (b - a) * (float(i) / float(n));
    mark(int(std::floor((p.x() - m_origin.x()) / m_cell)),
         int(std::floor((p.y() - m_origin.y()) / m_cell)));
  }
}

void OccupancyRaster::markPolygon(const std::vector<Eigen::Vector2f>& poly) {
  const int n = int(poly.size());
  for (int i = 0; i < n; ++i) markSegment(poly[i], poly[(i + 1) % n]);
  Eigen::AlignedBox2f bb;
  for (const auto& p : poly) bb.extend(p);
  const int x0 = int(std::floor((bb.min().x() - m_origin.x()) / m_cell));
  const int x1 = int(std::floor((bb.max().x() - m_origin.x()) / m_cell));
  const int y0 = int(std::floor((bb.min().y() - m_origin.y()) / m_cell));
  const int y1 = int(std::floor((bb.max().y() - m_origin.y()) / m_cell));
  if (x1 - x0 < 2 && y1 - y0 < 2) return;  // the edges already cover it
  for (int iy = y0; iy <= y1; ++iy)
    for (int ix = x0; ix <= x1; ++ix)
      if (insidePolygon(poly, m_origin + m_cell * Eigen::Vector2f(ix + 0.5f, iy + 0.5f)))
        mark(ix, iy);
}

bool OccupancyRaster::occupied(float x, float y) const {
  return cell(int(std::floor((x - m_origin.x()) / m_cell)),
              int(std::floor((y - m_origin.y()) / m_cell)));
}

bool OccupancyRaster::collidesDisc(const Eigen::Vector2f& c, float r) const {
  const int x0 = int(std::floor((c.x() - r - m_origin.x()) / m_cell));
  const int x1 = int(std::floor((c.x() + r - m_origin.x()) / m_cell));
  const int y0 = int(std::floor((c.y() - r - m_origin.y()) / m_cell));
  const int y1 = int(std::floor((c.y() + r - m_origin.y()) / m_cell));
  for (int iy = y0; iy <= y1; ++iy)
    for (int ix = x0; ix <= x1; ++ix) {
      if (!cell(ix, iy)) continue;
      // Closest point of the cell square to the centre.
      const Eigen::Vector2f lo = m_origin + m_cell * Eigen::Vector2f(float(ix), float(iy));
      const Eigen::Vector2f q = c.cwiseMax(lo).cwiseMin(lo + Eigen::Vector2f::Constant(m_cell));
      if ((q - c).squaredNorm() <= r * r) return true;
    }
  return false;
}

bool OccupancyRaster::collidesPolygon(const std::vector<Eigen::Vector2f>& poly) const {
  const int n = int(poly.size());
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2f a = poly[i], b = poly[(i + 1) % n];
    const int steps = std::max(1, int(std::ceil((b - a).norm() / (0.25f * m_cell))));
    for (int k = 0; k <= steps; ++k) {
      const Eigen::Vector2f p = a + (b - a) * (float(k) / float(steps));
      if (occupied(p.x(), p.y())) return true;
    }
  }
  Eigen::AlignedBox2f bb;
  for (const auto& p : poly) bb.extend(p);
  for (float y = bb.min().y(); y <= bb.max().y(); y += 0.5f * m_cell)
    for (float x = bb.min().x(); x <= bb.max().x(); x += 0.5f * m_cell)
      if (occupied(x, y) && insidePolygon(poly, {x, y})) return true;
  return false;
}

std::size_t OccupancyRaster::occupiedCount() const {
  return std::size_t(std::count(m_occ.begin(), m_occ.end(), std::uint8_t(1)));
}

}  // namespace rasm::sim
