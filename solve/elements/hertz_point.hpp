#pragma once
// Elliptical point contact of two bodies whose principal planes of curvature coincide (a crowned roller on a
// cam: the rolling plane and the roller's axial plane): Hertz's exact solution - the contact ellipse's
// eccentricity from the ratio of the principal relative curvatures through the complete elliptic integrals,
// the force-approach law F = K delta^1.5, the semi-axes and the maximum pressure.
//
// K. L. Johnson, Contact Mechanics, Cambridge 1985, section 4.2, eqs. 4.39-4.41. Relative radii Rx, Ry (m) in
// the two principal planes (1/Rx = 1/R1x + 1/R2x, a concave radius negative; both must be > 0), principal
// relative curvatures A = 1/(2 Rmax) <= B = 1/(2 Rmin), radius ratio r = B/A = Rmax/Rmin >= 1, sum of the
// curvatures Sigma rho = 1/Rx + 1/Ry = 2 (A + B), contact modulus E*, load P. The major semi-axis a lies
// along the larger radius, e^2 = m = 1 - b^2/a^2, K = K(e), E = E(e) (modulus e, std::comp_ellint_1/2):
//   B/A = ((a/b)^2 E - K) / (K - E)                                        (Johnson 4.39a/b, divided)
//   a^3 = 3 P (K - E) / (2 pi E* e^2 A),  b = a sqrt(1 - e^2)              (4.39a with p0 = 3P/(2 pi a b))
//   delta = p0 b K / E*,  p0 = 3 P / (2 pi a b)                            (4.40, 4.41)
// With D = (K - E)/m (= int_0^(pi/2) sin^2 / sqrt(1 - m sin^2); Byrd & Friedman 1971, 710.00/315.02) the
// ratio reads without cancellation: E - (1 - m) K = m (K - D), so
//   r = g(m) = (K - D) / ((1 - m) D)                                       (H1)
// and, in the dimensionless form of T. A. Harris and M. N. Kotzalas, Rolling Bearing Analysis, 5th ed.
// 2007, eqs. 6.39-6.41 (a = a* s, b = b* s, delta = delta* s^2 Sigma rho / 2, s = (3P / (2 Sigma rho
// E*))^(1/3)), with A = Sigma rho / (2 (1 + r)):
//   a*^3 = 2 D (1 + r) / pi,   b* = a* sqrt(1 - m),   delta* = 2 K / (pi a*)  (H2)
//   F(delta) = K_h delta^1.5,  K_h = 4/3 E* sqrt(2 / Sigma rho) delta*^-1.5  (H3)
// At r = 1 (m = 0, K = pi/2, D = pi/4) a* = b* = delta* = 1 and (H3) is Hertz's sphere on a flat,
// F = 4/3 E* sqrt(R') delta^1.5, R' = Rx = Ry. The ellipticity depends on the geometry only, not on the load.
//
// m(r) is found by a safeguarded Newton iteration on x = ln(a/b) (m = 1 - exp(-2x); h(x) = ln g - ln r rises
// with a slope between 1.5 and 3), started from Hamrock and Brewe's a/b = r^(2/pi) (J. Lubrication Technology
// 105, 1983, 171-177), bracketed by bisection. Derivatives for the Newton step and for dK_h/dRx (Byrd &
// Friedman 710.00, 710.02): dK/dm = (K - D) / (2 (1 - m)), dD/dm = (K - (2 - m) D) / (2 m (1 - m)); for
// m < 1/4 D and dD/dm come from their power series (Byrd & Friedman 900.00/900.07:
// D = pi/2 sum_{n>=1} c_n^2 2n/(2n-1) m^(n-1), c_n = (2n)! / (2^(2n) n!^2)), avoiding K - E's cancellation.
//
// A roller on a cam changes r at every evaluation (the cam's radius of curvature varies along the profile):
// EllipseTable holds ln a*, ln b*, ln delta* against s = ln r at nodes of the exact solution with their exact
// derivatives, and interpolates by cubic Hermite (39 ns against 1.4 us of CPU for the Newton solve; the
// interpolation error, 2e-10 relative at most, is measured in tests/solve/test_hertz_ellipse.cpp).
#include <array>
#include <vector>

namespace nvh::solve::hertz {

/// Hertz's ellipse for a radius ratio r = Rmax / Rmin >= 1, dimensionless (H1, H2), and the logarithmic
/// derivatives of a*, b*, delta* by s = ln r.
struct EllipseShape {
  double ratio = 1;  // r
  double m = 0;      // e^2 = 1 - (b/a)^2
  double a_star = 1, b_star = 1, delta_star = 1;
  double dln_a = 0, dln_b = 0, dln_delta = 0;  // d ln(a*) / ds etc., s = ln r
  double ellipticity() const;                  // a / b
};

/// The exact solution (Newton on the eccentricity). Throws std::invalid_argument for r < 1 or not finite.
EllipseShape ellipse_shape(double ratio);

/// Cubic Hermite interpolation of ellipse_shape in s = ln r over [0, ln max_ratio] (exact at r = 1); beyond
/// max_ratio the exact solution. Built once (nodes solved at construction), then shared read-only.
class EllipseTable {
 public:
  explicit EllipseTable(double max_ratio = 1e4, int intervals = 256);
  EllipseShape operator()(double ratio) const;
  double max_ratio() const { return max_ratio_; }

 private:
  double max_ratio_, step_;
  std::vector<std::array<double, 6>> nodes_;  // ln a*, ln b*, ln delta* and their s-derivatives
};

/// The contact of radii rx, ry (m, > 0) with contact modulus E* (Pa), its shape from its own EllipseTable.
class PointLaw {
 public:
  explicit PointLaw(double e_star) : e_star_(e_star) {}
  /// The ellipse of radii rx, ry (interpolated).
  EllipseShape shape(double rx, double ry) const;
  /// K_h (N/m^1.5) of F = K_h delta^1.5 (H3).
  double stiffness(double rx, double ry) const;
  /// dK_h / d rx (N/m^2.5) at fixed ry.
  double stiffness_derivative(double rx, double ry) const;
  double e_star() const { return e_star_; }

 private:
  double e_star_;
  EllipseTable table_;
};

/// The semi-axes along x and y (m) and the maximum pressure (Pa) under force f (N) (H2).
struct PointContact {
  double ax = 0, ay = 0, p0 = 0;
};
PointContact point_contact(double f, double rx, double ry, double e_star, const EllipseShape& shape);

}  // namespace nvh::solve::hertz
