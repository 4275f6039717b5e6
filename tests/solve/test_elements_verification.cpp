// Verification of the force elements, drivers and joints against closed forms (issue 12, item 5).
//
// Every test writes a scene as TOML text, runs it through solve's library (run_text) and reads the results
// file back: the tests use only the scene format (docs/scene-format.md) and the results layout
// (docs/results-format.md), not the C++ interface of the elements. Every asserted number comes from a
// closed form or a textbook formula evaluated here (cited at each test), never from this code; the
// tolerance is stated at each assertion and the measured error is printed ("measured: ...").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::run_text;
using testing::matrix;
using testing::num;
using testing::signal;
constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.81;

/// Largest |measured - expected(t)| over the samples.
double max_error(const Eigen::VectorXd& t, const Eigen::VectorXd& measured, const std::function<double(double)>& expected) {
  double e = 0;
  for (Eigen::Index k = 0; k < t.size(); ++k) e = std::max(e, std::abs(measured[k] - expected(t[k])));
  return e;
}

/// Times where y crosses `level` upwards (linear interpolation between samples).
std::vector<double> upward_crossings(const Eigen::VectorXd& t, const Eigen::VectorXd& y, double level) {
  std::vector<double> out;
  for (Eigen::Index k = 1; k < t.size(); ++k)
    if (y[k - 1] < level && y[k] >= level)
      out.push_back(t[k - 1] + (level - y[k - 1]) / (y[k] - y[k - 1]) * (t[k] - t[k - 1]));
  return out;
}

struct Extremum {
  double t, value;
};
/// Local maxima (sign = +1) or minima (sign = -1) of y, refined by a parabola through the three samples.
std::vector<Extremum> extrema(const Eigen::VectorXd& t, const Eigen::VectorXd& y, int sign) {
  std::vector<Extremum> out;
  for (Eigen::Index k = 1; k + 1 < t.size(); ++k) {
    const double a = sign * y[k - 1], b = sign * y[k], c = sign * y[k + 1];
    if (b > a && b >= c) {
      const double den = a - 2 * b + c, h = t[k + 1] - t[k];
      const double s = den != 0 ? 0.5 * (a - c) / den : 0.0;  // vertex offset in steps
      out.push_back({t[k] + s * h, sign * (b - 0.25 * (a - c) * s)});
    }
  }
  return out;
}

/// The rotation angle about a fixed global axis (x: 1, z: 3) from the Euler parameters: 2 atan2(e_axis, e0).
Eigen::VectorXd angle_about(const Eigen::MatrixXd& euler, int axis) {
  Eigen::VectorXd a(euler.rows());
  for (Eigen::Index k = 0; k < euler.rows(); ++k) a[k] = 2 * std::atan2(euler(k, axis), euler(k, 0));
  return a;
}

const char* kGround = R"(
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "o"
)";

// ==================================================================== bushing
// A rigid block on a 6-DOF bushing at its centre of mass (diagonal K, D): the six directions decouple into
// single-DOF oscillators m u'' + c u' + k u = F (Thomson & Dahleh, Theory of Vibration with Applications,
// 5th ed., ch. 2 free and damped vibration, ch. 4 step response):
//   z under gravity, from rest at u = 0:     z(t) = -(m g / k)(1 - cos(wn t)), static deflection m g / k
//   y from u = 0 with speed v0:              y(t) = (v0 / wn) sin(wn t)
//   x with damping ratio zeta, speed v0:     x(t) = (v0 / wd) exp(-zeta wn t) sin(wd t), wd = wn sqrt(1 - zeta^2)
TEST(Bushing, TranslationStaticDeflectionFrequencyAndDamping) {
  const double m = 2.0, kx = 2e4, ky = 5e4, kz = 8e4, zeta = 0.1, v0 = 0.1;
  const double wx = std::sqrt(kx / m), wy = std::sqrt(ky / m), wz = std::sqrt(kz / m);
  const double cx = 2 * zeta * std::sqrt(kx * m), wd = wx * std::sqrt(1 - zeta * zeta);
  const std::string text = std::string("[scene]\ngravity = [0, 0, -9.81]\n") + kGround + R"(
[[body]]
name = "block"
type = "rigid"
mass = )" + num(m) + R"(
inertia = [0.01, 0.012, 0.014]
velocity = [)" + num(v0) + ", " + num(v0) + R"(, 0]
  [[body.marker]]
  name = "c"
[[force]]
name = "mount"
type = "bushing"
i = "block.c"
j = "ground.o"
stiffness = [)" + num(kx) + ", " + num(ky) + ", " + num(kz) + R"(, 100, 100, 100]
damping = [)" + num(cx) + R"(, 0, 0, 0, 0, 0]
[clock]
end_time = 0.2
[integrator]
rtol = 1e-10
atol = 1e-13
[output]
sample_rate_hz = 20000
)";
  const auto file = run_text(text, "bushing_translation");
  const Eigen::VectorXd t = signal(file, "time");
  const double zs = m * kG / kz;  // the static deflection
  const double ez = max_error(t, signal(file, "bodies/block/position", 2), [&](double s) { return -zs * (1 - std::cos(wz * s)); }) / zs;
  const double ey = max_error(t, signal(file, "bodies/block/position", 1), [&](double s) { return v0 / wy * std::sin(wy * s); }) / (v0 / wy);
  const double ex = max_error(t, signal(file, "bodies/block/position", 0), [&](double s) {
                      return v0 / wd * std::exp(-zeta * wx * s) * std::sin(wd * s);
                    }) / (v0 / wd);
  // the static deflection: the middle of the undamped z oscillation
  const Eigen::VectorXd z = signal(file, "bodies/block/position", 2);
  const double mid = -0.5 * (z.maxCoeff() + z.minCoeff());
  std::printf("measured: bushing translation, error / amplitude: z %.3g, y %.3g, x (damped) %.3g; static deflection %.9g m (m g / k = %.9g)\n",
              ez, ey, ex, mid, zs);
  EXPECT_LT(ez, 1e-6);
  EXPECT_LT(ey, 1e-6);
  EXPECT_LT(ex, 1e-6);
  EXPECT_NEAR(mid, zs, 1e-4 * zs);  // limited by the 50 us sampling of the extremes (1 - cos(wz dt / 2) ~ 1e-5)
}

// Rotation: a constant torque T about x on the block (inertia Ixx) against the bushing's rotational stiffness:
//   theta(t) = (T / k)(1 - cos(wn t)), wn = sqrt(k / Ixx); static angle T / k (single-DOF oscillator as above).
// The bushing's angle is the axis-angle vector of the relative rotation, exact for a rotation about one axis.
TEST(Bushing, RotationStaticAngleAndFrequency) {
  const double ixx = 0.02, krx = 50.0, torque = 5.0, wn = std::sqrt(krx / ixx), theta_s = torque / krx;
  const std::string text = std::string(kGround) + R"(
[[body]]
name = "block"
type = "rigid"
mass = 2.0
inertia = [)" + num(ixx) + R"(, 0.03, 0.04]
  [[body.marker]]
  name = "c"
[[force]]
name = "mount"
type = "bushing"
i = "block.c"
j = "ground.o"
stiffness = [1e4, 1e4, 1e4, )" + num(krx) + R"(, 80, 120]
[[load]]
name = "torque"
type = "torque"
at = "block.c"
direction = [1, 0, 0]
table = [[0, )" + num(torque) + "], [10, " + num(torque) + R"(]]
[clock]
end_time = 0.5
[integrator]
rtol = 1e-10
atol = 1e-13
[output]
sample_rate_hz = 10000
)";
  const auto file = run_text(text, "bushing_rotation");
  const Eigen::VectorXd t = signal(file, "time");
  const Eigen::VectorXd theta = angle_about(matrix(file, "bodies/block/euler_parameters"), 1);
  const double e = max_error(t, theta, [&](double s) { return theta_s * (1 - std::cos(wn * s)); }) / theta_s;
  const double mid = 0.5 * (theta.maxCoeff() + theta.minCoeff());
  std::printf("measured: bushing rotation, error / static angle %.3g; static angle %.9g rad (T / k = %.9g)\n", e, mid, theta_s);
  EXPECT_LT(e, 1e-6);
  EXPECT_NEAR(mid, theta_s, 1e-4 * theta_s);  // sampling of the extremes, as above
}

// ==================================================================== torsional spring-damper
// A flywheel (J about its axis) on a revolute joint, held by a torsional spring-damper (k, d), started with
// speed w0 from phi = 0: J phi'' + d phi' + k phi = 0 (Thomson & Dahleh, ch. 2):
//   phi(t) = (w0 / wd) exp(-zeta wn t) sin(wd t), wn = sqrt(k / J), zeta = d / (2 sqrt(k J)),
//   damped period Td = 2 pi / wd, logarithmic decrement ln(phi_k / phi_k+1) = 2 pi zeta / sqrt(1 - zeta^2).
std::string flywheel_scene(double j, double k, double d, double w0, const std::string& extra, double end_time,
                           double rate_hz) {
  return std::string(kGround) + R"(
  [[body.marker]]
  name = "axis"
[[body]]
name = "fly"
type = "rigid"
mass = 1.0
inertia = [0.01, 0.01, )" + num(j) + R"(]
angular_velocity = [0, 0, )" + num(w0) + R"(]
  [[body.marker]]
  name = "hub"
[[joint]]
name = "bearing"
type = "revolute"
i = "fly.hub"
j = "ground.axis"
[[force]]
name = "coupling"
type = "torsional-spring-damper"
i = "fly.hub"
j = "ground.axis"
k = )" + num(k) + R"(
d = )" + num(d) + R"(
)" + extra + R"(
[clock]
i = "fly.hub"
j = "ground.axis"
end_time = )" + num(end_time) + R"(
[integrator]
rtol = 1e-10
atol = 1e-12
[output]
sample_rate_hz = )" + num(rate_hz) + "\n";
}

TEST(TorsionalSpringDamper, OscillatorFrequencyAndDamping) {
  const double j = 0.02, k = 50.0, zeta = 0.05, w0 = 2.0;
  const double wn = std::sqrt(k / j), d = 2 * zeta * std::sqrt(k * j), wd = wn * std::sqrt(1 - zeta * zeta);
  const auto file = run_text(flywheel_scene(j, k, d, w0, "", 1.0, 10000), "torsional_oscillator");
  const Eigen::VectorXd t = signal(file, "time"), phi = signal(file, "crank_angle_deg") * (kPi / 180);
  const double amp = w0 / wd;
  const double e = max_error(t, phi, [&](double s) { return amp * std::exp(-zeta * wn * s) * std::sin(wd * s); }) / amp;
  // frequency: mean period between upward zero crossings; damping: logarithmic decrement of the maxima
  const auto up = upward_crossings(t, phi, 0.0);
  ASSERT_GE(up.size(), 4u);
  const double td = (up.back() - up.front()) / static_cast<double>(up.size() - 1);
  const auto peaks = extrema(t, phi, +1);
  ASSERT_GE(peaks.size(), 4u);
  const double decrement = std::log(peaks.front().value / peaks.back().value) / static_cast<double>(peaks.size() - 1);
  const double td_ref = 2 * kPi / wd, dec_ref = 2 * kPi * zeta / std::sqrt(1 - zeta * zeta);
  std::printf("measured: torsional oscillator, history error / amplitude %.3g; period %.9g s (closed form %.9g); "
              "log decrement %.9g (closed form %.9g)\n", e, td, td_ref, decrement, dec_ref);
  EXPECT_LT(e, 1e-6);
  EXPECT_NEAR(td, td_ref, 1e-5 * td_ref);         // zero crossings interpolated linearly at 0.1 ms sampling
  EXPECT_NEAR(decrement, dec_ref, 1e-4 * dec_ref);  // peaks refined by a parabola through 3 samples
}

// Wind-up beyond half a turn: a constant torque T = k * 270 deg on the flywheel, critically damped
// (d = 2 sqrt(k J)); the spring's torque -k phi with phi the twist, 3 pi / 2 at rest (T = k phi, a
// torsion spring is linear in its twist whatever the number of turns). Step response of a critically damped
// oscillator (Thomson & Dahleh, ch. 4): phi(t) = phi_s (1 - (1 + wn t) exp(-wn t)), phi_s = T / k.
TEST(TorsionalSpringDamper, WindUpBeyondHalfATurn) {
  const double j = 0.01, k = 1.0, wn = std::sqrt(k / j), d = 2 * std::sqrt(k * j), phi_s = 1.5 * kPi, torque = k * phi_s;
  const std::string load = R"(
[[load]]
name = "drive"
type = "torque"
at = "fly.hub"
direction = [0, 0, 1]
table = [[0, )" + num(torque) + "], [100, " + num(torque) + "]]\n";
  const auto file = run_text(flywheel_scene(j, k, d, 0.0, load, 3.0, 1000), "torsional_windup");
  const Eigen::VectorXd t = signal(file, "time"), phi = signal(file, "crank_angle_deg") * (kPi / 180);
  const double e = max_error(t, phi, [&](double s) { return phi_s * (1 - (1 + wn * s) * std::exp(-wn * s)); });
  const double phi_end = phi[phi.size() - 1];
  const double spring_torque = signal(file, "forces/coupling/torque", 2)[phi.size() - 1];
  std::printf("measured: torsional wind-up, history error %.3g rad; twist at rest %.9g deg (270); spring torque "
              "%.9g N m (-k phi = %.9g)\n", e, phi_end * 180 / kPi, spring_torque, -k * phi_s);
  EXPECT_LT(e, 1e-6);                               // rad, over the whole run
  EXPECT_NEAR(phi_end, phi_s, 1e-6);                // rad: exp(-30) 31 = 3e-12 of the step is left at 3 s
  EXPECT_NEAR(spring_torque, -k * phi_s, 1e-6);     // N m: T = k phi at 270 deg
}

// ==================================================================== table-force
// A point mass on a tabulated spring (force along z_j against the deflection along z_j) under gravity.
// Linear table f = -k u: from rest at u = 0, u(t) = -(m g / k)(1 - cos(wn t)) (single-DOF oscillator).
TEST(TableForce, LinearTableStaticDeflectionAndPeriod) {
  const double m = 2.0, k = 2000.0, wn = std::sqrt(k / m), us = m * kG / k;
  const std::string text = std::string("[scene]\ngravity = [0, 0, -9.81]\n") + kGround + R"(
[[body]]
name = "mass"
type = "point-mass"
mass = )" + num(m) + R"(
  [[body.marker]]
  name = "c"
[[force]]
name = "mount"
type = "table-force"
i = "mass.c"
j = "ground.o"
table = [[-0.1, )" + num(0.1 * k) + "], [0.1, " + num(-0.1 * k) + R"(]]
[clock]
end_time = 1.0
[integrator]
rtol = 1e-10
atol = 1e-13
[output]
sample_rate_hz = 10000
)";
  const auto file = run_text(text, "table_linear");
  const Eigen::VectorXd t = signal(file, "time"), z = signal(file, "markers/mass.c/position", 2);
  const double e = max_error(t, z, [&](double s) { return -us * (1 - std::cos(wn * s)); }) / us;
  const auto up = upward_crossings(t, z, -us);
  const double period = (up.back() - up.front()) / static_cast<double>(up.size() - 1);
  std::printf("measured: linear table-force, history error / static deflection %.3g; period %.9g s (2 pi sqrt(m/k) = %.9g)\n",
              e, period, 2 * kPi / wn);
  EXPECT_LT(e, 1e-6);
  EXPECT_NEAR(period, 2 * kPi / wn, 1e-5 * 2 * kPi / wn);  // crossings interpolated at 0.1 ms sampling
}

// A non-linear (hardening) table, 10 kN/m up to 10 mm and 50 kN/m beyond, with a parallel damper; the mass
// comes to rest where the table's force equals its weight. By hand: m g = 147.15 N exceeds the 100 N at 10 mm,
// so u = 0.01 + (m g - 100) / 5e4 = 0.010943 m.
TEST(TableForce, NonlinearTableStaticDeflection) {
  const double m = 15.0, u_ref = 0.01 + (m * kG - 100.0) / 5e4;
  const std::string text = std::string("[scene]\ngravity = [0, 0, -9.81]\n") + kGround + R"(
  [[body.marker]]
  name = "above"
  at = [0, 0, 1]
[[body]]
name = "mass"
type = "point-mass"
mass = )" + num(m) + R"(
  [[body.marker]]
  name = "c"
[[force]]
name = "mount"
type = "table-force"
i = "mass.c"
j = "ground.o"
table = [[-0.05, 2100], [-0.01, 100], [0, 0], [0.01, -100]]
[[force]]
name = "damper"
type = "spring-damper"
i = "mass.c"
j = "ground.above"
d = 600
[clock]
end_time = 1.5
[integrator]
rtol = 1e-10
atol = 1e-13
[output]
sample_rate_hz = 1000
)";
  const auto file = run_text(text, "table_nonlinear");
  const Eigen::VectorXd z = signal(file, "markers/mass.c/position", 2);
  const double u = -z[z.size() - 1];
  std::printf("measured: hardening table-force, rest deflection %.9g m (by hand %.9g)\n", u, u_ref);
  EXPECT_NEAR(u, u_ref, 1e-8);  // m; zeta = 0.35 at 57.7 rad/s: exp(-30) of the transient is left at 1.5 s
}

// ==================================================================== motor curve
// A rotor (J) driven by a linear torque-speed curve T = T0 (1 - n / n0) from rest: J w' = T0 (1 - w / w0), so
//   w(t) = w0 (1 - exp(-t / tau)),  angle(t) = w0 (t - tau (1 - exp(-t / tau))),  tau = J w0 / T0.
TEST(MotorCurve, LinearTorqueSpeedCurveRunUpIsExponential) {
  const double j = 0.005, t0 = 2.0, n0 = 3000.0, w0 = n0 * 2 * kPi / 60, tau = j * w0 / t0;
  // the line through (0 rpm, T0) and (n0, 0), given at -n0 and 2 n0 (the table is held beyond its ends)
  const std::string text = std::string(kGround) + R"(
[[body]]
name = "rotor"
type = "rigid"
mass = 1.0
inertia = [0.01, 0.01, )" + num(j) + R"(]
  [[body.marker]]
  name = "shaft"
[[joint]]
name = "bearing"
type = "revolute"
i = "rotor.shaft"
j = "ground.o"
[[driver]]
name = "motor"
type = "motor"
i = "rotor.shaft"
j = "ground.o"
table = [[-3000, 4.0], [6000, -2.0]]
[clock]
i = "rotor.shaft"
j = "ground.o"
end_time = 2.0
[integrator]
rtol = 1e-10
atol = 1e-12
[output]
sample_rate_hz = 1000
)";
  const auto file = run_text(text, "motor_runup");
  const Eigen::VectorXd t = signal(file, "time"), w = signal(file, "bodies/rotor/angular_velocity", 2),
                        a = signal(file, "crank_angle_deg") * (kPi / 180);
  const double ew = max_error(t, w, [&](double s) { return w0 * (1 - std::exp(-s / tau)); }) / w0;
  const double ea = max_error(t, a, [&](double s) { return w0 * (s - tau * (1 - std::exp(-s / tau))); });
  std::printf("measured: motor run-up, speed error / w0 %.3g, angle error %.3g rad (tau = %.6g s)\n", ew, ea, tau);
  EXPECT_LT(ew, 1e-7);
  EXPECT_LT(ea, 4e-6);  // rad: 1e-8 of the 401 rad turned in the 2 s (rtol 1e-10 accumulated over 8e4 steps)
}

// ==================================================================== run-up speed driver
// rpm(t) linear from n1 at t = 0 to n2 at t1, held after: the crank angle is its integral,
//   angle(t) = (2 pi / 60)(n1 t + (n2 - n1) t^2 / (2 t1)) for t <= t1,
//   angle(t1) + (2 pi / 60) n2 (t - t1) after.
TEST(SpeedDriver, RunUpCrankAngleIsTheIntegralOfTheRamp) {
  const double n1 = 600, n2 = 3000, t1 = 1.0, c = 2 * kPi / 60;
  auto angle = [&](double s) {
    const double a1 = c * (n1 * std::min(s, t1) + (n2 - n1) * std::pow(std::min(s, t1), 2) / (2 * t1));
    return a1 + (s > t1 ? c * n2 * (s - t1) : 0.0);
  };
  auto speed = [&](double s) { return c * (s < t1 ? n1 + (n2 - n1) * s / t1 : n2); };
  const std::string text = std::string(kGround) + R"(
[[body]]
name = "crank"
type = "rigid"
mass = 1.0
inertia = [0.01, 0.01, 0.02]
  [[body.marker]]
  name = "main"
[[joint]]
name = "bearing"
type = "revolute"
i = "crank.main"
j = "ground.o"
[[driver]]
name = "speed"
type = "speed"
i = "crank.main"
j = "ground.o"
table = [[0.0, )" + num(n1) + "], [" + num(t1) + ", " + num(n2) + R"(]]
[clock]
i = "crank.main"
j = "ground.o"
end_time = 1.5
[integrator]
rtol = 1e-10
atol = 1e-12
[output]
sample_rate_hz = 2000
)";
  const auto file = run_text(text, "speed_runup");
  const Eigen::VectorXd t = signal(file, "time"), a = signal(file, "crank_angle_deg") * (kPi / 180),
                        w = signal(file, "bodies/crank/angular_velocity", 2);
  const double ea = max_error(t, a, angle), ew = max_error(t, w, speed);
  std::printf("measured: run-up driver, crank angle error %.3g rad (of %.6g), speed error %.3g rad/s\n", ea,
              angle(t[t.size() - 1]), ew);
  EXPECT_LT(ea, 1e-7);  // rad: the driver is a constraint, kept to the integrator's tolerance
  EXPECT_LT(ew, 1e-6);  // rad/s
}

// ==================================================================== end_time_limit
// A run ending by crank angle stops at end_time_limit when the angle is not reached by then: at 600 rpm
// (3600 deg/s) 36000 deg take 10 s; with end_time_limit = 0.5 s the run ends at 0.5 s at 1800 deg. With a
// limit longer than needed, the run ends by the angle: 720 deg at 0.2 s.
std::string clock_scene(const std::string& clock) {
  return std::string(kGround) + R"(
[[body]]
name = "crank"
type = "rigid"
mass = 1.0
inertia = [0.01, 0.01, 0.02]
  [[body.marker]]
  name = "main"
[[joint]]
name = "bearing"
type = "revolute"
i = "crank.main"
j = "ground.o"
[[driver]]
name = "speed"
type = "speed"
i = "crank.main"
j = "ground.o"
rpm = 600
[clock]
i = "crank.main"
j = "ground.o"
)" + clock + R"(
[output]
sample_rate_hz = 1000
)";
}

TEST(EndTimeLimit, StopsARunEndingByCrankAngle) {
  const auto file = run_text(clock_scene("end_angle_deg = 36000\nend_time_limit = 0.5\n"), "end_time_limit");
  const Eigen::VectorXd t = signal(file, "time"), a = signal(file, "crank_angle_deg");
  std::printf("measured: end_time_limit 0.5 s: last sample at %.9g s, %.9g deg\n", t[t.size() - 1], a[a.size() - 1]);
  EXPECT_NEAR(t[t.size() - 1], 0.5, 1e-9);   // s: the last sample (1 ms apart) is the limit
  EXPECT_NEAR(a[a.size() - 1], 1800.0, 1e-5);  // deg = 3600 deg/s x 0.5 s
}

TEST(EndTimeLimit, LongerLimitEndsByTheAngle) {
  const auto file = run_text(clock_scene("end_angle_deg = 720\nend_time_limit = 5.0\n"), "end_time_limit_long");
  const Eigen::VectorXd t = signal(file, "time"), a = signal(file, "crank_angle_deg");
  std::printf("measured: end_time_limit 5 s, end 720 deg: last sample at %.9g s, %.9g deg\n", t[t.size() - 1],
              a[a.size() - 1]);
  EXPECT_NEAR(t[t.size() - 1], 0.2, 1e-9);  // s: 720 deg at 3600 deg/s
  EXPECT_NEAR(a[a.size() - 1], 720.0, 1e-5);
}

// ==================================================================== spherical joint
// Conical pendulum: a bob on a spherical joint at distance L below-and-out from the pivot, the line at
// angle theta from the vertical, circling at the steady rate w^2 = g / (L cos(theta)) (Newton's law on the
// circle: tension S, S sin(theta) = m w^2 L sin(theta), S cos(theta) = m g). The bob is a rigid body with an isotropic inertia
// rotating at w about the vertical with the line: its angular momentum about its centre of mass, I w, stays
// constant, so it needs no moment and moves as a point mass. The line's tension is m g / cos(theta).
TEST(SphericalJoint, ConicalPendulumSteadyRate) {
  const double m = 0.5, l = 0.5, theta = 30.0 * kPi / 180, w = std::sqrt(kG / (l * std::cos(theta)));
  const double r = l * std::sin(theta), h = l * std::cos(theta);
  const std::string text = std::string("[scene]\ngravity = [0, 0, -9.81]\n") + kGround + R"(
[[body]]
name = "bob"
type = "rigid"
mass = )" + num(m) + R"(
inertia = [1e-4, 1e-4, 1e-4]
position = [)" + num(r) + ", 0, " + num(-h) + R"(]
velocity = [0, )" + num(w * r) + R"(, 0]
angular_velocity = [0, 0, )" + num(w) + R"(]
  [[body.marker]]
  name = "pivot"
  at = [)" + num(-r) + ", 0, " + num(h) + R"(]
[[joint]]
name = "pivot"
type = "spherical"
i = "bob.pivot"
j = "ground.o"
[clock]
end_time = 3.0
[integrator]
rtol = 1e-10
atol = 1e-12
[output]
sample_rate_hz = 1000
)";
  const auto file = run_text(text, "conical_pendulum");
  const Eigen::VectorXd t = signal(file, "time");
  const Eigen::MatrixXd p = matrix(file, "bodies/bob/position"), f = matrix(file, "joints/pivot/reaction_force");
  double ep = 0, ef = 0;
  for (Eigen::Index k = 0; k < t.size(); ++k) {
    const Eigen::Vector3d expected(r * std::cos(w * t[k]), r * std::sin(w * t[k]), -h);
    ep = std::max(ep, (p.row(k).transpose() - expected).norm());
    ef = std::max(ef, std::abs(f.row(k).norm() - m * kG / std::cos(theta)));
  }
  std::printf("measured: conical pendulum (w = %.6g rad/s, %.3g turns): path error %.3g m / r, tension error %.3g N "
              "(m g / cos theta = %.6g N)\n", w, w * t[t.size() - 1] / (2 * kPi), ep / r, ef, m * kG / std::cos(theta));
  EXPECT_LT(ep / r, 1e-6);  // the bob stays on the circle at the closed-form rate over 2.3 turns
  EXPECT_LT(ef, 1e-5);      // N (tension 5.66 N)
}

// ==================================================================== cylindrical joint
// A body on a cylindrical joint along global x, pushed by a constant axial force F and spinning at w about
// the axis (a principal axis through its centre of mass), under gravity -z: free translation
// x(t) = v0 t + F t^2 / (2 m), constant spin (no torque about the axis; Euler's equations for a principal
// axis), rotation angle w t; the joint carries the weight, reaction (0, 0, m g), and no moment.
TEST(CylindricalJoint, SlidesUnderAxialForceWhileSpinning) {
  const double m = 3.0, f = 6.0, v0 = 0.2, w = 20.0;
  const std::string text = std::string("[scene]\ngravity = [0, 0, -9.81]\n") + kGround + R"(
  [[body.marker]]
  name = "axis"
  z = [1, 0, 0]
  x = [0, 1, 0]
[[body]]
name = "slider"
type = "rigid"
mass = )" + num(m) + R"(
inertia = [0.004, 0.01, 0.012]
velocity = [)" + num(v0) + R"(, 0, 0]
angular_velocity = [)" + num(w) + R"(, 0, 0]
  [[body.marker]]
  name = "bore"
  z = [1, 0, 0]
  x = [0, 1, 0]
[[joint]]
name = "guide"
type = "cylindrical"
i = "slider.bore"
j = "ground.axis"
[[load]]
name = "push"
type = "force"
at = "slider.bore"
direction = [1, 0, 0]
table = [[0, )" + num(f) + "], [10, " + num(f) + R"(]]
[clock]
end_time = 1.0
[integrator]
rtol = 1e-10
atol = 1e-12
multiplier_atol = 1e-8
[output]
sample_rate_hz = 1000
)";
  const auto file = run_text(text, "cylindrical_slide");
  const Eigen::VectorXd t = signal(file, "time");
  const double ex = max_error(t, signal(file, "bodies/slider/position", 0), [&](double s) { return v0 * s + f * s * s / (2 * m); });
  const Eigen::MatrixXd e = matrix(file, "bodies/slider/euler_parameters"), wv = matrix(file, "bodies/slider/angular_velocity");
  const Eigen::MatrixXd rf = matrix(file, "joints/guide/reaction_force"), rt = matrix(file, "joints/guide/reaction_torque");
  double eangle = 0, ew = 0, ef = 0, et = 0;
  for (Eigen::Index k = 0; k < t.size(); ++k) {
    // the rotation from the closed form (cos(w t / 2), sin(w t / 2), 0, 0) to the computed one: conj(ref) * e
    const double c = std::cos(w * t[k] / 2), sn = std::sin(w * t[k] / 2);
    const double scalar = c * e(k, 0) + sn * e(k, 1);
    const Eigen::Vector3d vec(c * e(k, 1) - sn * e(k, 0), c * e(k, 2) + sn * e(k, 3), c * e(k, 3) - sn * e(k, 2));
    eangle = std::max(eangle, 2 * std::atan2(vec.norm(), std::abs(scalar)));
    ew = std::max(ew, (wv.row(k).transpose() - Eigen::Vector3d(w, 0, 0)).norm());
    ef = std::max(ef, (rf.row(k).transpose() - Eigen::Vector3d(0, 0, m * kG)).norm());
    et = std::max(et, rt.row(k).norm());
  }
  std::printf("measured: cylindrical joint, axial position error %.3g m, rotation angle error %.3g rad, spin error "
              "%.3g rad/s, reaction force error %.3g N, reaction moment %.3g N m\n", ex, eangle, ew, ef, et);
  EXPECT_LT(ex, 1e-8);      // m (travel 1.2 m)
  EXPECT_LT(eangle, 1e-6);  // rad (20 rad turned)
  EXPECT_LT(ew, 1e-6);      // rad/s
  EXPECT_LT(ef, 1e-4);      // N (weight 29.4 N)
  EXPECT_LT(et, 1e-4);      // N m
}

// ==================================================================== contact with clearance
// A ball released at height h above the contact plane with free play c: the documented gap is
// h(t) + c (gap = z_j . (p_i - p_j) + clearance), so free fall lasts until g t^2 / 2 = h + c:
//   t_contact = sqrt(2 (h + c) / g); before it gap(t) = h + c - g t^2 / 2 and no force.
TEST(ContactClearance, FirstContactAfterFreeFallThroughTheClearance) {
  const double h = 0.05, c = 0.01, t_ref = std::sqrt(2 * (h + c) / kG);
  const std::string text = std::string("[scene]\ngravity = [0, 0, -9.81]\n") + kGround + R"(
[[body]]
name = "ball"
type = "point-mass"
mass = 0.1
position = [0, 0, )" + num(h) + R"(]
  [[body.marker]]
  name = "c"
[[force]]
name = "stop"
type = "contact"
i = "ball.c"
j = "ground.o"
stiffness = 1e8
exponent = 1.5
restitution = 0.8
clearance = )" + num(c) + R"(
[clock]
end_time = )" + num(t_ref + 0.002) + R"(
[integrator]
rtol = 1e-10
atol = 1e-12
max_step = 1e-4
[output]
sample_rate_hz = 100000
)";
  const auto file = run_text(text, "contact_clearance");
  const Eigen::VectorXd t = signal(file, "time"), gap = signal(file, "forces/stop/gap"),
                        fn = signal(file, "forces/stop/normal_force");
  double t_contact = -1, egap = 0, fmax_before = 0;
  const double fmax_after = fn.maxCoeff();
  for (Eigen::Index k = 1; k < t.size(); ++k) {
    if (gap[k] <= 0) {
      t_contact = t[k - 1] + gap[k - 1] / (gap[k - 1] - gap[k]) * (t[k] - t[k - 1]);
      break;
    }
    egap = std::max(egap, std::abs(gap[k] - (h + c - 0.5 * kG * t[k] * t[k])));
    fmax_before = std::max(fmax_before, std::abs(fn[k]));
  }
  std::printf("measured: contact with clearance, first contact at %.9g s (sqrt(2 (h + c) / g) = %.9g s; "
              "without the clearance %.6g s), gap error %.3g m, force before %.3g N, largest force after %.4g N\n",
              t_contact, t_ref, std::sqrt(2 * h / kG), egap, fmax_before, fmax_after);
  EXPECT_NEAR(t_contact, t_ref, 1e-6);  // s; linear interpolation of the gap between 10 us samples: < 1e-9 s
  EXPECT_LT(egap, 1e-9);                // m
  EXPECT_EQ(fmax_before, 0.0);          // no force across the free play
  EXPECT_GT(fmax_after, 1.0);           // N: and the impact after it (the ball rebounds within the 2 ms)
}

// ==================================================================== Coulomb/Stribeck friction: stick-slip
// A block (m) pressed on a belt moving at v_b by a normal force N, held back by a spring k to the ground
// (Popp & Stelter, Stick-slip vibrations and chaos, Phil. Trans. R. Soc. Lond. A 332, 1990; derived here).
// With mu_s > mu_d and the block starting at rest on the belt at the spring's free length:
//   stick: x = v_b t until k x = mu_s N (t1 = mu_s N / (k v_b));
//   slip:  m x'' = -k x + mu_d N: a half-oscillation about x_d = mu_d N / k with w = sqrt(k / m), from
//          xi0 = (mu_s - mu_d) N / k, speed v_b; amplitude A = sqrt(xi0^2 + (v_b / w)^2);
//          maxima x_d + A, minima x_d - A; slip ends where the speed is v_b again, at x_d - xi0, after
//          t_slip = (2 pi - 2 atan(xi0 w / v_b)) / w;
//   stick again for 2 xi0 / v_b: the period is T = t_slip + 2 xi0 / v_b; first maximum at
//          t1 + atan2(v_b / w, xi0) / w.
// The law in solve is smooth: mu(v) = (mu_d + (mu_s - mu_d) exp(-(v / v_s)^2)) tanh(v / v_eps), with
// v_eps = 2e-7 m/s << v_s = 2e-5 m/s << v_b = 0.1 m/s; the belt is a 1e8 kg body on a prismatic joint
// (its speed changes by 1e-7 m/s over the run).
TEST(StickSlip, BlockOnAMovingBeltAgainstTheClosedForm) {
  const double m = 1.0, k = 100.0, n = 10.0, mus = 0.5, mud = 0.3, vb = 0.1, kc = 1e6;
  const double w = std::sqrt(k / m), xd = mud * n / k, xi0 = (mus - mud) * n / k, a = std::hypot(xi0, vb / w);
  const double t1 = mus * n / (k * vb), t_slip = (2 * kPi - 2 * std::atan(xi0 * w / vb)) / w, period = t_slip + 2 * xi0 / vb;
  const double t_max1 = t1 + std::atan2(vb / w, xi0) / w, delta = n / kc;  // delta: static penetration
  const std::string text = std::string(kGround) + R"(
  [[body.marker]]
  name = "anchor"
  at = [-1, 0, )" + num(-delta) + R"(]
  [[body.marker]]
  name = "rail"
  z = [1, 0, 0]
  x = [0, 1, 0]
[[body]]
name = "belt"
type = "rigid"
mass = 1e8
inertia = [1e8, 1e8, 1e8]
velocity = [)" + num(vb) + R"(, 0, 0]
  [[body.marker]]
  name = "surface"
  [[body.marker]]
  name = "rail"
  z = [1, 0, 0]
  x = [0, 1, 0]
[[body]]
name = "block"
type = "point-mass"
mass = )" + num(m) + R"(
position = [0, 0, )" + num(-delta) + R"(]
velocity = [)" + num(vb) + R"(, 0, 0]
  [[body.marker]]
  name = "c"
[[joint]]
name = "belt_guide"
type = "prismatic"
i = "belt.rail"
j = "ground.rail"
[[force]]
name = "friction"
type = "contact"
i = "block.c"
j = "belt.surface"
stiffness = )" + num(kc) + R"(
exponent = 1
restitution = 0.1
mu_static = )" + num(mus) + R"(
mu_dynamic = )" + num(mud) + R"(
stribeck_speed = 2e-5
regularization_speed = 2e-7
[[force]]
name = "spring"
type = "spring-damper"
i = "block.c"
j = "ground.anchor"
k = )" + num(k) + R"(
free_length = 1.0
[[load]]
name = "press"
type = "force"
at = "block.c"
direction = [0, 0, -1]
table = [[0, )" + num(n) + "], [100, " + num(n) + R"(]]
[clock]
end_time = 3.0
[integrator]
rtol = 1e-8
atol = 1e-11
[output]
sample_rate_hz = 10000
)";
  const auto file = run_text(text, "stick_slip");
  const Eigen::VectorXd t = signal(file, "time"), x = signal(file, "markers/block.c/position", 0);
  const auto maxima = extrema(t, x, +1), minima = extrema(t, x, -1);
  ASSERT_GE(maxima.size(), 3u);
  ASSERT_GE(minima.size(), 3u);
  double emax = 0, emin = 0;
  for (const auto& e : maxima) emax = std::max(emax, std::abs(e.value - (xd + a)));
  for (const auto& e : minima) emin = std::max(emin, std::abs(e.value - (xd - a)));
  const double t_period = (maxima.back().t - maxima.front().t) / static_cast<double>(maxima.size() - 1);
  std::printf("measured: stick-slip, %zu cycles: maxima error %.3g m (x_d + A = %.6g m), minima error %.3g m "
              "(x_d - A = %.6g m), period %.6g s (closed form %.6g s), first maximum at %.6g s (closed form %.6g s)\n",
              maxima.size(), emax, xd + a, emin, xd - a, t_period, period, maxima.front().t, t_max1);
  // Tolerances: the smooth law peaks just below mu_s (at v of a few v_eps), its break-away is delayed by the
  // slow passage through that peak while the spring force rises at k v_b, and it reaches mu_d only after a
  // slip speed of about 2 v_s: errors that shrink with v_s (measured: 6.6e-5 m and 1.5e-3 of the period at
  // v_s = 1e-4, v_eps = 1e-6; 1.1e-5 m and 2.4e-4 at the 2e-5, 2e-7 used here).
  EXPECT_NEAR(maxima.front().value, xd + a, 0.002 * a);  // 4.5e-5 m
  EXPECT_LT(emax, 0.002 * a);
  EXPECT_LT(emin, 0.002 * a);
  EXPECT_NEAR(t_period, period, 1e-3 * period);
  EXPECT_NEAR(maxima.front().t, t_max1, 1e-3 * period);
}

// ==================================================================== non-linear spring-damper
// f = k(dx) dx with k = k0 + kB (dx / xB)^2 (docs/scene-format.md): f = k0 dx + (kB / xB^2) dx^3.
// Static deflection of a hanging mass: k0 x + (kB / xB^2) x^3 = m g, a depressed cubic x^3 + p x + q = 0 with
// p = k0 xB^2 / kB > 0, q = -m g xB^2 / kB: one real root by Cardano's formula,
//   x = cbrt(-q/2 + sqrt(q^2/4 + p^3/27)) + cbrt(-q/2 - sqrt(q^2/4 + p^3/27)).
TEST(NonlinearSpringDamper, StaticDeflectionFromTheCubic) {
  const double m = 2.0, k0 = 1000, kb = 5000, xb = 0.01, l = 0.5;
  const double p = k0 * xb * xb / kb, q = -m * kG * xb * xb / kb, s = std::sqrt(q * q / 4 + p * p * p / 27);
  const double x_ref = std::cbrt(-q / 2 + s) + std::cbrt(-q / 2 - s);
  const std::string text = std::string("[scene]\ngravity = [0, 0, -9.81]\n") + kGround + R"(
[[body]]
name = "mass"
type = "point-mass"
mass = )" + num(m) + R"(
position = [0, 0, )" + num(-l) + R"(]
  [[body.marker]]
  name = "c"
[[force]]
name = "spring"
type = "spring-damper"
i = "mass.c"
j = "ground.o"
k = )" + num(k0) + R"(
kB = )" + num(kb) + R"(
xB = )" + num(xb) + R"(
d = 60
free_length = )" + num(l) + R"(
[clock]
end_time = 1.5
[integrator]
rtol = 1e-10
atol = 1e-13
[output]
sample_rate_hz = 1000
)";
  const auto file = run_text(text, "nonlinear_static");
  const Eigen::VectorXd dx = signal(file, "forces/spring/deflection"), z = signal(file, "markers/mass.c/position", 2);
  const double x = -z[z.size() - 1] - l;
  std::printf("measured: non-linear spring, rest deflection %.10g m (Cardano %.10g m; linear would give %.6g m); "
              "channel deflection %.10g m\n", x, x_ref, m * kG / k0, dx[dx.size() - 1]);
  EXPECT_NEAR(x, x_ref, 1e-9);  // m; zeta ~ 0.25 at ~60 rad/s: exp(-22) of the 6 mm transient left at 1.5 s
  EXPECT_NEAR(dx[dx.size() - 1], x_ref, 1e-9);
}

// The undamped oscillation of amplitude A (released at rest) has the period of the conservative system
//   T = 4 int_0^A dx / sqrt(2 (V(A) - V(x)) / m),  V(x) = k0 x^2 / 2 + kB x^4 / (4 xB^2)
// (Landau & Lifshitz, Mechanics, section 11, eq. 11.5); with x = A sin(u) the singularity goes:
//   T = 4 int_0^{pi/2} du / sqrt((2 / m)(k0 / 2 + kB A^2 (1 + sin^2 u) / (4 xB^2))),
// a smooth integral computed here by composite Simpson's rule (2000 intervals; error ~ 1e-15).
TEST(NonlinearSpringDamper, PeriodByQuadratureOfThePotential) {
  const double m = 1.0, k0 = 1000, kb = 5000, xb = 0.01, amp = 0.02, l = 1.0;
  auto integrand = [&](double u) {
    const double sn = std::sin(u);
    return 1.0 / std::sqrt((2 / m) * (k0 / 2 + kb * amp * amp * (1 + sn * sn) / (4 * xb * xb)));
  };
  const int n = 2000;
  const double h = (kPi / 2) / n;
  double sum = integrand(0) + integrand(kPi / 2);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4 : 2) * integrand(i * h);
  const double t_ref = 4 * sum * h / 3;
  const std::string text = std::string(kGround) + R"(
[[body]]
name = "mass"
type = "point-mass"
mass = )" + num(m) + R"(
position = [)" + num(l + amp) + R"(, 0, 0]
  [[body.marker]]
  name = "c"
[[force]]
name = "spring"
type = "spring-damper"
i = "mass.c"
j = "ground.o"
k = )" + num(k0) + R"(
kB = )" + num(kb) + R"(
xB = )" + num(xb) + R"(
free_length = )" + num(l) + R"(
[clock]
end_time = 1.0
[integrator]
rtol = 1e-10
atol = 1e-13
[output]
sample_rate_hz = 20000
)";
  const auto file = run_text(text, "nonlinear_period");
  const Eigen::VectorXd t = signal(file, "time"), x = signal(file, "markers/mass.c/position", 0);
  const auto up = upward_crossings(t, x, l);
  ASSERT_GE(up.size(), 3u);
  const double period = (up.back() - up.front()) / static_cast<double>(up.size() - 1);
  const auto maxima = extrema(t, x, +1);
  double eamp = 0;
  for (const auto& e : maxima) eamp = std::max(eamp, std::abs(e.value - l - amp));
  std::printf("measured: non-linear spring, period %.10g s (quadrature %.10g s; linear 2 pi sqrt(m/k0) = %.6g s); "
              "amplitude kept within %.3g m\n", period, t_ref, 2 * kPi * std::sqrt(m / k0), eamp);
  EXPECT_NEAR(period, t_ref, 1e-6 * t_ref);  // crossings interpolated linearly at 50 us sampling
  EXPECT_LT(eamp, 1e-7);                     // m: energy conserved (no damper), amplitude A kept
}

}  // namespace
}  // namespace nvh::solve
