// The closed-form bearings (short, long) against published closed forms.
//
// References (none computed with this code):
// - Ocvirk short bearing, steady: W = mu U L^3 / (4 c^2) eps / (1 - eps^2)^2 sqrt(pi^2 (1 - eps^2) + 16
// eps^2),
//   tan(attitude) = pi sqrt(1 - eps^2) / (4 eps); Dubois and Ocvirk, NACA Report 1157 (1953); also Hamrock,
//   Schmid and Jacobson, Fundamentals of Fluid Film Lubrication, 2nd ed. (2004), eqs. 12.62-12.66.
// - Short-bearing stiffness and damping (load W along -Y, rotation from X to Y), nondimensional K c / W and
//   C c omega / W with A0 = [pi^2 (1 - eps^2) + 16 eps^2]^(-3/2) (Childs, Turbomachinery Rotordynamics,
//   Wiley 1993, sec. 3.5; the same forms are used by the ROSS rotordynamics package):
//     kxx = 4 A0 [2 pi^2 + (16 - pi^2) eps^2]
//     kxy = pi A0 [pi^2 (1 - eps^2)^2 - 16 eps^4] / (eps sqrt(1 - eps^2))
//     kyx = -pi A0 [pi^2 + (32 + pi^2) eps^2 + (32 - 2 pi^2) eps^4] / (eps sqrt(1 - eps^2))
//     kyy = 4 A0 [pi^2 + (32 + pi^2) eps^2 + (32 - 2 pi^2) eps^4] / (1 - eps^2)
//     cxx = 2 pi sqrt(1 - eps^2) [pi^2 + 2 (pi^2 - 8) eps^2] A0 / eps,  cxy = cyx = -8 A0 [pi^2 + 2 (pi^2 -
//     8) eps^2] cyy = 2 pi A0 [pi^2 + 2 (24 - pi^2) eps^2 + pi^2 eps^4] / (eps sqrt(1 - eps^2))
// - Long bearing, half-Sommerfeld (Guembel), steady (Hamrock et al. 2004, eqs. 12.27-12.30 with U = omega R):
//     W_r = 12 mu U R^2 L eps^2 / (c^2 (2 + eps^2)(1 - eps^2)),  W_t = 6 pi mu U R^2 L eps / (c^2 (2 + eps^2)
//     sqrt(1 - eps^2))
// - Short bearing pure squeeze: p = 6 mu dh/dt / h^3 (z^2 - L^2/4) where dh/dt < 0, integrated here by a
//   20000-panel Simpson rule in the test (an independent quadrature of the textbook pressure).
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <numbers>
#include <vector>

#include "solve/bearing/long_bearing.hpp"
#include "solve/bearing/short_bearing.hpp"

namespace nvh::bearing {
namespace {

constexpr double kPi = std::numbers::pi;

BearingSpec test_bearing(Model model, double l_over_d) {
  BearingSpec s;
  s.model = model;
  s.diameter = 0.06;
  s.width = l_over_d * s.diameter;
  s.radial_clearance = 30e-6;
  s.viscosity = 0.02;
  return s;
}

TEST(bearing_short, OcvirkLoadAndAttitude) {
  const BearingSpec s = test_bearing(Model::kShort, 0.25);
  const double w = 300, U = w * s.radius(), L = s.width, c = s.radial_clearance;
  for (double eps : {0.05, 0.3, 0.6, 0.9, 0.99}) {
    Kinematics k;
    k.e = {eps * c, 0};
    k.omega_journal = w;
    const FilmResult r = evaluate_short(s, k);
    const double W = s.viscosity * U * L * L * L / (4 * c * c) * eps / std::pow(1 - eps * eps, 2) *
                     std::sqrt(kPi * kPi * (1 - eps * eps) + 16 * eps * eps);
    const double attitude = std::atan(kPi * std::sqrt(1 - eps * eps) / (4 * eps));
    EXPECT_NEAR(r.force.norm() / W, 1.0, 1e-12) << "eps " << eps;
    EXPECT_NEAR(std::atan2(r.force.y(), -r.force.x()), attitude, 1e-12) << "eps " << eps;
    EXPECT_NEAR(r.side_flow / (eps * c * U * L), 1.0, 1e-12);  // Q = eps c U L
  }
}

TEST(bearing_short, StiffnessAndDampingAgainstChilds) {
  const BearingSpec s = test_bearing(Model::kShort, 0.3);
  const double w = 400, c = s.radial_clearance;
  for (double eps : {0.1, 0.3, 0.5, 0.7, 0.9}) {
    Kinematics k;
    k.e = {eps * c, 0};
    k.omega_journal = w;
    const FilmResult r = evaluate_short(s, k);
    // Frame of the reference: Y along the film force (load W along -Y), X = Y turned by -90 deg.
    const double W = r.force.norm();
    const Eigen::Vector2d Y = r.force / W, X(Y.y(), -Y.x());
    Eigen::Matrix2d T;
    T << X.transpose(), Y.transpose();
    const Eigen::Matrix2d K = -T * r.jacobian.leftCols<2>() * T.transpose() * c / W;
    const Eigen::Matrix2d C = -T * r.jacobian.rightCols<2>() * T.transpose() * c * w / W;
    const double p2 = kPi * kPi, e2 = eps * eps, se = std::sqrt(1 - e2);
    const double A0 = std::pow(p2 * (1 - e2) + 16 * e2, -1.5);
    Eigen::Matrix2d Kref, Cref;
    Kref << 4 * A0 * (2 * p2 + (16 - p2) * e2),
        kPi * A0 * (p2 * std::pow(1 - e2, 2) - 16 * e2 * e2) / (eps * se),
        -kPi * A0 * (p2 + (32 + p2) * e2 + (32 - 2 * p2) * e2 * e2) / (eps * se),
        4 * A0 * (p2 + (32 + p2) * e2 + (32 - 2 * p2) * e2 * e2) / (1 - e2);
    const double cxy = -8 * A0 * (p2 + 2 * (p2 - 8) * e2);
    Cref << 2 * kPi * se * (p2 + 2 * (p2 - 8) * e2) * A0 / eps, cxy, cxy,
        2 * kPi * A0 * (p2 + 2 * (24 - p2) * e2 + p2 * e2 * e2) / (eps * se);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) {
        EXPECT_NEAR(K(i, j), Kref(i, j), 1e-9 * Kref.norm()) << "K" << i << j << " eps " << eps;
        EXPECT_NEAR(C(i, j), Cref(i, j), 1e-9 * Cref.norm()) << "C" << i << j << " eps " << eps;
      }
  }
}

TEST(bearing_short, PureSqueezeAgainstQuadrature) {
  // Journal approaching the shell along x at eps = 0.5 without rotation: the loaded half is cos(theta) > 0.
  const BearingSpec s = test_bearing(Model::kShort, 0.4);
  const double c = s.radial_clearance, eps = 0.5, v = 0.01, R = s.radius(), L = s.width;
  Kinematics k;
  k.e = {eps * c, 0};
  k.e_dot = {v, 0};
  const FilmResult r = evaluate_short(s, k);
  // F_x = -R int int p cos = -R int (-mu L^3 h_t / h^3) cos, h_t = -v cos theta, over cos > 0.
  const int n = 20000;
  double sum = 0;
  for (int i = 0; i <= n; ++i) {
    const double t = -kPi / 2 + kPi * i / n;
    const double h = c * (1 - eps * std::cos(t));
    const double f = -std::pow(std::cos(t), 2) / (h * h * h);
    sum += f * (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2));
  }
  const double Fx = s.viscosity * R * L * L * L * v * sum * (kPi / n) / 3;
  EXPECT_NEAR(r.force.x() / Fx, 1.0, 1e-9);
  EXPECT_NEAR(r.force.y(), 0.0, 1e-9 * std::abs(Fx));
}

TEST(bearing_long, GuembelLoadAgainstClosedForm) {
  const BearingSpec s = test_bearing(Model::kLong, 1.0);
  const double w = 200, U = w * s.radius(), R = s.radius(), L = s.width, c = s.radial_clearance;
  const double mu = s.viscosity;
  for (double eps : {0.1, 0.4, 0.7, 0.95}) {
    Kinematics k;
    k.e = {0, -eps * c};  // journal displaced downwards
    k.omega_journal = w;
    const FilmResult r = evaluate_long(s, k);
    const double Wr = 12 * mu * U * R * R * L * eps * eps / (c * c * (2 + eps * eps) * (1 - eps * eps));
    const double Wt =
        6 * kPi * mu * U * R * R * L * eps / (c * c * (2 + eps * eps) * std::sqrt(1 - eps * eps));
    // The film pushes the journal back along the line of centres and forward, 90 deg ahead of it.
    const Eigen::Vector2d er = k.e / k.e.norm(), et(-er.y(), er.x());
    EXPECT_NEAR(-r.force.dot(er) / Wr, 1.0, 1e-9) << "eps " << eps;
    EXPECT_NEAR(r.force.dot(et) / Wt, 1.0, 1e-9) << "eps " << eps;
  }
}

TEST(bearing_closed_forms, FrictionTorquesBalanceTheFilmMoment) {
  // Moment balance of the film about the shell centre: Tj + Ts + (e x F)_z = 0 (docs/bearing.md).
  for (Model model : {Model::kShort, Model::kLong}) {
    const BearingSpec s = test_bearing(model, 0.5);
    Kinematics k;
    k.e = {0.3 * s.radial_clearance, -0.5 * s.radial_clearance};
    k.e_dot = {0.002, 0.001};
    k.omega_journal = 250;
    k.omega_shell = -40;
    const FilmResult r = model == Model::kShort ? evaluate_short(s, k) : evaluate_long(s, k);
    const double exf = k.e.x() * r.force.y() - k.e.y() * r.force.x();
    EXPECT_NEAR(r.torque_journal + r.torque_shell + exf, 0.0, 1e-9 * std::abs(r.torque_journal));
  }
}

}  // namespace
}  // namespace nvh::bearing

namespace nvh::bearing {
namespace {

// A massless journal in a short bearing under a load of constant magnitude rotating with the journal
// (synchronous, as an unbalance): de/dt from the film equilibrium F(e, de/dt) = -W(t) (Booker's mobility
// idea), integrated by RK4. The orbit must close into a circle; in the frame rotating with the load the
// film sees the speed |omega_m - Omega| = omega / 2, so the radius is the static eccentricity under W at
// speed omega: Ocvirk's W(eps) inverted by bisection (the reference).
TEST(bearing_short, RotatingLoadOrbitCloses) {
  const BearingSpec s = test_bearing(Model::kShort, 0.4);
  const double w = 300, W = 800, c = s.radial_clearance, U = w * s.radius(), L = s.width;
  auto ocvirk = [&](double eps) {
    return s.viscosity * U * L * L * L / (4 * c * c) * eps / std::pow(1 - eps * eps, 2) *
           std::sqrt(kPi * kPi * (1 - eps * eps) + 16 * eps * eps);
  };
  double lo = 0, hi = 0.999;
  for (int i = 0; i < 100; ++i) (ocvirk(0.5 * (lo + hi)) < W ? lo : hi) = 0.5 * (lo + hi);
  const double eps_ref = 0.5 * (lo + hi);

  auto velocity = [&](const Eigen::Vector2d& e, double t, Eigen::Vector2d v) {
    const Eigen::Vector2d load = W * Eigen::Vector2d(std::cos(w * t), std::sin(w * t));
    for (int it = 0; it < 50; ++it) {
      Kinematics k;
      k.e = e;
      k.e_dot = v;
      k.omega_journal = w;
      const FilmResult r = evaluate_short(s, k);
      const Eigen::Vector2d residual = r.force + load;
      v -= Eigen::Matrix2d(r.jacobian.rightCols<2>()).inverse() * residual;
      if (residual.norm() < 1e-10 * W) break;
    }
    return v;
  };
  const int steps = 400;
  const double T = 2 * kPi / w, dt = T / steps;
  Eigen::Vector2d e(0.3 * c, 0), v(0, 0);  // (at e = 0 and v = 0 there is no film force to invert)
  std::vector<Eigen::Vector2d> last_cycle, previous_cycle;
  double t = 0;
  for (int cycle = 0; cycle < 8; ++cycle) {
    previous_cycle = last_cycle;
    last_cycle.clear();
    for (int n = 0; n < steps; ++n) {
      const Eigen::Vector2d k1 = velocity(e, t, v);
      const Eigen::Vector2d k2 = velocity(e + 0.5 * dt * k1, t + 0.5 * dt, k1);
      const Eigen::Vector2d k3 = velocity(e + 0.5 * dt * k2, t + 0.5 * dt, k2);
      const Eigen::Vector2d k4 = velocity(e + dt * k3, t + dt, k3);
      e += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      v = k4;
      t += dt;
      last_cycle.push_back(e);
    }
  }
  double gap = 0, radius_error = 0;
  for (int n = 0; n < steps; ++n) {
    gap = std::max(gap, (last_cycle[n] - previous_cycle[n]).norm());
    radius_error = std::max(radius_error, std::abs(last_cycle[n].norm() / c - eps_ref));
  }
  EXPECT_LT(gap / c, 2e-5);  // measured 5.3e-6 after 8 cycles
  EXPECT_LT(radius_error, 1e-4);
  std::printf("rotating load: orbit gap between cycles 7 and 8 = %.1e c, |eps - eps_Ocvirk| = %.1e\n",
              gap / c, radius_error);
}

}  // namespace
}  // namespace nvh::bearing
