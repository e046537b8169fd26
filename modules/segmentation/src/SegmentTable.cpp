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
}  // namespace

void SegmentTable::compute(const maps::SurfelArrays& s) {
  m_max_label = 0;
  for (int i = 0; i < s.size; ++i)
    if (s.alive(i)) m_max_label = std::max(m_max_label, s.segment[i]);
  const std::size_t L = std::size_t(m_max_label) + 1;
  const int chunks = (s.size + kChunk - 1) / kChunk;
  // Pass 1: moments per label, per chunk of surfels, then summed (deterministic order).
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
  m_segments.clear();
  std::vector<int> slot(L, -1);
  for (std::size_t l = 1; l < L; ++l) {
    const Moments& m = total[l];
    if (m.n == 0) continue;
    SegmentStats st;
    st.id = std::uint32_t(l);
    st.surfels = m.n;
    st.stable_surfels = m.stable;
    st.centroid = m.sum / m.n;
    const Eigen::Matrix3d cov = m.sum2 / m.n - st.centroid * st.centroid.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    // Eigen sorts eigenvalues increasingly: reverse to decreasing variance.
    for (int k = 0; k < 3; ++k) st.axes.col(k) = es.eigenvectors().col(2 - k);
    if (st.axes.determinant() < 0) st.axes.col(2) = -st.axes.col(2);
    st.bbox_min = m.lo;
    st.bbox_max = m.hi;
    st.last_seen = m.last;
    slot[l] = int(m_segments.size());
    m_segments.push_back(st);
  }
  // Pass 2: extents along the axes.
  std::vector<std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>> ext(std::size_t(std::max(chunks, 0)));
  const double inf = std::numeric_limits<double>::infinity();
  compute::forEach1D(chunks, [&](int c) {
    auto& e = ext[std::size_t(c)];
    e.assign(m_segments.size(), {Eigen::Vector3d::Constant(inf), Eigen::Vector3d::Constant(-inf)});
    const int i1 = std::min(s.size, (c + 1) * kChunk);
    for (int i = c * kChunk; i < i1; ++i) {
      const std::uint32_t l = s.segment[i];
      if (!l || !s.alive(i)) continue;
      const SegmentStats& st = m_segments[std::size_t(slot[l])];
      const Eigen::Vector3d q = st.axes.transpose() * (s.position(i).cast<double>() - st.centroid);
      auto& [lo, hi] = e[std::size_t(slot[l])];
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
  });
  for (std::size_t k = 0; k < m_segments.size(); ++k) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(inf), hi = Eigen::Vector3d::Constant(-inf);
    for (const auto& e : ext) {
      lo = lo.cwiseMin(e[k].first);
      hi = hi.cwiseMax(e[k].second);
    }
    m_segments[k].extents = hi - lo;
  }
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
  std::sort(out.begin(), out.end(), [](const SegmentStats& a, const SegmentStats& b) { return a.id < b.id; });
  m_segments.swap(out);
}

std::vector<std::uint32_t> denseRelabelling(const SegmentTable& table) {
  std::vector<std::uint32_t> out(std::size_t(table.maxLabel()) + 1, 0u);
  std::uint32_t next = 1;
  for (const SegmentStats& s : table.segments()) out[s.id] = next++;
  return out;
}

}  // namespace rasm::segmentation
