#include "solve/bearing/short_bearing.hpp"

#include <cmath>
#include <numbers>

#include "solve/bearing/film_quadrature.hpp"

namespace nvh::bearing {

namespace {
constexpr double kPi = std::numbers::pi;
}

FilmResult evaluate_short(const BearingSpec& spec, const Kinematics& k, Detail detail) {
  check_eccentricity(spec, k);
  const double R = spec.radius(), L = spec.width, c = spec.radial_clearance, mu = spec.viscosity;
  const double ex = k.e.x(), ey = k.e.y(), vx = k.e_dot.x(), vy = k.e_dot.y();
  const double wm = 0.5 * (k.omega_journal + k.omega_shell);
  const double A = wm * ex - vy, B = wm * ey + vx;
  const double rho = std::hypot(A, B);
  const double beta = std::atan2(B, A);

  FilmResult r;
  set_min_film(spec, k, r);
  const double K = mu * R * L * L * L;  // int p dz = -mu L^3 G / h^3

  // Loaded half circle (G < 0): force, Jacobian and the pressure part of the friction torque.
  double pressure_torque = 0;  // int G h_theta / h^3 d theta
  if (rho > 0) {
    integrate_film(c, ex, ey, beta - kPi, beta, [&](const FilmPoint& q) {
      const double cs = q.cos_theta, sn = q.sin_theta;
      const double G = A * sn - B * cs;
      const double h3 = q.h * q.h * q.h, h4 = h3 * q.h;
      const double w = q.weight * K;
      r.force += w * G / h3 * Eigen::Vector2d(cs, sn);
      const Eigen::Vector2d n(cs, sn);
      r.jacobian.col(0) += w * (wm * sn / h3 + 3 * G * cs / h4) * n;
      r.jacobian.col(1) += w * (-wm * cs / h3 + 3 * G * sn / h4) * n;
      r.jacobian.col(2) += w * (-cs / h3) * n;
      r.jacobian.col(3) += w * (-sn / h3) * n;
      pressure_torque += q.weight * G * (ex * sn - ey * cs) / h3;
    });
  }
  // Couette shear over the full circle: int d theta / h = 2 pi / (c sqrt(1 - eps^2)).
  const double eps = k.e.norm() / c;
  const double couette = mu * R * R * R * L * 2 * kPi / (c * std::sqrt(1 - eps * eps));
  const double pressure_part = -0.5 * R * mu * L * L * L * pressure_torque;
  r.torque_journal = couette * (k.omega_shell - k.omega_journal) + pressure_part;
  r.torque_shell = couette * (k.omega_journal - k.omega_shell) + pressure_part;

  // Peak pressure on the mid-plane: max of -G / h^3 over the loaded half, (1.5 mu L^2) times it.
  if (rho > 0 && detail == Detail::kFull) {
    auto minus_g_h3 = [&](double t) {
      const double h = c - ex * std::cos(t) - ey * std::sin(t);
      return -(A * std::sin(t) - B * std::cos(t)) / (h * h * h);
    };
    double best = beta - kPi, best_value = 0;
    const int n = 720;
    for (int i = 1; i < n; ++i) {
      const double t = beta - kPi + kPi * i / n;
      const double v = minus_g_h3(t);
      if (v > best_value) best_value = v, best = t;
    }
    double a = best - kPi / n, b = best + kPi / n;  // golden-section refinement of the bracket
    const double gr = 0.5 * (std::sqrt(5.0) - 1);
    for (int i = 0; i < 60; ++i) {
      const double x1 = b - gr * (b - a), x2 = a + gr * (b - a);
      if (minus_g_h3(x1) > minus_g_h3(x2))
        b = x2;
      else
        a = x1;
    }
    const double t = 0.5 * (a + b);
    r.max_pressure = 1.5 * mu * L * L * minus_g_h3(t);
    r.max_pressure_angle = std::remainder(t, 2 * kPi);
  }
  r.side_flow = 2 * rho * R * L;
  r.feed_flow = r.side_flow;
  r.power_loss =
      -(r.torque_journal * k.omega_journal + r.torque_shell * k.omega_shell + r.force.dot(k.e_dot));
  return r;
}

}  // namespace nvh::bearing
