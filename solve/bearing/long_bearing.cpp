#include "solve/bearing/long_bearing.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "solve/bearing/film_quadrature.hpp"

namespace nvh::bearing {

namespace {

constexpr double kPi = std::numbers::pi;

/// The closed-form long-bearing film for one motion.
struct LongFilm {
  double c, ex, ey, A, B, C = 0, scale;  // scale = 12 mu R^2
  double theta0;                         // maximum film: p = 0 there

  LongFilm(const BearingSpec& s, const Kinematics& k) : c(s.radial_clearance), ex(k.e.x()), ey(k.e.y()) {
    const double wm = 0.5 * (k.omega_journal + k.omega_shell);
    A = wm * ex - k.e_dot.y();
    B = wm * ey + k.e_dot.x();
    scale = 12 * s.viscosity * s.radius() * s.radius();
    theta0 = (ex == 0 && ey == 0 ? 0.0 : std::atan2(ey, ex)) + kPi;
    double ig = 0, i1 = 0;
    integrate_film(c, ex, ey, theta0, theta0 + 2 * kPi, [&](const FilmPoint& q) {
      const double h3 = q.h * q.h * q.h;
      ig += q.weight * gamma(q) / h3;
      i1 += q.weight / h3;
    });
    C = -ig / i1;
  }
  double gamma(const FilmPoint& q) const { return -A * q.cos_theta - B * q.sin_theta; }
  double h(double t) const { return c - ex * std::cos(t) - ey * std::sin(t); }
  double dp(double t) const {
    const double hh = h(t);
    return scale * (-A * std::cos(t) - B * std::sin(t) + C) / (hh * hh * hh);
  }
  /// p(b) - p(a), exact.
  double rise(double a, double b) const {
    if (b == a) return 0;
    double s = 0;
    const double lo = std::min(a, b), hi = std::max(a, b);
    integrate_film(c, ex, ey, lo, hi,
                   [&](const FilmPoint& q) { s += q.weight * (gamma(q) + C) / (q.h * q.h * q.h); });
    return (b > a ? 1 : -1) * scale * s;
  }
};

struct Closed {
  Eigen::Vector2d force = Eigen::Vector2d::Zero();
  double pressure_torque = 0, max_pressure = 0, max_angle = 0;
};

Closed solve_closed(const BearingSpec& spec, const Kinematics& k) {
  const LongFilm f(spec, k);
  Closed out;
  const double R = spec.radius(), L = spec.width;
  // p on a subdivision of one turn starting at the maximum film (p = 0 there), then the positive intervals.
  const int n = 720;
  std::vector<double> t(n + 1), p(n + 1);
  for (int i = 0; i <= n; ++i) t[i] = f.theta0 + 2 * kPi * i / n;
  p[0] = 0;
  for (int i = 1; i <= n; ++i) p[i] = p[i - 1] + f.rise(t[i - 1], t[i]);
  p[n] = 0;                    // periodic by construction of C
  auto zero_in = [&](int i) {  // p changes sign in [t_i, t_i+1]: Newton from the secant point
    double x = t[i] - p[i] * (t[i + 1] - t[i]) / (p[i + 1] - p[i]);
    for (int it = 0; it < 8; ++it) {
      const double px = p[i] + f.rise(t[i], x), d = f.dp(x);
      if (d == 0) break;
      const double nx = std::clamp(x - px / d, t[i], t[i + 1]);
      if (std::abs(nx - x) < 1e-15) break;
      x = nx;
    }
    return x;
  };
  double begin = t[0];
  for (int i = 0; i < n; ++i) {
    const bool a = p[i] > 0, b = p[i + 1] > 0;  // p[0] = p[n] = 0: every interval closes
    if (!a && b) begin = zero_in(i);
    if (a && !b) {
      integrate_film(f.c, f.ex, f.ey, begin, zero_in(i), [&](const FilmPoint& q) {
        const double g = (f.gamma(q) + f.C) / (q.h * q.h * q.h);
        out.force += q.weight * g * Eigen::Vector2d(q.sin_theta, -q.cos_theta);
        out.pressure_torque += q.weight * (f.gamma(q) + f.C) / (q.h * q.h);
      });
    }
    if (p[i] > out.max_pressure) out.max_pressure = p[i], out.max_angle = t[i];
  }
  out.force *= f.scale * R * L;
  out.pressure_torque *= -0.5 * R * L * f.scale;
  // The peak: p' = 0 where Gamma + C = 0; refine around the best sample by golden section.
  if (out.max_pressure > 0) {
    double a = out.max_angle - 2 * kPi / n, b = out.max_angle + 2 * kPi / n;
    const double t0 = out.max_angle, p0 = out.max_pressure;
    auto pr = [&](double x) { return p0 + f.rise(t0, x); };
    const double gr = 0.5 * (std::sqrt(5.0) - 1);
    for (int i = 0; i < 50; ++i) {
      const double x1 = b - gr * (b - a), x2 = a + gr * (b - a);
      if (pr(x1) > pr(x2))
        b = x2;
      else
        a = x1;
    }
    out.max_angle = 0.5 * (a + b);
    out.max_pressure = pr(out.max_angle);
  }
  return out;
}

}  // namespace

double long_bearing_pressure(const BearingSpec& spec, const Kinematics& k, double theta) {
  const LongFilm f(spec, k);
  const double t = f.theta0 + std::fmod(theta - f.theta0 + 4 * kPi, 2 * kPi);
  return f.rise(f.theta0, t);
}

FilmResult evaluate_long(const BearingSpec& spec, const Kinematics& k) {
  check_eccentricity(spec, k);
  const double R = spec.radius(), L = spec.width, c = spec.radial_clearance, mu = spec.viscosity;
  const Closed s = solve_closed(spec, k);
  FilmResult r;
  set_min_film(spec, k, r);
  r.force = s.force;
  const double eps = k.e.norm() / c;
  const double couette = mu * R * R * R * L * 2 * kPi / (c * std::sqrt(1 - eps * eps));
  r.torque_journal = couette * (k.omega_shell - k.omega_journal) + s.pressure_torque;
  r.torque_shell = couette * (k.omega_journal - k.omega_shell) + s.pressure_torque;
  r.max_pressure = s.max_pressure;
  r.max_pressure_angle = std::remainder(s.max_angle, 2 * kPi);
  r.power_loss =
      -(r.torque_journal * k.omega_journal + r.torque_shell * k.omega_shell + r.force.dot(k.e_dot));
  // Jacobian by central differences of the closed form.
  const double wm = std::abs(0.5 * (k.omega_journal + k.omega_shell));
  const double de = 1e-6 * c;
  const double dv = 1e-6 * c * std::max({wm, k.e_dot.norm() / c, 1.0});
  for (int q = 0; q < 4; ++q) {
    Kinematics plus = k, minus = k;
    const double step = q < 2 ? de : dv;
    (q < 2 ? plus.e : plus.e_dot)[q % 2] += step;
    (q < 2 ? minus.e : minus.e_dot)[q % 2] -= step;
    r.jacobian.col(q) = (solve_closed(spec, plus).force - solve_closed(spec, minus).force) / (2 * step);
  }
  return r;
}

}  // namespace nvh::bearing
