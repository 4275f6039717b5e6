#pragma once
// The valvetrain with the paper's lever follower (testdata/valvetrain/valvetrain_lever.toml and its flexible
// and kinematic variants; docs/valvetrain.md section 10): the chain's geometry computed from the drawing and
// the cam's lift table alone, shared by the tests of the rigid lever (test_valvetrain_lever.cpp) and of the
// flexible one (test_flexible_lever.cpp):
//
// - the roller's centre lies on the cam's pitch curve (the profile offset by the roller's radius) less the
//   roller's Palmgren approach: in the cam's frame R_c = Q(psi) - delta n(psi), with Q(psi) = (Rb + Rr +
//   s(-psi)) (cos psi, sin psi) (a radial follower on the cam's +x axis sees s(theta): section 1's
//   convention) and n the pitch curve's outward normal; and on the circle of radius L_rp about the lever's
//   pivot. Two equations in the lever's angle beta (of the chord from the pivot to the roller's centre) and
//   the pitch point's angle psi, solved by Newton;
// - the lever's cup, at L_pp on the same line (plus, for a flexible lever, its bending offset from the
// chord),
//   holds the pushrod's lower end; the pushrod, shortened by its force over EA/L, turns the rocker by phi
//   with |B(phi) - C| = L (as in test_valvetrain_kinematics.cpp);
// - the valve follows the rocker's foot less the lash and the foot's Hertz approach (F / k)^(2/3).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <numbers>

#include "solve/cam/profiles.hpp"
#include "solve_fixture.hpp"

namespace nvh::solve::lever_chain {

constexpr double kPi = std::numbers::pi;

// The drawing of valvetrain_lever.toml (m): the cam's axis C0, base radius and roller; the lever's pivot and
// its arms to the roller (L_rp) and the cup (L_pp), along +x at rest; the rocker's pivot P, ball arm a, foot
// arm b; the pushrod's length; the valve's rest height; the lash.
constexpr double kCamX = -0.010, kCamY = 0.030, kRb = 0.025, kRr = 0.0125;
constexpr double kLeverX = -0.060, kLeverY = 0.0675, kLrp = 0.050, kLpp = 0.060;
constexpr double kPx = 0.040, kPy = 0.3675, kA = 0.040, kB = 0.058, kLength = 0.300;
constexpr double kValveY0 = 0.2675, kLash = 0.0005;
constexpr double kPushrodRate = 4.3e7, kFootHertz = 1.5e10, kRollerWidthMm = 15;

/// The scene's cam: the polynomial event of valvetrain_lever.toml.
inline std::unique_ptr<cam::CamProfile> scene_cam() {
  cam::PolynomialEvent e;
  e.lift = 0.00805, e.rise_angle = 52 * kPi / 180, e.ramp_angle = 22 * kPi / 180, e.ramp_height = 0.000333;
  e.base_radius = kRb, e.roller_radius = kRr, e.nose_angle = kPi;
  return cam::polynomial_cam(e);
}

/// The lever's angle beta at cam angle theta with the roller sunk by delta into the cam (Newton on the two
/// components of R_c(beta) - Q(psi) + delta n(psi), the Jacobian by central differences).
inline double lever_angle(const cam::CamProfile& cam, double theta, double delta, double beta0) {
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

/// The rocker's angle phi with the pushrod of length `length` from the cup C to the ball B(phi) = P + a (-cos
/// phi, -sin phi) (Newton; phi < 0 opens the valve).
inline double rocker_angle(double cup_x, double cup_y, double length) {
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

/// One sample of a run, what the closed form needs: the cam angle (rad), the cam's normal force and the force
/// vector it puts on the roller (N, global x and y), the pushrod's end forces (N, compression positive), the
/// lash's force (N).
struct Sample {
  double theta, cam_force, cam_fx, cam_fy, pushrod_i, pushrod_j, lash;
};

/// The bending offset (m) of the cup from the chord pivot-roller, along the lever's normal (-sin beta, cos
/// beta), for a sample at lever angle beta; 0 for a rigid lever.
using CupOffset = std::function<double(const Sample&, double beta)>;

/// The expected valve lift (m) of a sample; `beta` carries the lever's angle from one sample to the next (the
/// Newton start), `offset` the flexible lever's bending (or none).
inline double expected_lift(const cam::CamProfile& cam, const Sample& s, double& beta,
                            const CupOffset& offset) {
  const double delta =
      3.84e-5 * std::pow(s.cam_force, 0.9) / std::pow(kRollerWidthMm, 0.8) * 1e-3;  // Palmgren, m
  beta = lever_angle(cam, s.theta, delta, beta);
  const double w = offset ? offset(s, beta) : 0.0;
  const double cup_x = kLeverX + kLpp * std::cos(beta) - w * std::sin(beta),
               cup_y = kLeverY + kLpp * std::sin(beta) + w * std::cos(beta);
  const double shortening = 0.5 * (s.pushrod_i + s.pushrod_j) / kPushrodRate;
  const double phi = rocker_angle(cup_x, cup_y, kLength - shortening);
  return -kB * std::sin(phi) - kLash - std::pow(s.lash / kFootHertz, 2.0 / 3.0);
}

/// The samples of a results file of one of the lever scenes.
inline std::vector<Sample> samples(const std::filesystem::path& file) {
  using testing::signal;
  const auto angle = signal(file, "crank_angle_deg");
  const auto fc = signal(file, "forces/cam/normal_force"), fl = signal(file, "forces/lash/normal_force");
  const Eigen::MatrixXd f = testing::matrix(file, "forces/cam/force");  // (n, 3), on the roller
  const auto fi = signal(file, "forces/pushrod/force_i"), fj = signal(file, "forces/pushrod/force_j");
  std::vector<Sample> out(static_cast<std::size_t>(angle.size()));
  for (Eigen::Index k = 0; k < angle.size(); ++k)
    out[static_cast<std::size_t>(k)] = {angle[k] * kPi / 180, fc[k], f(k, 0), f(k, 1), fi[k], fj[k], fl[k]};
  return out;
}

}  // namespace nvh::solve::lever_chain
