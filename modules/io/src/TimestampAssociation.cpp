#include "rasm/io/TimestampAssociation.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <tuple>

namespace rasm::io {

std::vector<std::pair<std::size_t, std::size_t>> associateTimestamps(const std::vector<double>& a,
                                                                     const std::vector<double>& b,
                                                                     double max_dt_s,
                                                                     double offset_s) {
  std::vector<std::size_t> bi(b.size());
  std::iota(bi.begin(), bi.end(), 0);
  std::sort(bi.begin(), bi.end(), [&](std::size_t x, std::size_t y) { return b[x] < b[y]; });
  std::vector<double> bs(b.size());
  for (std::size_t k = 0; k < bi.size(); ++k) bs[k] = b[bi[k]] + offset_s;

  // Candidates (|dt|, t_a, t_b) as associate.py sorts its tuples.
  struct Cand {
    double dt, ta, tb;
    std::size_t i, j;
  };
  std::vector<Cand> cands;
  for (std::size_t i = 0; i < a.size(); ++i) {
    auto it = std::lower_bound(bs.begin(), bs.end(), a[i] - max_dt_s);
    for (; it != bs.end() && *it <= a[i] + max_dt_s; ++it) {
      const double dt = std::abs(a[i] - *it);
      if (dt < max_dt_s) {
        const std::size_t j = bi[std::size_t(it - bs.begin())];
        cands.push_back({dt, a[i], b[j], i, j});
      }
    }
  }
  std::sort(cands.begin(), cands.end(), [](const Cand& x, const Cand& y) {
    return std::tie(x.dt, x.ta, x.tb) < std::tie(y.dt, y.ta, y.tb);
  });
  std::vector<char> used_a(a.size(), 0), used_b(b.size(), 0);
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (const Cand& c : cands)
    if (!used_a[c.i] && !used_b[c.j]) {
      used_a[c.i] = used_b[c.j] = 1;
      out.emplace_back(c.i, c.j);
    }
  std::sort(out.begin(), out.end(), [&](const auto& x, const auto& y) {
    return std::tie(a[x.first], b[x.second]) < std::tie(a[y.first], b[y.second]);
  });
  return out;
}

std::size_t closestIndex(const std::vector<double>& s, double t) {
  if (s.empty()) throw std::invalid_argument("closestIndex: empty stamp list");
  const auto it = std::lower_bound(s.begin(), s.end(), t);
  if (it == s.begin()) return 0;
  if (it == s.end()) return s.size() - 1;
  const std::size_t hi = std::size_t(it - s.begin());
  return (t - s[hi - 1] <= s[hi] - t) ? hi - 1 : hi;
}

}  // namespace rasm::io
