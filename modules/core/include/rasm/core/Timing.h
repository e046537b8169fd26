#pragma once
// Wall-clock timing of stages (report.json / frames.csv milliseconds; tests never assert on them).

#include <chrono>

namespace rasm {

using Clock = std::chrono::steady_clock;

/// Milliseconds since t0.
inline double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace rasm
