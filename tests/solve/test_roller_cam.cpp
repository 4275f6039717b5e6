// The roller-cam contact and the kinematic cam (lift driver) against closed forms (issue 13, item 1).
//
// The scene: a cam on a revolute joint turned at constant speed by a speed driver, and a radial in-line
// roller lifter on a prismatic joint along global x (the cam's +x at cam angle 0), held on the cam by a
// preloaded spring. The references are written out here, independently of solve/cam: the tangent cam's lift
// (base circle Rb, nose circle Rn at distance d, straight flanks tangent to both; a radial roller of radius
// Rr):
//   nose  |psi| <= psi_t:        rho = d cos psi + sqrt((Rn + Rr)^2 - d^2 sin^2 psi)
//   flank psi_t < |psi| < beta:  rho = (Rb + Rr) / cos(beta - |psi|),   cos beta = (Rb - Rn) / d
//   base  |psi| >= beta:         rho = Rb + Rr;   lift s = rho - (Rb + Rr), psi measured from the nose,
// the Hertz line contact (Johnson, Contact Mechanics 1985, eq. 4.45: p0 = sqrt(F E* / (pi L R))), Palmgren's
// approach of a steel line contact (Harris & Kotzalas, Rolling Bearing Analysis 2007, eq. 6.46: delta [mm] =
// 3.84e-5 F^0.9 / l^0.8, F in N, l in mm), the quasi-static power balance of the cam (torque = -F_line s'),
// and the separation speed of a follower of mass m on a spring: contact is lost where F0 + k s + m s''
// omega^2 < 0.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>

#include "solve_fixture.hpp"
#include "valvetrain_statics.hpp"

namespace nvh::solve {
namespace {

using testing::num;
using testing::run_text;
using testing::signal;
constexpr double kPi = std::numbers::pi;

// The cam (m): base circle, nose circle, lobe distance, roller; nose at cam angle 180 deg (the run starts on
// the base circle).
constexpr double kRb = 0.02, kRn = 0.01, kD = 0.02, kRr = 0.012, kWidth = 0.015;
constexpr double kNoseDeg = 180;

/// The tangent cam's lift (m) at cam angle theta (rad), written out from the geometry (header).
double tangent_lift(double theta) {
  double psi = std::remainder(theta - kNoseDeg * kPi / 180, 2 * kPi);
  psi = std::abs(psi);
  const double beta = std::acos((kRb - kRn) / kD);
  const double psi_t = std::atan2((kRn + kRr) * std::sin(beta), kD + (kRn + kRr) * std::cos(beta));
  double rho;
  if (psi <= psi_t)
    rho = kD * std::cos(psi) + std::sqrt((kRn + kRr) * (kRn + kRr) - kD * kD * std::sin(psi) * std::sin(psi));
  else if (psi < beta)
    rho = (kRb + kRr) / std::cos(beta - psi);
  else
    rho = kRb + kRr;
  return rho - (kRb + kRr);
}

/// The scene: `cam_rpm`, lifter mass (kg), spring rate (N/m) and preload (N) at zero lift, and the follower's
/// guidance: "contact" (roller-cam, with `contact_keys`) or "driver" (the kinematic cam).
std::string tangent_profile() {
  return "profile = \"tangent\"\nbase_radius = " + num(kRb) + "\nnose_radius = " + num(kRn) +
         "\nlobe_distance = " + num(kD) + "\nroller_radius = " + num(kRr) +
         "\nnose_angle_deg = " + num(kNoseDeg) + "\n";
}

std::string scene(double cam_rpm, double mass, double k, double preload, const std::string& guidance,
                  const std::string& contact_keys, double revolutions, double rate_hz,
                  const std::string& profile = tangent_profile()) {
  const double x0 = kRb + kRr, seat = 0.2;
  const double free_length = (seat - x0) + preload / k;
  std::string s = R"(
[scene]
name = "roller-cam"
gravity = [0, 0, 0]
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "axis"
  [[body.marker]]
  name = "bore"
  at = [)" + num(x0) +
                  R"(, 0, 0]
  z = [1, 0, 0]
  x = [0, 1, 0]
  [[body.marker]]
  name = "seat"
  at = [)" + num(seat) +
                  R"(, 0, 0]
[[body]]
name = "cam"
type = "rigid"
mass = 2.0
inertia = [1e-3, 1e-3, 1e-3]
position = [0, 0, 0]
  [[body.marker]]
  name = "lobe"
[[body]]
name = "lifter"
type = "rigid"
mass = )" + num(mass) +
                  R"(
inertia = [1e-4, 1e-4, 1e-4]
position = [)" + num(x0) +
                  R"(, 0, 0]
  [[body.marker]]
  name = "roller"
  [[body.marker]]
  name = "slide"
  z = [1, 0, 0]
  x = [0, 1, 0]
[[joint]]
name = "camshaft"
type = "revolute"
i = "cam.lobe"
j = "ground.axis"
[[joint]]
name = "bore"
type = "prismatic"
i = "lifter.slide"
j = "ground.bore"
[[driver]]
name = "cam-speed"
type = "speed"
i = "cam.lobe"
j = "ground.axis"
rpm = )" + num(cam_rpm) +
                  R"(
[[force]]
name = "valve-spring"
type = "spring-damper"
i = "lifter.roller"
j = "ground.seat"
k = )" + num(k) + R"(
free_length = )" + num(free_length) +
                  "\n";
  if (guidance == "contact") {
    s += "[[force]]\nname = \"cam\"\ntype = \"roller-cam\"\ni = \"lifter.roller\"\nj = "
         "\"cam.lobe\"\nroller_width = " +
         num(kWidth) + "\n" + profile + contact_keys;
  } else {
    s += "[[driver]]\nname = \"cam\"\ntype = \"lift\"\ni = \"lifter.slide\"\nj = \"ground.bore\"\nrpm = " +
         num(cam_rpm) + "\n" + profile;
  }
  s += "[clock]\nend_time = " + num(revolutions * 60.0 / cam_rpm) +
       "\n[integrator]\nrtol = 1e-8\natol = 1e-11\n" + "max_step = " + num(0.5 / 360 * 60.0 / cam_rpm) +
       "\n[output]\nsample_rate_hz = " + num(rate_hz) + "\n";
  return s;
}

// The kinematic cam: the lifter's position follows the closed-form lift exactly (the constraint's tolerance).
TEST(LiftDriver, FollowsTheTangentCamLift) {
  const double rpm = 600;
  const auto file = run_text(scene(rpm, 0.5, 1e4, 200, "driver", "", 1.0, 36000), "lift_driver");
  const Eigen::VectorXd t = signal(file, "time"), x = signal(file, "bodies/lifter/position", 0);
  double err = 0, peak = 0;
  for (Eigen::Index k = 0; k < t.size(); ++k) {
    const double theta = rpm * 2 * kPi / 60 * t[k];
    err = std::max(err, std::abs(x[k] - (kRb + kRr) - tangent_lift(theta)));
    peak = std::max(peak, x[k] - (kRb + kRr));
  }
  std::printf("measured: lift error %.3g m, peak lift %.6g m (expected %.6g)\n", err, peak, kD + kRn - kRb);
  EXPECT_LT(err, 1e-9);  // the constraint holds to the integrator's tolerance
  // The driver's work (the power of its reaction, /energy/input) is the spring's energy: the balance closes
  // to the accuracy of the reaction (an index-2 multiplier, multiplier_atol 1e-3 N): 1e-4 of the input.
  const Eigen::VectorXd input = signal(file, "energy/input"), balance = signal(file, "energy/balance");
  std::printf("measured: energy balance %.3g J of input up to %.3g J\n", balance.cwiseAbs().maxCoeff(),
              input.cwiseAbs().maxCoeff());
  EXPECT_GT(input.cwiseAbs().maxCoeff(), 0.1);
  EXPECT_LT(balance.cwiseAbs().maxCoeff(), 1e-4 * input.cwiseAbs().maxCoeff());
  EXPECT_NEAR(peak, kD + kRn - kRb, 1e-6);  // nose top reached (sampled at 0.01 deg)
}

// The roller on the cam at a low speed: the lifter follows the lift minus Palmgren's approach of the measured
// contact force; the Hertz pressure on the base circle and the cam's torque (power balance) as closed forms.
TEST(RollerCam, QuasiStaticLiftHertzAndTorque) {
  const double rpm = 30, k = 5e4, f0 = 500;
  const auto file =
      run_text(scene(rpm, 0.5, k, f0, "contact", "restitution = 0.5\n", 1.0, 3600), "roller_cam_slow");
  const Eigen::VectorXd t = signal(file, "time"), x = signal(file, "bodies/lifter/position", 0);
  const Eigen::VectorXd fn = signal(file, "forces/cam/normal_force"),
                        p0 = signal(file, "forces/cam/hertz_pressure");
  const Eigen::VectorXd torque = signal(file, "forces/cam/cam_torque");
  const double e_star = 1.0 / (2 * (1 - 0.3 * 0.3) / 207e9);
  double lift_err = 0, torque_err = 0, torque_peak = 0, p_err = 0;
  const double w = rpm * 2 * kPi / 60;
  for (Eigen::Index i = 0; i < t.size(); ++i) {
    const double theta = w * t[i];
    if (theta < 10 * kPi / 180) continue;  // the start from zero approach rings out first
    const double s = tangent_lift(theta);
    const double h = 1e-6, ds = (tangent_lift(theta + h) - tangent_lift(theta - h)) / (2 * h);
    // The approach is along the contact normal, which leans from the follower's line by the pressure angle
    // phi, tan phi = s' / (Rb + Rr + s) for a radial follower: the lifter sits delta / cos(phi) lower.
    const double approach = 3.84e-5 * std::pow(fn[i], 0.9) / std::pow(kWidth * 1e3, 0.8) * 1e-3;  // m
    const double rho = kRb + kRr + s, cos_phi = rho / std::hypot(rho, ds);
    lift_err = std::max(lift_err, std::abs(x[i] - (kRb + kRr) - (s - approach / cos_phi)));
    // Power balance: the cam's torque times omega equals minus the power into the lifter's spring line
    // (F_line = spring force, quasi-static), T = -F_line ds/dtheta.
    const double f_line = f0 + k * (x[i] - (kRb + kRr));
    torque_err = std::max(torque_err, std::abs(torque[i] + f_line * ds));
    torque_peak = std::max(torque_peak, std::abs(f_line * ds));
    const double from_nose = std::abs(std::remainder(theta - kNoseDeg * kPi / 180, 2 * kPi));
    if (from_nose >
        std::acos((kRb - kRn) / kD) + 1e-3) {  // base circle (beyond the flank): 1/R = 1/Rr + 1/Rb
      const double r = 1.0 / (1.0 / kRr + 1.0 / kRb);
      p_err = std::max(p_err, std::abs(p0[i] / std::sqrt(fn[i] * e_star / (kPi * kWidth * r)) - 1));
    }
  }
  std::printf(
      "measured: lift error %.3g m, torque error %.3g N m of %.3g, base-circle Hertz pressure %.3g rel "
      "(p0 at preload %.4g MPa)\n",
      lift_err, torque_err, torque_peak, p_err, p0[p0.size() - 1] * 1e-6);
  EXPECT_LT(lift_err, 1e-9);                  // m: the integrator's tolerance and the inertia at 30 rpm
  EXPECT_LT(torque_err, 2e-3 * torque_peak);  // the inertia and the approach's share of the power
  EXPECT_LT(p_err, 1e-6);
}

// The eccentric cam (the paper's eq. 1; smooth: no acceleration jumps), lifter mass m on a spring k with
// preload F0 at zero lift: the line force F0 + k s + m s'' omega^2 (quasi-static plus the follower's inertia)
// is smallest where s'' < 0, and the roller leaves the cam when it reaches 0 (the closed form, evaluated here
// from eq. 1 on a fine grid): below that speed the contact holds, above it separates; the element's smallest
// contact force at 0.9 of that speed converges to the closed form's as the contact stiffness grows.
constexpr double kE = 0.005;  // eccentricity (m): a disc of radius Rb + e whose centre is e off the axis
double eccentric_lift(double theta, int derivative) {
  auto rho = [](double th) {
    const double psi = th - kPi;  // peak lift (2 e) at cam angle 180 deg
    const double r = kRb + kE + kRr;
    return kE * std::cos(psi) + std::sqrt(r * r - kE * kE * std::sin(psi) * std::sin(psi)) - (kRb + kRr);
  };
  const double h = 1e-4;
  if (derivative == 0) return rho(theta);
  if (derivative == 1) return (rho(theta + h) - rho(theta - h)) / (2 * h);
  return (rho(theta + h) - 2 * rho(theta) + rho(theta - h)) / (h * h);
}

TEST(RollerCam, SeparationSpeedOfTheEccentricCam) {
  const double m = 0.5, k = 2e4, f0 = 100;
  const std::string profile = "profile = \"eccentric\"\nbase_radius = " + num(kRb) +
                              "\neccentricity = " + num(kE) + "\nroller_radius = " + num(kRr) +
                              "\nnose_angle_deg = 180\n";
  // Closed form: the speed where min over theta of (F0 + k s) / (-m s'') (s'' < 0) is reached.
  double w2 = 1e300;
  for (int i = 0; i < 36000; ++i) {
    const double th = 2 * kPi * i / 36000, dds = eccentric_lift(th, 2);
    if (dds < 0) w2 = std::min(w2, (f0 + k * eccentric_lift(th, 0)) / (-m * dds));
  }
  const double rpm_sep = std::sqrt(w2) * 60 / (2 * kPi);
  // The smallest normal force at 0.9 of it, closed form: min (F0 + k s + m s'' w^2) / cos(phi).
  const double w = 0.9 * std::sqrt(w2);
  double f_min = 1e300;
  for (int i = 0; i < 36000; ++i) {
    const double th = 2 * kPi * i / 36000, s = eccentric_lift(th, 0), ds = eccentric_lift(th, 1);
    const double rho = kRb + kRr + s;
    f_min = std::min(f_min, (f0 + k * s + m * eccentric_lift(th, 2) * w * w) * std::hypot(rho, ds) / rho);
  }
  auto smallest_force = [&](double rpm, const std::string& keys, double* separated) {
    const auto file =
        run_text(scene(rpm, m, k, f0, "contact", keys, 2.0, rpm * 6 * 10, profile), "eccentric");
    const Eigen::VectorXd fn = signal(file, "forces/cam/normal_force"),
                          sep = signal(file, "forces/cam/separated");
    const Eigen::Index half = fn.size() / 2;  // the second revolution: the start has rung out
    if (separated) *separated = sep.tail(fn.size() - half).maxCoeff();
    return fn.tail(fn.size() - half).minCoeff();
  };
  double sep_below = 0, sep_above = 0;
  const double f_hertz = smallest_force(0.9 * rpm_sep, "restitution = 0.3\n", &sep_below);
  smallest_force(1.1 * rpm_sep, "restitution = 0.3\n", &sep_above);
  std::printf(
      "measured: separation speed (closed form) %.1f rpm; smallest contact force at 0.9 of it %.3f N "
      "(closed form %.3f N); separated below / above: %g / %g\n",
      rpm_sep, f_hertz, f_min, sep_below, sep_above);
  EXPECT_EQ(sep_below, 0.0);
  EXPECT_EQ(sep_above, 1.0);
  EXPECT_NEAR(f_hertz, f_min, 0.02 * f0);  // the contact's own vibration about the rigid-body force
  // Convergence with a linear contact stiffness: the error falls as the contact's frequency rises above the
  // cam's.
  double last = 1e300;
  for (const double kc : {1e6, 1e7, 1e8}) {
    const double f =
        smallest_force(0.9 * rpm_sep, "restitution = 0.3\nstiffness = " + num(kc) + "\n", nullptr);
    std::printf("measured: contact stiffness %.0e N/m: smallest force %.3f N, error %.3f N\n", kc, f,
                f - f_min);
    EXPECT_LT(std::abs(f - f_min), last);
    last = std::abs(f - f_min);
  }
  EXPECT_LT(last, 0.02 * f0);
}

}  // namespace
}  // namespace nvh::solve

namespace nvh::solve {
namespace {

// The valvetrain scene of the study (testdata/valvetrain/valvetrain.toml) at a low speed (325 cam rpm): at
// the top of the lift the valve stands where the kinematic chain puts it, less the chain's elastic
// deflections under the forces the run reports and the pushrod's tilt (valvetrain_statics.hpp; the pushrod
// chain's rate EA/L = 4.3e7 N/m).
TEST(Valvetrain, TopOfTheLiftIsTheKinematicLiftLessTheDeflections) {
  const std::string text =
      testing::shipped_scene("valvetrain/valvetrain.toml", {{"rpm = 650 ", "rpm = 325 "}});
  const auto file = run_text(text, "valvetrain_slow", nullptr, "valvetrain");
  const Eigen::VectorXd pushrod = signal(file, "forces/pushrod/force_i");
  // m: the inertia at 325 cam rpm, the seat's and the chain's settling
  EXPECT_NEAR(valvetrain_statics::top_of_second_lift_error(file, pushrod, 4.3e7), 0.0, 1e-6);
}

}  // namespace
}  // namespace nvh::solve
