#pragma once
// Private helpers of the world and trajectory generators: a seeded random stream that gives the
// same numbers with every standard library (raw std::mt19937_64 bits, no std distributions),
// and numbers printed rounded, without trailing zeros.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace rasm::sim::gen {

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : m_g(seed) {}
  /// Uniform in [0, 1).
  double uniform() { return double(m_g() >> 11) * (1.0 / 9007199254740992.0); }
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  /// Uniform integer in [0, n).
  int index(int n) { return std::min(n - 1, int(uniform() * n)); }
  bool chance(double p) { return uniform() < p; }
  template <class T>
  T pick(const std::vector<T>& v) {
    return v[std::size_t(index(int(v.size())))];
  }
  /// Index drawn with probability proportional to its weight.
  int weighted(const std::vector<double>& w) {
    double sum = 0;
    for (double x : w) sum += x;
    double r = uniform() * sum;
    for (std::size_t i = 0; i < w.size(); ++i) {
      if (r < w[i]) return int(i);
      r -= w[i];
    }
    for (std::size_t i = w.size(); i-- > 0;)
      if (w[i] > 0) return int(i);
    return 0;
  }

 private:
  std::mt19937_64 m_g;
};

/// `v` rounded to `decimals`, trailing zeros and a lone "-" of "-0" dropped: 1.5, 0.74, -2, 0.
inline std::string num(double v, int decimals = 3) {
  const double s = std::pow(10.0, decimals);
  double r = std::round(v * s) / s;
  if (r == 0.0) r = 0.0;  // no "-0"
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, r);
  std::string t = buf;
  if (t.find('.') != std::string::npos) {
    while (!t.empty() && t.back() == '0') t.pop_back();
    if (!t.empty() && t.back() == '.') t.pop_back();
  }
  if (t == "-0") t = "0";
  return t;
}

}  // namespace rasm::sim::gen
