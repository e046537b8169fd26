#pragma once
// One check per kind of number read from outside (files, command lines): finite, and within the
// range the value can physically take. The message names the value and what was expected; the
// caller prefixes where it came from (file:line, key, option).

#include <cmath>
#include <sstream>
#include <string>

#include "rasm/core/Error.h"

namespace rasm {

/// The largest coordinate (metres from the origin) any input may give: far beyond any indoor
/// scene, and small enough for float geometry (a ray tracer aborts on 1e30).
constexpr double kMaxCoordinate_m = 1e4;
/// The largest size (metres) of an object or a scale factor an input may give.
constexpr double kMaxSize_m = 1e3;

/// "" when `value` is a finite number in [lo, hi], else what is wrong with it ("value nan is not
/// a finite number", "value 1e+30 out of range, expected [-10000, 10000]").
inline std::string rangeProblem(double value, double lo, double hi) {
  std::ostringstream s;
  if (!std::isfinite(value))
    s << "value " << value << " is not a finite number";
  else if (!(value >= lo && value <= hi))
    s << "value " << value << " out of range, expected [" << lo << ", " << hi << "]";
  return s.str();
}

/// Throws InputError("<what>: <rangeProblem>") unless `value` is finite and in [lo, hi].
inline void requireFiniteIn(double value, double lo, double hi, const std::string& what) {
  if (const std::string p = rangeProblem(value, lo, hi); !p.empty()) throwInputError(what, p);
}

/// A coordinate in metres: finite and within +-kMaxCoordinate_m.
inline void requireCoordinate(double value_m, const std::string& what) {
  requireFiniteIn(value_m, -kMaxCoordinate_m, kMaxCoordinate_m, what);
}

/// An angle in degrees: finite and within +-360 * 1000 (any number of turns a user writes).
inline void requireAngleDeg(double value_deg, const std::string& what) {
  requireFiniteIn(value_deg, -360e3, 360e3, what);
}

}  // namespace rasm
