// The valvetrain with the paper's follower, a roller on a pivoting lever
// (testdata/valvetrain/valvetrain_lever.toml; the paper 001's eqs. 2-3, its lever ratio R_cp;
// docs/valvetrain.md section 10), run through solve at a low speed against the chain's geometry, computed
// here from the drawing and the cam's lift table alone (lever_chain.hpp: the roller's centre on the pitch
// curve less its Palmgren approach and on the lever's circle, the cup on the lever, the pushrod shortened by
// its force turning the rocker, the valve less the lash and the foot's Hertz approach).
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

#include "lever_chain.hpp"
#include "solve/cam/profiles.hpp"
#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::signal;
using namespace lever_chain;

TEST(ValvetrainLever, TopOfTheLiftIsTheLeverChainsGeometryLessTheDeflections) {
  const std::string text =
      testing::shipped_scene("valvetrain/valvetrain_lever.toml",
                             {{"rpm = 650 ", "rpm = 325 "}, {"end_angle_deg = 760", "end_angle_deg = 300"}});
  const auto file = testing::run_text(text, "valvetrain_lever_slow", nullptr, "valvetrain");
  const auto cam = scene_cam();
  const auto angle = signal(file, "crank_angle_deg");
  const auto y = signal(file, "bodies/valve/position", 1);
  const std::vector<Sample> run = samples(file);
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
    const double expected = expected_lift(*cam, run[static_cast<std::size_t>(k)], beta, nullptr);
    err = std::max(err, std::abs(lift - expected));
    ++n;
    if (k == top) {
      const double beta_rigid = lever_angle(*cam, run[static_cast<std::size_t>(k)].theta, 0, beta);
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
  const auto cam = scene_cam();
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
