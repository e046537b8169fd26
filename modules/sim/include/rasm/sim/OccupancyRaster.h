#pragma once
// 2-D occupancy raster of a world's geometry inside a height band [z_min, z_max]: every
// triangle is clipped to the band and its footprint on the floor plane is marked. It is the
// robot's collision model (a planar robot hits whatever occupies its height band; it can pass
// under a desk top that is above the band).

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "rasm/sim/World.h"

namespace rasm::sim {

class OccupancyRaster {
 public:
  OccupancyRaster() = default;
  /// Rasterizes `world` at `cell_m` resolution over its xy bounds (plus a margin).
  OccupancyRaster(const World& world, float z_min_m, float z_max_m, float cell_m = 0.02f);

  float cellSize() const { return m_cell; }
  int width() const { return m_w; }
  int height() const { return m_h; }
  Eigen::Vector2f origin() const { return m_origin; }  ///< world xy of cell (0, 0)'s corner

  /// Whether the cell containing world point (x, y) is occupied (outside the raster: false).
  bool occupied(float x, float y) const;
  /// Whether any occupied cell overlaps the disc (centre, radius); cells count as squares.
  bool collidesDisc(const Eigen::Vector2f& centre, float radius_m) const;
  /// Whether any occupied cell overlaps the simple polygon (world coordinates).
  bool collidesPolygon(const std::vector<Eigen::Vector2f>& polygon_world) const;
  /// Number of occupied cells (for tests and statistics).
  std::size_t occupiedCount() const;

 private:
  bool cell(int ix, int iy) const {
    return ix >= 0 && iy >= 0 && ix < m_w && iy < m_h && m_occ[std::size_t(iy) * m_w + ix];
  }
  void mark(int ix, int iy) {
    if (ix >= 0 && iy >= 0 && ix < m_w && iy < m_h) m_occ[std::size_t(iy) * m_w + ix] = 1;
  }
  void markSegment(const Eigen::Vector2f& a, const Eigen::Vector2f& b);
  void markPolygon(const std::vector<Eigen::Vector2f>& poly);

  float m_cell = 0.02f;
  int m_w = 0, m_h = 0;
  Eigen::Vector2f m_origin = Eigen::Vector2f::Zero();
  std::vector<std::uint8_t> m_occ;
};

}  // namespace rasm::sim
