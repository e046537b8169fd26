#pragma once
// CPU launchers: run a kernel functor over a 1-D or 2-D range with OpenMP. The functor is the same
// struct the CUDA launchers (ParallelCuda.cuh) run, with `RASM_HD void operator()(int i) const` or
// `(int x, int y) const`. Reductions take `RASM_HD void operator()(int i, Acc& acc) const`
// and need `Acc::operator+=`; each thread accumulates privately and the partials are summed
// in a fixed order, so results are deterministic for a given thread count.

#include <algorithm>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace rasm::compute {

enum class Backend { Cpu, Cuda };

inline int maxThreads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

template <typename F>
void forEach1D(int n, const F& f) {
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n; ++i) f(i);
}

/// Rows are distributed over threads; x runs innermost (cache friendly for pitched images).
template <typename F>
void forEach2D(int width, int height, const F& f) {
#pragma omp parallel for schedule(static)
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) f(x, y);
}

template <typename Acc, typename F>
Acc reduce1D(int n, const F& f, const Acc& zero = Acc()) {
  const int nt = std::max(1, std::min(maxThreads(), n / 256 + 1));
  std::vector<Acc> partial(nt, zero);
#pragma omp parallel num_threads(nt)
  {
#ifdef _OPENMP
    const int t = omp_get_thread_num();
#else
    const int t = 0;
#endif
    const int begin = static_cast<int>(static_cast<long long>(n) * t / nt);
    const int end = static_cast<int>(static_cast<long long>(n) * (t + 1) / nt);
    Acc& acc = partial[t];
    for (int i = begin; i < end; ++i) f(i, acc);
  }
  Acc total = zero;
  for (const Acc& p : partial) total += p;
  return total;
}

template <typename Acc, typename F>
Acc reduce2D(int width, int height, const F& f, const Acc& zero = Acc()) {
  return reduce1D<Acc>(
      width * height, [&](int i, Acc& acc) { f(i % width, i / width, acc); }, zero);
}

}  // namespace rasm::compute
