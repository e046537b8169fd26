#include "rasm/segmentation/SegmentTable.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <limits>

#include "rasm/compute/Parallel.h"

namespace rasm::segmentation {

namespace {
struct Moments {
  int n = 0, stable = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum2 = Eigen::Matrix3d::Zero();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  float last = -std::numeric_limits<float>::infinity();
  void add(const Moments& o) {
    n += o.n;
    stable += o.stable;
    sum += o.sum;
    sum2 += o.sum2;
    lo = lo.cwiseMin(o.lo);
    hi = hi.cwiseMax(o.hi);
    last = std::max(last, o.last);
  }
};

constexpr int kChunk = 1 << 16;

/// Moments of the alive, labelled surfels per label 0..L-1: per chunk of surfels in parallel,
/// then summed in chunk order (deterministic).
std::vector<Moments> momentsPerLabel(const maps::SurfelArrays& s, std::size_t L) {
  const int chunks = (s.size + kChunk - 1) / kChunk;
  std::vector<std::vector<Moments>> part(std::size_t(std::max(chunks, 0)));
  compute::forEach1D(chunks, [&](int c) {
    std::vector<Moments>& m = part[std::size_t(c)];
    m.assign(L, Moments());
    const int i1 = std::min(s.size, (c + 1) * kChunk);
    for (int i = c * kChunk; i < i1; ++i) {
      const std::uint32_t l = s.segment[i];
      if (!l || !s.alive(i)) continue;
      const Eigen::Vector3d p = s.position(i).cast<double>();
      Moments& a = m[l];
      ++a.n;
      a.stable += s.stable(i);
      a.sum += p;
      a.sum2 += p * p.transpose();
      a.lo = a.lo.cwiseMin(p);
      a.hi = a.hi.cwiseMax(p);
      a.last = std::max(a.last, s.t_last[i]);
    }
  });
  std::vector<Moments> total(L);
  for (const auto& m : part)
    for (std::size_t l = 0; l < L; ++l) total[l].add(m[l]);
  return total;
}

/// A segment's stats from its moments: centroid, PCA and upright axes, box and last time seen
/// (the extents come from the second pass).
SegmentStats statsFromMoments(std::uint32_t id, const Moments& m) {
  SegmentStats st;
  st.id = id;
  st.surfels = m.n;
  st.stable_surfels = m.stable;
  st.centroid = m.sum / m.n;
  const Eigen::Matrix3d cov = m.sum2 / m.n - st.centroid * st.centroid.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  // Eigen sorts eigenvalues increasingly: reverse to decreasing variance.
  for (int k = 0; k < 3; ++k) st.axes.col(k) = es.eigenvectors().col(2 - k);
  if (st.axes.determinant() < 0) st.axes.col(2) = -st.axes.col(2);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eh(cov.topLeftCorner<2, 2>());
  const Eigen::Vector2d h0 = eh.eigenvectors().col(1);
  st.upright_axes.col(0) = Eigen::Vector3d(h0.x(), h0.y(), 0.0);
  st.upright_axes.col(1) = Eigen::Vector3d(-h0.y(), h0.x(), 0.0);
  st.upright_axes.col(2) = Eigen::Vector3d::UnitZ();
  st.bbox_min = m.lo;
  st.bbox_max = m.hi;
  st.last_seen = m.last;
  return st;
}

constexpr int kBins = 256;
/// Histograms of the surfel centres projected on a segment's PCA axes (0-2) and upright axes
/// (3-5), kBins each over the projection of its bounding box.
struct AxisHistograms {
  double lo[6], width[6];
  std::vector<int> bins;
};

Eigen::Vector3d statsAxis(const SegmentStats& st, int ax) {
  return ax < 3 ? Eigen::Vector3d(st.axes.col(ax)) : Eigen::Vector3d(st.upright_axes.col(ax - 3));
}

AxisHistograms emptyHistograms(const SegmentStats& st) {
  AxisHistograms h;
  h.bins.assign(6 * kBins, 0);
  for (int ax = 0; ax < 6; ++ax) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d corner((c & 1) ? st.bbox_max.x() : st.bbox_min.x(),
                                   (c & 2) ? st.bbox_max.y() : st.bbox_min.y(),
                                   (c & 4) ? st.bbox_max.z() : st.bbox_min.z());
      const double q = statsAxis(st, ax).dot(corner - st.centroid);
      lo = std::min(lo, q);
      hi = std::max(hi, q);
    }
    h.lo[ax] = lo;
    h.width[ax] = std::max(hi - lo, 1e-9) / kBins;
  }
  return h;
}

/// Extents along the axes between the 1st and 99th percentile of the projected surfel centres
/// (a few stray surfels do not stretch an object), and the upright box's centre.
void setPercentileExtents(SegmentStats& st, const AxisHistograms& h) {
  st.upright_centre = st.centroid;
  for (int ax = 0; ax < 6; ++ax) {
    const int* b = h.bins.data() + ax * kBins;
    const double n = st.surfels, lo_q = 0.01 * n, hi_q = 0.99 * n;
    double acc = 0;
    int b_lo = 0, b_hi = kBins - 1;
    for (int j = 0; j < kBins; ++j) {
      if (acc <= lo_q) b_lo = j;
      acc += b[j];
      if (acc < hi_q) b_hi = j + 1;
    }
    b_hi = std::min(b_hi, kBins - 1);
    (ax < 3 ? st.extents[ax] : st.upright_extents[ax - 3]) =
        std::max(0.0, (b_hi + 1 - b_lo) * h.width[ax]);
    if (ax >= 3)  // the middle of the percentile range, along the upright axis
      st.upright_centre += statsAxis(st, ax) * (h.lo[ax] + 0.5 * (b_lo + b_hi + 1) * h.width[ax]);
  }
}

}  // namespace

void SegmentTable::compute(const maps::SurfelArrays& s) {
  m_max_label = 0;
  for (int i = 0; i < s.size; ++i)
    if (s.alive(i)) m_max_label = std::max(m_max_label, s.segment[i]);
  const std::size_t L = std::size_t(m_max_label) + 1;
  // Pass 1: moments per label.
  const std::vector<Moments> total = momentsPerLabel(s, L);
  m_segments.clear();
  std::vector<int> slot(L, -1);
  for (std::size_t l = 1; l < L; ++l) {
    if (total[l].n == 0) continue;
    slot[l] = int(m_segments.size());
    m_segments.push_back(statsFromMoments(std::uint32_t(l), total[l]));
  }
  // Pass 2: percentile extents from histograms of the projected centres. Serial: O(N) every few
  // frames.
  std::vector<AxisHistograms> hist;
  hist.reserve(m_segments.size());
  for (const SegmentStats& st : m_segments) hist.push_back(emptyHistograms(st));
  for (int i = 0; i < s.size; ++i) {
    const std::uint32_t l = s.segment[i];
    if (!l || !s.alive(i)) continue;
    const int k = slot[l];
    const SegmentStats& st = m_segments[std::size_t(k)];
    AxisHistograms& h = hist[std::size_t(k)];
    const Eigen::Vector3d d = s.position(i).cast<double>() - st.centroid;
    for (int ax = 0; ax < 6; ++ax) {
      const double q = statsAxis(st, ax).dot(d);
      const int b = std::min(kBins - 1, std::max(0, int((q - h.lo[ax]) / h.width[ax])));
      ++h.bins[std::size_t(ax * kBins + b)];
    }
  }
  for (std::size_t k = 0; k < m_segments.size(); ++k) setPercentileExtents(m_segments[k], hist[k]);
}

const SegmentStats* SegmentTable::find(std::uint32_t id) const {
  const auto it = std::lower_bound(m_segments.begin(), m_segments.end(), id,
                                   [](const SegmentStats& s, std::uint32_t v) { return s.id < v; });
  return it != m_segments.end() && it->id == id ? &*it : nullptr;
}

void SegmentTable::renumber(const std::vector<std::uint32_t>& table) {
  std::vector<SegmentStats> out;
  m_max_label = 0;
  for (SegmentStats s : m_segments) {
    const std::uint32_t id = s.id < table.size() ? table[s.id] : 0u;
    if (!id) continue;
    s.id = id;
    m_max_label = std::max(m_max_label, id);
    out.push_back(s);
  }
  std::sort(out.begin(), out.end(),
            [](const SegmentStats& a, const SegmentStats& b) { return a.id < b.id; });
  m_segments.swap(out);
}

std::vector<std::uint32_t> denseRelabelling(const SegmentTable& table) {
  std::vector<std::uint32_t> out(std::size_t(table.maxLabel()) + 1, 0u);
  std::uint32_t next = 1;
  for (const SegmentStats& s : table.segments()) out[s.id] = next++;
  return out;
}

}  // namespace rasm::segmentation
