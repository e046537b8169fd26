#pragma once
// Degrees and radians. Parameters are given in degrees (INI files, reports), the maths runs in
// radians: the one conversion constant of the project.

#include <cmath>

namespace rasm {

/// Radians per degree.
inline constexpr double kRadPerDeg = M_PI / 180.0;
/// Radians per degree as a float (float(pi) / 180 and float(pi / 180) are the same float).
inline constexpr float kRadPerDegF = float(M_PI / 180.0);

}  // namespace rasm
