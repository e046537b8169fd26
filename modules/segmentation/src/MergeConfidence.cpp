#include "rasm/segmentation/MergeConfidence.h"

#include <algorithm>
#include <numeric>

namespace rasm::segmentation {

std::vector<MergeConfidence::Pair> MergeConfidence::update(
    const std::vector<Pair>& cosegmented, const std::vector<std::uint32_t>& visible,
    int threshold) {
  const auto inView = [&](std::uint32_t l) {
    return std::binary_search(visible.begin(), visible.end(), l);
  };
  // Decrement every standing pair whose labels are both in view and not together this frame.
  for (auto it = m_psi.begin(); it != m_psi.end();) {
    const Pair p(std::uint32_t(it->first >> 32), std::uint32_t(it->first));
    if (inView(p.first) && inView(p.second) &&
        !std::binary_search(cosegmented.begin(), cosegmented.end(), p)) {
      if (--it->second <= 0) {
        it = m_psi.erase(it);
        continue;
      }
    }
    ++it;
  }
  std::vector<Pair> due;
  for (const Pair& p : cosegmented)
    if (++m_psi[key(p.first, p.second)] > threshold) due.push_back(p);
  return due;
}

void MergeConfidence::rename(std::uint32_t from, std::uint32_t to) {
  std::vector<std::pair<std::uint64_t, int>> moved;
  for (auto it = m_psi.begin(); it != m_psi.end();) {
    const std::uint32_t a = std::uint32_t(it->first >> 32), b = std::uint32_t(it->first);
    if (a == from || b == from) {
      const std::uint32_t other = a == from ? b : a;
      if (other != to) moved.emplace_back(key(other, to), it->second);
      it = m_psi.erase(it);
    } else {
      ++it;
    }
  }
  for (const auto& [k, v] : moved) m_psi[k] += v;
}

void MergeConfidence::remap(const std::vector<std::uint32_t>& table) {
  std::unordered_map<std::uint64_t, int> out;
  for (const auto& [k, v] : m_psi) {
    const std::uint32_t a = std::uint32_t(k >> 32), b = std::uint32_t(k);
    const std::uint32_t na = a < table.size() ? table[a] : 0u,
                        nb = b < table.size() ? table[b] : 0u;
    if (na && nb && na != nb) out[key(na, nb)] += v;
  }
  m_psi.swap(out);
}

int MergeConfidence::confidence(std::uint32_t a, std::uint32_t b) const {
  const auto it = m_psi.find(key(a, b));
  return it == m_psi.end() ? 0 : it->second;
}

std::vector<std::uint32_t> mergeTable(const std::vector<MergeConfidence::Pair>& due, int& merges) {
  std::uint32_t top = 0;
  for (const auto& [a, b] : due) top = std::max({top, a, b});
  std::vector<std::uint32_t> parent(std::size_t(top) + 1);
  std::iota(parent.begin(), parent.end(), 0u);
  const auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  merges = 0;
  for (const auto& [a, b] : due) {
    const std::uint32_t ra = find(a), rb = find(b);
    if (ra == rb) continue;
    parent[std::max(ra, rb)] = std::min(ra, rb);
    ++merges;
  }
  std::vector<std::uint32_t> table(parent.size());
  for (std::uint32_t l = 0; l < table.size(); ++l) table[l] = find(l);
  return table;
}

}  // namespace rasm::segmentation
