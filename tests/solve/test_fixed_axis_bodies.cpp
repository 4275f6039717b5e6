// The slider and the rotor (solve/fixed_axis_body.hpp): rigid bodies of one coordinate on a fixed axis of the
// ground, against closed forms of classical mechanics, against the same bodies modelled as free rigid bodies
// with joints, and their analytic Jacobian against differences of the residual.
//
// References:
//   - the damped mass on a spring along an inclined guide: x(t) = x_eq + e^(-zeta w t) (x0 - x_eq)
//     (cos(w_d t) + zeta w / w_d sin(w_d t)), the guide's side force -m g_perp (gravity across the axis);
//   - the compound pendulum's period T = 4 sqrt(I_p / (m g L)) K(sin(theta0 / 2)), K the complete elliptic
//     integral of the first kind by the arithmetic-geometric mean, K(k) = pi / (2 AGM(1, sqrt(1 - k^2)))
//     (Abramowitz and Stegun 17.6.1); its pivot reaction from the energy integral omega^2 = 2 m g L (cos
//     theta - cos theta0) / I_p and alpha = -m g L sin(theta) / I_p: F = m a_cm - m g;
//   - a disc spinning at Omega with its symmetry axis tilted by beta from the shaft: the bearing moment of
//     dynamic imbalance |M| = Omega^2 (C - A) sin(beta) cos(beta), perpendicular to the shaft, turning with
//     it (Den Hartog, Mechanical Vibrations, 1956, section 6.4).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "jacobian_check.hpp"
#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::column;
using testing::matrix;
using testing::num;
using testing::run_text;
using testing::scene_error;
using testing::signal;

constexpr double kPi = std::numbers::pi;

// ------------------------------------------------------------------ slider
// A 2 kg slider on a guide inclined 30 deg in the x-y plane, gravity -y, on a spring-damper to the ground.
constexpr double kSliderMass = 2.0, kSliderK = 8.0e3, kSliderC = 8.0;
std::string slider_scene(const std::string& extra = "") {
  return R"(
[scene]
gravity = [0, -9.81, 0]
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "anchor"
  at = [-0.8660254037844386, -0.5, 0]
[[body]]
name = "s"
type = "slider"
axis = [0.8660254037844386, 0.5, 0]
mass = )" +
         num(kSliderMass) + R"(
position = [0, 0, 0]
speed = 0.3
  [[body.marker]]
  name = "hook"
  at = [0, 0, 0]
[[force]]
name = "spring"
type = "spring-damper"
i = "s.hook"
j = "ground.anchor"
k = )" + num(kSliderK) +
         R"(
d = )" + num(kSliderC) +
         R"(
free_length = 1.0
)" + extra +
         R"(
[clock]
end_time = 0.2
[integrator]
rtol = 1e-10
atol = 1e-12
[output]
sample_rate_hz = 2000
)";
}

TEST(Slider, DampedSpringOnAnInclinedGuideIsTheClosedForm) {
  const auto out = run_text(slider_scene(), "slider_spring");
  const Eigen::VectorXd t = signal(out, "time"), s = signal(out, "bodies/s/coordinate");
  // Along the axis: m s'' = -k s - c s' - m g sin(30 deg) (the spring is at its free length at s = 0).
  const double w = std::sqrt(kSliderK / kSliderMass),
               zeta = kSliderC / (2 * std::sqrt(kSliderK * kSliderMass));
  const double wd = w * std::sqrt(1 - zeta * zeta), x_eq = -kSliderMass * 9.81 * 0.5 / kSliderK;
  const double x0 = -x_eq, v0 = 0.3;  // relative to the equilibrium
  const Eigen::MatrixXd hook_acc = matrix(out, "markers/s.hook/acceleration");
  const Eigen::Vector3d axis(0.8660254037844386, 0.5, 0);
  double worst = 0, worst_acc = 0;
  for (Eigen::Index k = 0; k < t.size(); ++k) {
    const double e = std::exp(-zeta * w * t[k]), c = std::cos(wd * t[k]), sn = std::sin(wd * t[k]);
    const double b = (v0 + zeta * w * x0) / wd;
    const double x = x_eq + e * (x0 * c + b * sn);
    worst = std::max(worst, std::abs(s[k] - x));
    // s'' = -(k (s - x_eq) + c s') / m, along the axis (SliderBody::marker_acceleration)
    const double xr = e * (x0 * c + b * sn),
                 v = e * ((b * wd - zeta * w * x0) * c - (x0 * wd + zeta * w * b) * sn);
    worst_acc = std::max(
        worst_acc,
        (hook_acc.row(k).transpose() - (-(kSliderK * xr + kSliderC * v) / kSliderMass) * axis).norm());
  }
  std::printf("measured: the hook's acceleration against the closed form %.2e m/s^2\n", worst_acc);
  EXPECT_LT(worst_acc, 1e-5);  // m/s^2, of about 13 m/s^2 at the start (measured below 1e-6)
  std::printf("measured: slider coordinate against the closed form %.2e m (amplitude %.2e m)\n", worst,
              std::abs(x0) + v0 / w);
  EXPECT_LT(worst, 1e-9);  // metres
  // The guide carries gravity's part across the axis, nothing along it: F_s = -m (g - (g . a) a).
  const Eigen::MatrixXd f = matrix(out, "bodies/s/support_force");
  const Eigen::Vector3d a(0.8660254037844386, 0.5, 0), g(0, -9.81, 0);
  const Eigen::Vector3d expected = -kSliderMass * (g - g.dot(a) * a);
  double side = 0;
  for (Eigen::Index k = 0; k < f.rows(); ++k) side = std::max(side, (f.row(k).transpose() - expected).norm());
  std::printf("measured: the guide's side force against -m g_perp %.2e N (m g = %.2f N)\n", side,
              kSliderMass * 9.81);
  EXPECT_LT(side, 1e-6 * kSliderMass * 9.81);
  // The position follows the coordinate along the axis.
  const Eigen::MatrixXd p = matrix(out, "bodies/s/position");
  EXPECT_NEAR((p.row(p.rows() - 1).transpose() - s[s.size() - 1] * a).norm(), 0.0, 1e-12);
}

// ------------------------------------------------------------------ rotor: the compound pendulum
// A bar of 1.5 kg, I_cm = 0.02 kg m^2 about z, its centre of mass L = 0.25 m from the pivot, released at
// theta0 from the downward vertical; gravity -y, the axis z through the origin.
constexpr double kPendulumMass = 1.5, kPendulumInertia = 0.02, kPendulumArm = 0.25;
std::string pendulum_scene(double theta0, const std::string& body_type, double end_time) {
  const double x = kPendulumArm * std::sin(theta0), y = -kPendulumArm * std::cos(theta0);
  // The same body as a rotor, or as a rigid body on a revolute joint (the comparison).
  const bool rotor = body_type == "rotor";
  return R"(
[scene]
gravity = [0, -9.81, 0]
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "pin"
[[body]]
name = "bar"
type = ")" +
         body_type + R"("
)" + (rotor ? "axis = [0, 0, 1]\npivot = [0, 0, 0]\n" : "") +
         R"(mass = )" + num(kPendulumMass) + R"(
inertia = [0.01, 0.015, )" +
         num(kPendulumInertia) + R"(]
position = [)" +
         num(x) + ", " + num(y) + R"(, 0]
  [[body.marker]]
  name = "pin"
  at = [)" +
         num(-x) + ", " + num(-y) + R"(, 0]
  [[body.marker]]
  name = "cm"
)" + (rotor ? "" : R"(
[[joint]]
name = "pivot"
type = "revolute"
i = "bar.pin"
j = "ground.pin"
)") + R"(
[clock]
end_time = )" +
         num(end_time) + R"(
[integrator]
rtol = 1e-10
atol = 1e-12
[output]
sample_rate_hz = 20000
)";
}

/// The complete elliptic integral of the first kind K(k) by the arithmetic-geometric mean.
double elliptic_k(double k) {
  double a = 1, b = std::sqrt(1 - k * k);
  for (int i = 0; i < 30; ++i) {
    const double an = 0.5 * (a + b);
    b = std::sqrt(a * b), a = an;
  }
  return kPi / (2 * a);
}

TEST(Rotor, CompoundPendulumPeriodIsTheEllipticIntegral) {
  const double theta0 = 2.0;  // rad: a large swing, 33 % longer than the small-angle period
  const double ip = kPendulumInertia + kPendulumMass * kPendulumArm * kPendulumArm;
  const double period =
      4 * std::sqrt(ip / (kPendulumMass * 9.81 * kPendulumArm)) * elliptic_k(std::sin(theta0 / 2));
  const auto out = run_text(pendulum_scene(theta0, "rotor", 1.2 * period), "rotor_pendulum");
  const auto t = column(out, "time"), rate = column(out, "bodies/bar/coordinate_rate");
  // Released at rest, the bar swings back (rate < 0), stops at the far end (T/2), swings forward (rate > 0) and
  // stops again where it started (T): the one crossing of the rate from positive to 0.
  std::vector<double> crossings;
  for (std::size_t k = 1; k < t.size(); ++k)
    if (rate[k - 1] > 0 && rate[k] <= 0)  // the swing back ends (theta = theta0 again: t = T)
      crossings.push_back(t[k - 1] + (t[k] - t[k - 1]) * rate[k - 1] / (rate[k - 1] - rate[k]));
  ASSERT_EQ(crossings.size(), 1u) << "one full period in the run";
  std::printf("measured: period %.9f s, closed form %.9f s (%.1e)\n", crossings[0], period,
              crossings[0] / period - 1);
  // Linear interpolation of the rate near its zero (where it is smooth and steep) at 20 kHz: tolerance 1e-6 of
  // the period.
  EXPECT_NEAR(crossings[0], period, 1e-6 * period);
  // The energy is conserved (no damping): its balance over the run.
  const Eigen::VectorXd balance = signal(out, "energy/balance");
  EXPECT_LT(balance.cwiseAbs().maxCoeff(), 1e-7 * kPendulumMass * 9.81 * kPendulumArm);  // 4e-8 at rtol 1e-10
}

TEST(Rotor, MarkerAccelerationIsTangentialPlusCentripetal) {
  // The centre of mass of the swinging bar: a = L phi'' (cos phi, sin phi) + L phi'^2 (-sin phi, cos phi),
  // phi from the downward vertical, phi'' = -(m g L / I_pivot) sin phi (the pendulum's equation), phi and
  // phi' from the run. The rotor's closed form (RotorBody::marker_acceleration) and the rigid body's
  // difference of its marker Jacobian (Body's default) against it.
  const double theta0 = 2.0, ip = kPendulumInertia + kPendulumMass * kPendulumArm * kPendulumArm;
  const double scale = kPendulumMass * 9.81 * kPendulumArm / ip * kPendulumArm;  // |a| at most ~ 2 x this
  for (const std::string type : {"rotor", "rigid"}) {
    const auto out = run_text(pendulum_scene(theta0, type, 0.5), "rotor_acceleration_" + type);
    const Eigen::MatrixXd p = matrix(out, "bodies/bar/position"),
                          w = matrix(out, "bodies/bar/angular_velocity"),
                          a = matrix(out, "markers/bar.cm/acceleration");
    double err = 0;
    for (Eigen::Index k = 0; k < p.rows(); ++k) {
      const double phi = std::atan2(p(k, 0), -p(k, 1)), rate = w(k, 2);
      const double acc = -kPendulumMass * 9.81 * kPendulumArm / ip * std::sin(phi);
      const Eigen::Vector3d expected(kPendulumArm * (acc * std::cos(phi) - rate * rate * std::sin(phi)),
                                     kPendulumArm * (acc * std::sin(phi) + rate * rate * std::cos(phi)), 0);
      err = std::max(err, (a.row(k).transpose() - expected).norm());
    }
    std::printf("measured: %s, centre of mass acceleration against the closed form: %.2e of %.3f m/s^2\n",
                type.c_str(), err / scale, scale);
    // measured 1.6e-8 (rotor) and 2.5e-5 (rigid: its w' is IDA's on the revolute's index-2 rows, not
    // controlled by the error test, as for the valve tip of test_valvetrain_kinematics.cpp)
    EXPECT_LT(err, (type == "rotor" ? 1e-6 : 1e-4) * scale) << type;
  }
}

TEST(Rotor, PivotReactionIsNewtonEulersAndTheRevoluteJointsReaction) {
  const double theta0 = kPi / 2;  // released from the horizontal
  const double end = 0.6;
  const auto rotor = run_text(pendulum_scene(theta0, "rotor", end), "rotor_reaction");
  const auto rigid = run_text(pendulum_scene(theta0, "rigid", end), "rigid_reaction");
  const Eigen::VectorXd theta_r = signal(rotor, "bodies/bar/coordinate");
  const Eigen::MatrixXd f = matrix(rotor, "bodies/bar/support_force"),
                        tq = matrix(rotor, "bodies/bar/support_torque");
  const Eigen::MatrixXd fj = matrix(rigid, "joints/pivot/reaction_force");
  const double ip = kPendulumInertia + kPendulumMass * kPendulumArm * kPendulumArm;
  const double mgl = kPendulumMass * 9.81 * kPendulumArm;
  double worst = 0, worst_joint = 0, axial = 0;
  for (Eigen::Index k = 0; k < f.rows(); ++k) {
    const double th = theta0 + theta_r[k];  // from the downward vertical (the coordinate turns it about +z)
    const double w2 = 2 * mgl * (std::cos(th) - std::cos(theta0)) / ip, alpha = -mgl * std::sin(th) / ip;
    const Eigen::Vector3d d(kPendulumArm * std::sin(th), -kPendulumArm * std::cos(th), 0);
    const Eigen::Vector3d a_cm = alpha * Eigen::Vector3d(-d.y(), d.x(), 0) - w2 * d;  // alpha z x d - w^2 d
    const Eigen::Vector3d expected = kPendulumMass * (a_cm - Eigen::Vector3d(0, -9.81, 0));
    worst = std::max(worst, (f.row(k).transpose() - expected).norm());
    if (k < fj.rows()) worst_joint = std::max(worst_joint, (f.row(k) - fj.row(k)).norm());
    axial = std::max(axial, std::abs(tq(k, 2)));
  }
  const double scale = kPendulumMass * 9.81;
  std::printf(
      "measured: pivot force against the closed form %.2e N, against the revolute joint %.2e N (m g = "
      "%.2f N); moment about the axis %.2e N m\n",
      worst, worst_joint, scale, axial);
  EXPECT_LT(worst, 1e-6 * scale) << "against the closed form";
  EXPECT_LT(worst_joint, 1e-5 * scale) << "against the rigid body's revolute joint";
  EXPECT_LT(axial, 1e-6 * mgl) << "the bearing carries no moment about its own axis";
}

TEST(Rotor, TiltedDiscBearingMomentIsTheDynamicImbalance) {
  // A disc (A = 0.01, C = 0.02 kg m^2) with its symmetry axis tilted by beta about x, on a shaft along z,
  // spinning freely at Omega; no gravity. Its centre of mass is on the shaft: no bearing force.
  const double a_moment = 0.01, c_moment = 0.02, beta = 0.1, omega = 50.0;
  const double e0 = std::cos(beta / 2), e1 = std::sin(beta / 2);
  const std::string text = R"(
[[body]]
name = "ground"
type = "ground"
[[body]]
name = "disc"
type = "rotor"
axis = [0, 0, 1]
mass = 3.0
inertia = [)" + num(a_moment) +
                           ", " + num(a_moment) + ", " + num(c_moment) + R"(]
orientation = [)" + num(e0) +
                           ", " + num(e1) + R"(, 0, 0]
speed = )" + num(omega) + R"(
[clock]
end_time = 0.2
[integrator]
rtol = 1e-10
atol = 1e-12
[output]
sample_rate_hz = 1000
)";
  const auto out = run_text(text, "tilted_disc");
  const Eigen::MatrixXd m = matrix(out, "bodies/disc/support_torque"),
                        f = matrix(out, "bodies/disc/support_force");
  const Eigen::VectorXd rate = signal(out, "bodies/disc/coordinate_rate");
  const double expected = omega * omega * (c_moment - a_moment) * std::sin(beta) * std::cos(beta);
  std::printf("measured: bearing moment %.9f N m, closed form %.9f N m\n", m.row(m.rows() - 1).norm(),
              expected);
  for (Eigen::Index k = 0; k < m.rows(); ++k) {
    EXPECT_NEAR(m.row(k).norm(), expected, 1e-8 * expected) << "sample " << k;
    EXPECT_NEAR(m(k, 2), 0.0, 1e-8 * expected);
    EXPECT_LT(f.row(k).norm(), 1e-9);
    EXPECT_NEAR(rate[k], omega, 1e-9 * omega);  // no torque about the shaft: the speed stays
  }
  // It turns with the disc: at theta = 0 it lies along -x (the moment that would right the tilted disc, which
  // the bearing supplies: d H / dt = omega x H, H = J_g omega).
  const Eigen::Vector3d h0 =
      Eigen::Vector3d(0, -(c_moment - a_moment) * std::sin(beta) * std::cos(beta) * omega, 0);
  const Eigen::Vector3d m0 = Eigen::Vector3d(0, 0, omega).cross(h0);
  EXPECT_LT((m.row(0).transpose() - m0).norm(), 1e-8 * expected);
}

// ------------------------------------------------------------------ analytic Jacobian
// A rotor with an offset centre of mass and a tilted inertia, and a slider on an inclined guide, joined by a
// spring-damper and a contact with friction, under gravity; a rigid body jointed to the rotor by a spherical
// joint (the constraint rows of a rotor's marker).
TEST(FixedAxisBodies, AnalyticJacobianMatchesDifferences) {
  const std::string text = R"(
[scene]
gravity = [0.5, -9.81, 0.2]
[[body]]
name = "ground"
type = "ground"
[[body]]
name = "r"
type = "rotor"
axis = [0.1, 0.2, 1.0]
pivot = [0.01, -0.02, 0.0]
mass = 2.0
inertia = [0.02, 0.03, 0.04, 0.001, 0.002, 0.003]
position = [0.05, 0.02, 0.01]
orientation = [0.9, 0.1, 0.2, 0.3]
speed = 3.0
  [[body.marker]]
  name = "m"
  at = [0.05, -0.02, 0.03]
  z = [0.2, 0.3, 1.0]
  [[body.marker]]
  name = "ball"
  at = [-0.04, 0.01, 0.0]
[[body]]
name = "s"
type = "slider"
axis = [0.3, 1.0, -0.2]
mass = 1.5
position = [0.12, 0.25, 0.02]
orientation = [0.95, 0.0, 0.3, 0.1]
speed = -0.4
  [[body.marker]]
  name = "m"
  at = [-0.03, 0.01, 0.04]
  z = [0.1, -0.2, 1.0]
[[body]]
name = "link"
type = "rigid"
mass = 0.5
inertia = [0.001, 0.002, 0.0025]
position = [0.0, 0.0, 0.05]
  [[body.marker]]
  name = "ball"
  at = [0.01, 0.01, -0.05]
[[joint]]
name = "ball"
type = "spherical"
i = "link.ball"
j = "r.ball"
[[force]]
name = "spring"
type = "spring-damper"
i = "r.m"
j = "s.m"
k = 1.0e5
d = 300.0
free_length = 0.05
[[force]]
name = "touch"
type = "contact"
i = "s.m"
j = "r.m"
stiffness = 1e8
exponent = 1.5
restitution = 0.7
clearance = -0.5
mu_dynamic = 0.1
regularization_speed = 0.01
[clock]
end_time = 0.01
)";
  for (unsigned seed : {1u, 2u, 3u}) {
    Scene s = parse_scene(text, "fixed_axis_jacobian.toml", ".");
    const testing::Comparison c = testing::compare(s, seed);
    EXPECT_LT(c.worst, 1e-6) << "seed " << seed << ": worst at " << c.where;
    EXPECT_LT(c.outside, 1e-9) << "seed " << seed << ": differences outside the sparsity pattern";
  }
}

// ------------------------------------------------------------------ scene errors
TEST(FixedAxisBodies, BadKeysAreNamed) {
  const std::string head = R"(
[[body]]
name = "ground"
type = "ground"
[[body]]
name = "b"
)";
  auto error = [&](const std::string& body) {
    return scene_error(head + body + "\n[clock]\nend_time = 0.1\n");
  };
  EXPECT_NE(error("type = \"slider\"\nmass = 1\n").find("'body[2].axis'"), std::string::npos)
      << error("type = \"slider\"\nmass = 1\n");
  EXPECT_NE(error("type = \"slider\"\nmass = 1\naxis = [0, 0, 0]\n").find("the axis must not be zero"),
            std::string::npos);
  const std::string v = error("type = \"slider\"\nmass = 1\naxis = [0, 1, 0]\nvelocity = [0, 1, 0]\n");
  EXPECT_NE(v.find("'body[2].velocity'"), std::string::npos) << v;
  EXPECT_NE(v.find("`speed`"), std::string::npos) << v;
  const std::string i = error("type = \"slider\"\nmass = 1\naxis = [0, 1, 0]\ninertia = [1, 1, 1]\n");
  EXPECT_NE(i.find("'body[2].inertia'"), std::string::npos) << i;
  EXPECT_NE(error("type = \"rotor\"\nmass = 1\naxis = [0, 0, 1]\n").find("'body[2].inertia'"),
            std::string::npos);
  const std::string w = error(
      "type = \"rotor\"\nmass = 1\naxis = [0, 0, 1]\ninertia = [1, 1, 1]\nangular_velocity = [0, 0, 3]\n");
  EXPECT_NE(w.find("'body[2].angular_velocity'"), std::string::npos) << w;
  EXPECT_NE(error("type = \"rotor\"\nmass = 1\naxis = [0, 0, 1]\ninertia = [1, 1, 1]\nrpm = 3\n").find("rpm"),
            std::string::npos);
}

}  // namespace
}  // namespace nvh::solve
