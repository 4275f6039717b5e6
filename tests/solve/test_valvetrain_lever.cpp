// The valvetrain with the paper's follower, a roller on a pivoting lever
// (testdata/valvetrain/valvetrain_lever.toml; the paper 001's eqs. 2-3, its lever ratio R_cp;
// docs/valvetrain.md section 10), run through solve at a low speed against the chain's geometry, computed
// here from the drawing and the cam's lift table alone:
//
// - the roller's centre lies on the cam's pitch curve (the profile offset by the roller's radius) less the
//   roller's Palmgren approach: in the cam's frame R_c = Q(psi) - delta n(psi), with Q(psi) = (Rb + Rr +
//   s(-psi)) (cos psi, sin psi) (a radial follower on the cam's +x axis sees s(theta): section 1's
//   convention) and n the pitch curve's outward normal; and on the circle of radius L_rp about the lever's
//   pivot. Two equations in the lever's angle beta and the pitch point's angle psi, solved by Newton;
// - the lever's cup, at L_pp on the same line, holds the pushrod's lower end; the pushrod, shortened by its
//   force over EA/L, turns the rocker by phi with |B(phi) - C(beta)| = L (as in
//   test_valvetrain_kinematics.cpp);
// - the valve follows the rocker's foot less the lash and the foot's Hertz approach (F / k)^(2/3).
//
// The forces that set the deflections are the ones the run reports; the geometry is not. What the closed form
// leaves out: the contacts' damping (their reported forces include it) and the pushrod's distributed inertia
// (its shortening is taken from the mean of its end forces), both small at 325 cam rpm.
//
// The kinematic lever scene (valvetrain_lever_kinematic.toml: the roller held on the pitch curve by the `cam`
// joint, a rigid pushrod, the foot on the tip) against the same geometry without deflections, and the cam
// joint's reaction against the chain's energy balance: with the cam angle theta the only coordinate and
// theta' = omega constant, the cam's force F on the roller's centre R does the work
//   F . dR/dtheta = dV/dtheta + (omega^2 / 2) dM/dtheta,                                      (virtual work)
// M(theta) = I_lever beta_theta^2 + I_rocker phi_theta^2 + m_valve x_theta^2 the chain's generalized mass and
// V the valve spring's and gravity's potential (Lagrange's equation of a driven one-degree-of-freedom chain).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "solve/cam/profiles.hpp"
#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::signal;
constexpr double kPi = std::numbers::pi;

// The drawing of valvetrain_lever.toml (m): the cam's axis C0, base radius and roller; the lever's pivot and
// its arms to the roller (L_rp) and the cup (L_pp), along +x at rest; the rocker's pivot P, ball arm a, foot
// arm b; the pushrod's length; the valve's rest height; the lash.
constexpr double kCamX = -0.010, kCamY = 0.030, kRb = 0.025, kRr = 0.0125;
constexpr double kLeverX = -0.060, kLeverY = 0.0675, kLrp = 0.050, kLpp = 0.060;
constexpr double kPx = 0.040, kPy = 0.3675, kA = 0.040, kB = 0.058, kLength = 0.300;
constexpr double kValveY0 = 0.2675, kLash = 0.0005;
constexpr double kPushrodRate = 4.3e7, kFootHertz = 1.5e10, kRollerWidthMm = 15;

// The lever's angle beta at cam angle theta with the roller sunk by delta into the cam (Newton on the two
// components of R_c(beta) - Q(psi) + delta n(psi), the Jacobian by central differences).
double lever_angle(const cam::CamProfile& cam, double theta, double delta, double beta0) {
  auto residual = [&](double beta, double psi) {
    const double rx = kLeverX + kLrp * std::cos(beta) - kCamX, ry = kLeverY + kLrp * std::sin(beta) - kCamY;
    const double c = std::cos(theta), s = std::sin(theta);
    const double xc = c * rx + s * ry, yc = -s * rx + c * ry;  // in the cam's frame: Rot(-theta)
    const auto l = cam.lift(-psi);
    const double r = kRb + kRr + l.s, dr = -l.ds;  // r(psi) and dr/dpsi
    const double tx = dr * std::cos(psi) - r * std::sin(psi), ty = dr * std::sin(psi) + r * std::cos(psi);
    const double tn = std::hypot(tx, ty);
    const double qx = r * std::cos(psi) - delta * ty / tn, qy = r * std::sin(psi) + delta * tx / tn;
    return std::array<double, 2>{xc - qx, yc - qy};
  };
  double beta = beta0;
  const double rx0 = kLeverX + kLrp * std::cos(beta) - kCamX, ry0 = kLeverY + kLrp * std::sin(beta) - kCamY;
  double psi = std::atan2(ry0, rx0) - theta;
  for (int it = 0; it < 60; ++it) {
    const auto f = residual(beta, psi);
    constexpr double h = 1e-7;
    const auto fb1 = residual(beta + h, psi), fb0 = residual(beta - h, psi);
    const auto fp1 = residual(beta, psi + h), fp0 = residual(beta, psi - h);
    const double j11 = (fb1[0] - fb0[0]) / (2 * h), j21 = (fb1[1] - fb0[1]) / (2 * h);
    const double j12 = (fp1[0] - fp0[0]) / (2 * h), j22 = (fp1[1] - fp0[1]) / (2 * h);
    const double det = j11 * j22 - j12 * j21;
    const double db = (f[0] * j22 - f[1] * j12) / det, dp = (j11 * f[1] - j21 * f[0]) / det;
    beta -= db, psi -= dp;
    if (std::abs(db) + std::abs(dp) < 1e-15) break;
  }
  return beta;
}

// The rocker's angle phi with the pushrod of length `length` from the cup C to the ball B(phi) = P + a (-cos
// phi, -sin phi) (Newton; phi < 0 opens the valve).
double rocker_angle(double cup_x, double cup_y, double length) {
  double phi = 0;
  for (int it = 0; it < 60; ++it) {
    const double dx = kPx - kA * std::cos(phi) - cup_x, dy = kPy - kA * std::sin(phi) - cup_y;
    const double g = dx * dx + dy * dy - length * length;
    const double g_phi = 2 * dx * kA * std::sin(phi) - 2 * dy * kA * std::cos(phi);
    const double step = g / g_phi;
    phi -= step;
    if (std::abs(step) < 1e-16) break;
  }
  return phi;
}

TEST(ValvetrainLever, TopOfTheLiftIsTheLeverChainsGeometryLessTheDeflections) {
  const std::string text =
      testing::shipped_scene("valvetrain/valvetrain_lever.toml",
                             {{"rpm = 650 ", "rpm = 325 "}, {"end_angle_deg = 760", "end_angle_deg = 300"}});
  const auto file = testing::run_text(text, "valvetrain_lever_slow", nullptr, "valvetrain");
  cam::PolynomialEvent e;  // the scene's cam
  e.lift = 0.00805, e.rise_angle = 52 * kPi / 180, e.ramp_angle = 22 * kPi / 180, e.ramp_height = 0.000333;
  e.base_radius = kRb, e.roller_radius = kRr, e.nose_angle = kPi;
  const auto cam = cam::polynomial_cam(e);

  const auto angle = signal(file, "crank_angle_deg");
  const auto y = signal(file, "bodies/valve/position", 1);
  const auto fc = signal(file, "forces/cam/normal_force"), fl = signal(file, "forces/lash/normal_force");
  const auto fi = signal(file, "forces/pushrod/force_i"), fj = signal(file, "forces/pushrod/force_j");
  Eigen::Index top = 0;
  for (Eigen::Index k = 0; k < y.size(); ++k)
    if (y[k] < y[top]) top = k;
  const double lift_top = kValveY0 - y[top];
  // Every sample with the valve open by more than 2 mm: the opening flank from 218 cam deg, the top at 270
  // and the closing flank to the run's end at 300 deg.
  double err = 0, beta = 0, deflection_top = 0, rigid_top = 0;
  int n = 0;
  for (Eigen::Index k = 0; k < y.size(); ++k) {
    const double lift = kValveY0 - y[k];
    if (lift < 0.002) continue;
    const double theta = angle[k] * kPi / 180;
    const double delta =
        3.84e-5 * std::pow(fc[k], 0.9) / std::pow(kRollerWidthMm, 0.8) * 1e-3;  // Palmgren, m
    beta = lever_angle(*cam, theta, delta, beta);
    const double cup_x = kLeverX + kLpp * std::cos(beta), cup_y = kLeverY + kLpp * std::sin(beta);
    const double shortening = 0.5 * (fi[k] + fj[k]) / kPushrodRate;
    const double phi = rocker_angle(cup_x, cup_y, kLength - shortening);
    const double expected = -kB * std::sin(phi) - kLash - std::pow(fl[k] / kFootHertz, 2.0 / 3.0);
    err = std::max(err, std::abs(lift - expected));
    ++n;
    if (k == top) {
      const double beta_rigid = lever_angle(*cam, theta, 0, beta);
      const double rigid = -kB * std::sin(rocker_angle(kLeverX + kLpp * std::cos(beta_rigid),
                                                       kLeverY + kLpp * std::sin(beta_rigid), kLength));
      rigid_top = rigid - kLash, deflection_top = rigid_top - expected;
    }
  }
  std::printf(
      "measured: valve lift at the top %.4f mm (cam angle %.2f deg); the rigid lever chain %.4f mm less "
      "deflections %.4f mm; largest error over %d samples with the valve open by more than 2 mm: %.3g um\n",
      lift_top * 1e3, angle[top], rigid_top * 1e3, deflection_top * 1e3, n, err * 1e6);
  EXPECT_GT(n, 10);
  EXPECT_NEAR(lift_top, 0.0135, 0.0005);  // m: 14.0 mm by eq. 7's ratios, less the lash and the deflections
  EXPECT_LT(err, 5e-7);  // m, of 13.4 mm (measured 0.14 um: the contacts' damping on the flanks)
}

// The rigid lever chain at cam angle theta: the lever's angle, the rocker's, the valve's opening (m).
struct LeverChain {
  double beta, phi, opening;
};
LeverChain rigid_chain(const cam::CamProfile& cam, double theta, double beta0) {
  const double beta = lever_angle(cam, theta, 0, beta0);
  const double phi = rocker_angle(kLeverX + kLpp * std::cos(beta), kLeverY + kLpp * std::sin(beta), kLength);
  return {beta, phi, -kB * std::sin(phi)};
}

TEST(ValvetrainLever, KinematicSceneIsTheRigidChainAndItsCamForceDoesTheChainsWork) {
  const std::string text = testing::shipped_scene(
      "valvetrain/valvetrain_lever_kinematic.toml",
      {{"end_angle_deg = 760", "end_angle_deg = 370"}, {"sample_rate_hz = 40000", "sample_rate_hz = 5000"}});
  const auto file = testing::run_text(text, "valvetrain_lever_kinematic");
  cam::PolynomialEvent e;  // the scene's cam
  e.lift = 0.00805, e.rise_angle = 52 * kPi / 180, e.ramp_angle = 22 * kPi / 180, e.ramp_height = 0.000333;
  e.base_radius = kRb, e.roller_radius = kRr, e.nose_angle = kPi;
  const auto cam = cam::polynomial_cam(e);
  // The scene's masses: the lever with 3/8 of the pushrod (centre of mass 43.87 mm from the pivot), the
  // rocker with 1/2 of it (centre of mass on its pivot), the valve with a third of the spring's active coils;
  // the spring's rate and free length (installed at 60 mm).
  constexpr double kLeverMass = 0.48475, kLeverArm = 0.04387,
                   kLeverI = 2.446e-4 + kLeverMass * kLeverArm * kLeverArm;
  constexpr double kRockerI = 7.0e-4, kValveMass = 0.314, kRate = 40886, kSpringFree = 0.072, kG = 9.81;
  const double omega = 650 * 2 * kPi / 60;

  const auto angle = signal(file, "crank_angle_deg");
  const auto y = signal(file, "bodies/valve/position", 1), v = signal(file, "bodies/valve/velocity", 1);
  const auto f = testing::matrix(file, "joints/cam/reaction_force");
  double err_x = 0, err_v = 0, err_w = 0, x_max = 0, v_max = 0, w_max = 0, beta = 0;
  for (Eigen::Index k = 0; k < y.size(); ++k) {
    const double theta = angle[k] * kPi / 180;
    constexpr double h = 1e-4;  // rad: central differences of the closed form in theta
    const LeverChain c = rigid_chain(*cam, theta, beta);
    const LeverChain cp = rigid_chain(*cam, theta + h, c.beta), cm = rigid_chain(*cam, theta - h, c.beta);
    beta = c.beta;
    // d/dtheta and d2/dtheta2 of the lever's and rocker's angles and of the valve's opening.
    const double b1 = (cp.beta - cm.beta) / (2 * h), b2 = (cp.beta - 2 * c.beta + cm.beta) / (h * h);
    const double p1 = (cp.phi - cm.phi) / (2 * h), p2 = (cp.phi - 2 * c.phi + cm.phi) / (h * h);
    const double x1 = (cp.opening - cm.opening) / (2 * h),
                 x2 = (cp.opening - 2 * c.opening + cm.opening) / (h * h);
    err_x = std::max(err_x, std::abs(kValveY0 - y[k] - c.opening));
    err_v = std::max(err_v, std::abs(-v[k] - x1 * omega));
    x_max = std::max(x_max, c.opening), v_max = std::max(v_max, std::abs(x1 * omega));
    // The roller's centre moves on the lever's circle: dR/dtheta = L_rp beta_theta (-sin beta, cos beta).
    const double work = f(k, 0) * -kLrp * std::sin(c.beta) * b1 + f(k, 1) * kLrp * std::cos(c.beta) * b1;
    const double spring = kRate * (kSpringFree - 0.060 + c.opening);
    const double dv =
        spring * x1 - kValveMass * kG * x1 + kLeverMass * kG * kLeverArm * std::cos(c.beta) * b1;
    const double dm = 2 * (kLeverI * b1 * b2 + kRockerI * p1 * p2 + kValveMass * x1 * x2);
    const double expected = dv + 0.5 * omega * omega * dm;
    err_w = std::max(err_w, std::abs(work - expected));
    w_max = std::max(w_max, std::abs(expected));
  }
  std::printf(
      "kinematic lever chain: largest opening %.5f mm; errors: opening %.2e m, speed %.2e m/s (of %.3f); "
      "the cam's work F.dR/dtheta against the chain's %.3g N m/rad (of %.3g)\n",
      x_max * 1e3, err_x, err_v, v_max, err_w, w_max);
  EXPECT_NEAR(x_max, 0.0140, 0.0002);  // m: 8.05 mm at the roller through R_cp 1.2 and the rocker's 1.45
  EXPECT_LT(err_x, 1e-9);              // m: the run's rtol 1e-8, atol 1e-11 (measured 6.8e-11)
  EXPECT_LT(err_v, 1e-6 * v_max);      // of 1.85 m/s (measured 1.1e-7 m/s)
  EXPECT_LT(err_w, 1e-4 * w_max);      // of 22.1 N m/rad (measured 6.4e-5: 2.9e-6 of it)
}

}  // namespace
}  // namespace nvh::solve
