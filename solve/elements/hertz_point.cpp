// Hertz's exact elliptical point contact (hertz_point.hpp; Johnson 1985 section 4.2, the equations H1-H3
// written out in the header).
#include "solve/elements/hertz_point.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace nvh::solve::hertz {
namespace {

constexpr double kPi = std::numbers::pi;

/// K(m), D(m) = (K - E)/m and their derivatives by the parameter m = e^2; q = 1 - m given separately so
/// that it keeps its relative precision near m = 1.
struct Integrals {
  double k = 0, d = 0, dk = 0, dd = 0;
};

Integrals integrals(double m, double q) {
  Integrals r;
  const double e = std::sqrt(m);
  r.k = std::comp_ellint_1(e);
  if (m < 0.25) {
    // D = pi/2 sum_{n>=1} c_n^2 2n/(2n-1) m^(n-1), c_n = c_(n-1) (2n-1)/(2n) (Byrd & Friedman 900.07);
    // terms fall at least as fast as m^n: 40 terms reach 1e-24 at m = 1/4.
    double c = 1, power = 1, power_d = 0, sum = 0, sum_d = 0;  // power = m^(n-1), power_d = (n-1) m^(n-2)
    for (int n = 1; n <= 40; ++n) {
      c *= (2.0 * n - 1) / (2.0 * n);
      const double coef = c * c * 2.0 * n / (2.0 * n - 1);
      sum += coef * power;
      sum_d += coef * power_d;
      if (coef * power < 1e-18 * sum && n > 2) break;
      power_d = n * power;
      power *= m;
    }
    r.d = kPi / 2 * sum;
    r.dd = kPi / 2 * sum_d;
  } else {
    const double ee = std::comp_ellint_2(e);
    r.d = (r.k - ee) / m;
    r.dd = (r.k - (2 - m) * r.d) / (2 * m * q);  // Byrd & Friedman 710.02 through D
  }
  r.dk = (r.k - r.d) / (2 * q);  // Byrd & Friedman 710.00: (E - (1 - m) K) / (2 m (1 - m))
  return r;
}

/// d ln g / dm of (H1): g = (K - D) / ((1 - m) D).
double dln_ratio(const Integrals& v, double q) {
  return (v.dk - v.dd) / (v.k - v.d) + 1 / q - v.dd / v.d;
}

/// The dimensionless ellipse (H2) and its s-derivatives at m (q = 1 - m) for ratio r.
EllipseShape shape_at(double r, double m, double q) {
  const Integrals v = integrals(m, q);
  EllipseShape s;
  s.ratio = r;
  s.m = m;
  s.a_star = std::cbrt(2 * v.d * (1 + r) / kPi);
  s.b_star = s.a_star * std::sqrt(q);
  s.delta_star = 2 * v.k / (kPi * s.a_star);
  const double dm_ds = 1 / dln_ratio(v, q);  // s = ln r = ln g(m)
  s.dln_a = (v.dd / v.d * dm_ds + r / (1 + r)) / 3;
  s.dln_b = s.dln_a - dm_ds / (2 * q);
  s.dln_delta = v.dk / v.k * dm_ds - s.dln_a;
  return s;
}

}  // namespace

double EllipseShape::ellipticity() const {
  return a_star / b_star;
}

EllipseShape ellipse_shape(double ratio) {
  if (!(ratio >= 1) || !std::isfinite(ratio))
    throw std::invalid_argument(
        "hertz::ellipse_shape: the radius ratio Rmax/Rmin must be finite and >= 1, got " +
        std::to_string(ratio));
  if (ratio == 1) return shape_at(1, 0, 1);
  const double target = std::log(ratio);
  // h(x) = ln g(m(x)) - ln r, x = ln(a/b), m = 1 - exp(-2x): h(0) = -ln r < 0 and h rises with slope 1.5 (x
  // -> 0) .. 2 (x -> inf), so the root lies in (0, ln r].
  double lo = 0, hi = target;
  double x = std::clamp(2 / kPi * target, lo, hi);  // Hamrock & Brewe's a/b = r^(2/pi)
  for (int it = 0; it < 100; ++it) {
    const double q = std::exp(-2 * x), m = -std::expm1(-2 * x);
    const Integrals v = integrals(m, q);
    const double h = std::log((v.k - v.d) / (q * v.d)) - target;
    if (h == 0) break;
    (h < 0 ? lo : hi) = x;
    const double slope = dln_ratio(v, q) * 2 * q;  // dh/dx
    double next = x - h / slope;
    if (!(next >= lo && next <= hi)) next = 0.5 * (lo + hi);  // Newton left the bracket: bisect
    const double step = next - x;
    x = next;
    // Newton converges quadratically (measured: error_{n+1} ~ 0.02 error_n^2): after a step below 1e-7 x the
    // error is at round-off
    if (std::abs(step) <= 1e-7 * x + 1e-16 || hi - lo <= 1e-15 * hi) break;
  }
  return shape_at(ratio, -std::expm1(-2 * x), std::exp(-2 * x));
}

EllipseTable::EllipseTable(double max_ratio, int intervals)
    : max_ratio_(max_ratio), step_(std::log(max_ratio) / intervals) {
  nodes_.reserve(intervals + 1);
  for (int i = 0; i <= intervals; ++i) {
    const EllipseShape s = ellipse_shape(i == intervals ? max_ratio : std::exp(i * step_));
    nodes_.push_back(
        {std::log(s.a_star), std::log(s.b_star), std::log(s.delta_star), s.dln_a, s.dln_b, s.dln_delta});
  }
}

EllipseShape EllipseTable::operator()(double ratio) const {
  if (!(ratio >= 1) || ratio > max_ratio_) return ellipse_shape(ratio);
  const double s = std::log(ratio);
  const std::size_t i = std::min(static_cast<std::size_t>(s / step_), nodes_.size() - 2);
  const double t = s / step_ - double(i), h = step_;
  // cubic Hermite basis and its t-derivative
  const double h00 = (1 + 2 * t) * (1 - t) * (1 - t), h10 = t * (1 - t) * (1 - t), h01 = t * t * (3 - 2 * t),
               h11 = t * t * (t - 1);
  const double d00 = 6 * t * (t - 1), d10 = (1 - t) * (1 - 3 * t), d01 = -d00, d11 = t * (3 * t - 2);
  const auto& y0 = nodes_[i];
  const auto& y1 = nodes_[i + 1];
  double value[3], slope[3];
  for (int k = 0; k < 3; ++k) {
    value[k] = h00 * y0[k] + h10 * h * y0[k + 3] + h01 * y1[k] + h11 * h * y1[k + 3];
    slope[k] = (d00 * y0[k] + d01 * y1[k]) / h + d10 * y0[k + 3] + d11 * y1[k + 3];
  }
  EllipseShape e;
  e.ratio = ratio;
  e.a_star = std::exp(value[0]);
  e.b_star = std::exp(value[1]);
  e.delta_star = std::exp(value[2]);
  e.m = -std::expm1(2 * (value[1] - value[0]));
  e.dln_a = slope[0];
  e.dln_b = slope[1];
  e.dln_delta = slope[2];
  return e;
}

EllipseShape PointLaw::shape(double rx, double ry) const {
  return table_(rx >= ry ? rx / ry : ry / rx);
}

double PointLaw::stiffness(double rx, double ry) const {
  const double sigma = 1 / rx + 1 / ry;
  return 4.0 / 3.0 * e_star_ * std::sqrt(2 / sigma) * std::pow(shape(rx, ry).delta_star, -1.5);
}

double PointLaw::stiffness_derivative(double rx, double ry) const {
  // ln K_h = ln(4/3 E* sqrt 2) - ln(Sigma rho) / 2 - 1.5 ln delta*(s), s = |ln rx - ln ry|
  const double sigma = 1 / rx + 1 / ry;
  const EllipseShape e = shape(rx, ry);
  const double ds = (rx >= ry ? 1.0 : -1.0) / rx;
  const double k = 4.0 / 3.0 * e_star_ * std::sqrt(2 / sigma) * std::pow(e.delta_star, -1.5);
  return k * (0.5 / (rx * rx * sigma) - 1.5 * e.dln_delta * ds);
}

PointContact point_contact(double f, double rx, double ry, double e_star, const EllipseShape& shape) {
  if (f <= 0) return {};
  const double sigma = 1 / rx + 1 / ry;
  const double scale = std::cbrt(3 * f / (2 * sigma * e_star));
  const double major = shape.a_star * scale, minor = shape.b_star * scale;
  PointContact c;
  c.ax = ry >= rx ? minor : major;  // the major semi-axis along the larger radius
  c.ay = ry >= rx ? major : minor;
  c.p0 = 3 * f / (2 * kPi * c.ax * c.ay);
  return c;
}

}  // namespace nvh::solve::hertz
