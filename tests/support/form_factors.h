// Closed forms of the light a point receives from an axis-aligned rectangle
// above it: the projected solid angle (the integral of cos over the solid
// angle), which the closed-form lighting tests compare renders against.
#pragma once

#include <cmath>

namespace pt::test {

/// Integral of cos over the rectangle [0, x] x [0, z] at height h above a
/// point (a corner above it), signed by the quadrant of (x, z).
inline double corner_integral(double x, double z, double h) {
  double a = std::fabs(x) / h, b = std::fabs(z) / h, sa = std::sqrt(1 + a * a), sb = std::sqrt(1 + b * b);
  double value = 0.5 * (a / sa * std::atan(b / sa) + b / sb * std::atan(a / sb));
  return std::copysign(1.0, x) * std::copysign(1.0, z) * value;
}

/// Integral of cos (projected solid angle) of the horizontal rectangle
/// [x0, x1] x [z0, z1] at height h above the point (px, py, pz), facing it,
/// by inclusion-exclusion of its corners.
inline double projected_solid_angle(double x0, double x1, double z0, double z1, double h, double px, double pz) {
  x0 -= px, x1 -= px, z0 -= pz, z1 -= pz;
  return corner_integral(x1, z1, h) - corner_integral(x0, z1, h) - corner_integral(x1, z0, h) +
         corner_integral(x0, z0, h);
}

}  // namespace pt::test
