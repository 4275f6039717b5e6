#pragma once
// Elliptical point contact of two bodies whose principal planes of curvature coincide (a crowned roller on a
// cam: the rolling plane and the roller's axial plane): Hertz's force-approach law F = K delta^1.5, the
// semi-axes of the contact ellipse and the maximum pressure, with the approximations of B. J. Hamrock and
// D. E. Brewe, "Simplified solution for stresses and deformations", J. Lubrication Technology 105 (1983)
// 171-177 (also B. J. Hamrock, Fundamentals of Fluid Film Lubrication, 1994, ch. 3) for the ellipticity and
// the complete elliptic integrals. The exact theory: K. L. Johnson, Contact Mechanics, 1985, section 4.2.
//
// Radii of relative curvature Rx, Ry (m) in the two principal planes (1/Rx = 1/R1x + 1/R2x, a concave radius
// negative; both must be > 0), 1/R = 1/Rx + 1/Ry, radius ratio alpha = Rmax / Rmin >= 1, E' = 2 E*:
//   k = alpha^(2/pi)                           ellipticity (major / minor semi-axis)
//   Ee = 1 + (pi/2 - 1) / alpha                 complete elliptic integral of the second kind
//   Fe = pi/2 + (pi/2 - 1) ln alpha             ... of the first kind
//   a = (6 k^2 Ee F R / (pi E'))^(1/3)         major semi-axis, along the direction of the larger radius
//   b = (6 Ee F R / (pi k E'))^(1/3)           minor semi-axis
//   delta = Fe (9 / (2 Ee R) (F / (pi k E'))^2)^(1/3),  so  F = K delta^1.5,  K = pi k E' sqrt(2 Ee R / 9) /
//   Fe^1.5 p0 = 3 F / (2 pi a b)
// At alpha = 1 the approximations are exact (k = 1, Ee = Fe = pi/2) and the law is Hertz's sphere on a flat:
// F = 4/3 E* sqrt(R') delta^1.5, a = b = (3 F R' / (4 E*))^(1/3), R' = Rx = Ry. Hamrock and Brewe state
// errors of a few percent for 1 <= alpha <= 100 (measured against the exact elliptic-integral solution in
// tests/solve/test_roller_cam.cpp).
#include <algorithm>
#include <cmath>
#include <numbers>

namespace nvh::solve::hertz {

struct Ellipse {
  double k = 1, ee = 0, fe = 0;  // ellipticity, elliptic integrals E and F (approximations)
  double r = 0;                  // 1 / (1/Rx + 1/Ry) (m)
  bool major_along_y = true;     // the major semi-axis lies in the y plane (Ry >= Rx)
};

/// The ellipse's constants for radii rx, ry (m, > 0).
inline Ellipse ellipse(double rx, double ry) {
  constexpr double q = std::numbers::pi / 2 - 1;
  Ellipse e;
  e.major_along_y = ry >= rx;
  const double alpha = e.major_along_y ? ry / rx : rx / ry;
  e.k = std::pow(alpha, 2 / std::numbers::pi);
  e.ee = 1 + q / alpha;
  e.fe = std::numbers::pi / 2 + q * std::log(alpha);
  e.r = 1.0 / (1.0 / rx + 1.0 / ry);
  return e;
}

/// K (N/m^1.5) of F = K delta^1.5 for radii rx, ry (m) and contact modulus E* (Pa).
inline double point_stiffness(double rx, double ry, double e_star) {
  const Ellipse e = ellipse(rx, ry);
  return std::numbers::pi * e.k * 2 * e_star * std::sqrt(2 * e.ee * e.r / 9) / std::pow(e.fe, 1.5);
}

/// dK / d rx (N/m^2.5) at fixed ry, by the chain rule through alpha and R (the formulas above).
inline double point_stiffness_derivative(double rx, double ry, double e_star) {
  constexpr double q = std::numbers::pi / 2 - 1;
  const Ellipse e = ellipse(rx, ry);
  const double alpha = e.major_along_y ? ry / rx : rx / ry;
  const double dalpha = e.major_along_y ? -ry / (rx * rx) : 1.0 / ry;  // d alpha / d rx
  // ln K = ln k + ln(E') + (ln Ee + ln R) / 2 - 1.5 ln Fe + const
  const double dlnk = 2 / std::numbers::pi / alpha * dalpha;
  const double dlnee = -q / (alpha * alpha) / e.ee * dalpha;
  const double dlnfe = q / alpha / e.fe * dalpha;
  const double dlnr = e.r / (rx * rx);  // R = 1 / (1/rx + 1/ry): dR/drx = R^2 / rx^2
  return point_stiffness(rx, ry, e_star) * (dlnk + 0.5 * (dlnee + dlnr) - 1.5 * dlnfe);
}

/// The semi-axes along x and y (m) and the maximum pressure (Pa) under force f (N).
struct PointContact {
  double ax = 0, ay = 0, p0 = 0;
};
inline PointContact point_contact(double f, double rx, double ry, double e_star) {
  if (f <= 0) return {};
  const Ellipse e = ellipse(rx, ry);
  const double e_prime = 2 * e_star;
  const double major = std::cbrt(6 * e.k * e.k * e.ee * f * e.r / (std::numbers::pi * e_prime));
  const double minor = std::cbrt(6 * e.ee * f * e.r / (std::numbers::pi * e.k * e_prime));
  PointContact c;
  c.ax = e.major_along_y ? minor : major;
  c.ay = e.major_along_y ? major : minor;
  c.p0 = 3 * f / (2 * std::numbers::pi * c.ax * c.ay);
  return c;
}

}  // namespace nvh::solve::hertz
