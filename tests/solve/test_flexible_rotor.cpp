// The flexible body on a fixed axis (solve/flexible_rotor_body.hpp: `axis` on a flexible body) against
// references not computed with it:
//   1. a uniform beam clamped at its root in condense and turned on a fixed axis there is the pinned-free
//      beam in its plane of rotation and the clamped-free beam out of it: the linearised modes against the
//      Euler-Bernoulli frequency factors of R. D. Blevins, Formulas for Natural Frequency and Mode Shape
//      (Van Nostrand 1979), table 8-1 (pinned-free: beta L = 3.92660, 7.06858, 10.21018; clamped-free
//      1.87510, 4.69409, 7.85476): f = (beta L)^2 / (2 pi L^2) sqrt(E I / (rho A));
//      with `mode_numbers`, only the in-plane modes of a rod stiffer in its plane, the same in-plane
//      frequencies and no out-of-plane mode;
//   2. the model's analytic Jacobian against central differences of its residual (jacobian_check.hpp);
//   3. a flexible pendulum (a Craig-Bampton rod falling from the horizontal): on the fixed axis and as a
//      floating frame on a revolute joint, whose bases span the same motions, the tip's path, and its energy
//      balance; by generalized-alpha against IDA; stiff and damped, the support's reaction against the rigid
//      pendulum's closed form;
//   4. the errors a bad scene gets.
#include <gtest/gtest.h>

#include <unistd.h>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <sstream>

#include "common/log.hpp"
#include "common/provenance.hpp"
#include "condense/condense.hpp"
#include "jacobian_check.hpp"
#include "solve/flexible_rotor_body.hpp"
#include "solve/linearize.hpp"
#include "solve/scene.hpp"
#include "solve_fixture.hpp"
#include "tests/condense/beam_fixtures.hpp"

namespace nvh::solve {
namespace {

namespace fs = std::filesystem;
using condense::testing::circle;
using condense::testing::point;
using condense::testing::Steel;
using condense::testing::straight_beam;
constexpr double kPi = std::numbers::pi;
constexpr double kLength = 1.0, kDiameter = 0.02;  // m: the steel rod of test_jacobian_flexible.cpp

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("nvh_flexrotor_" + std::to_string(::getpid()) + "_" + name);
  fs::create_directories(d);
  return d;
}

/// The rod along x from the origin, 32 Euler-Bernoulli elements (no rotary inertia). `clamped`: held in all
/// six DOF at the root (an observation point "a" there), else free with an interface "a" at the root; an
/// interface "b" at the tip either way. Craig-Bampton with `modes` fixed-interface modes, or a modal
/// reduction of `modes` modes (the clamped rod only).
void write_rod(const fs::path& file, bool clamped, condense::ReductionMethod method, int modes,
               double diameter = kDiameter, double damping = 0.0, double iz_factor = 1.0) {
  condense::BeamSection s = circle(diameter);
  s.Iz *= iz_factor;  // bending in the x-y plane, the plane of rotation about z
  s.rotary_inertia = false;
  condense::Component c = straight_beam(kLength, s, 32, Steel{});
  c.interfaces = {point("b", {kLength, 0, 0})};
  if (clamped) {
    condense::Support root;
    root.at = {0, 0, 0};
    root.dofs.fill(true);
    root.path = "fix[1]";
    c.supports = {root};
    c.observers = {point("a", {0, 0, 0})};
    if (method == condense::ReductionMethod::kModal)
      c.interfaces.clear(), c.observers.push_back(point("b", {kLength, 0, 0}));
  } else {
    c.interfaces.insert(c.interfaces.begin(), point("a", {0, 0, 0}));
  }
  c.reduction.method = method;
  c.reduction.orthonormalize = true;
  c.reduction.damping_ratio = damping;
  c.reduction.modes = modes;
  std::ostringstream quiet;
  const Logger log(quiet, "test", Verbosity::kQuiet);
  condense::write_superelement(file,
                               condense::condense_component(c, condense::EigenBackend::kBlockLanczos, log),
                               make_provenance("test", 0, nullptr, {}));
}

std::string rotor_scene(const std::string& superelement, const std::string& gravity,
                        const std::string& extra = "") {
  return "[scene]\ngravity = " + gravity +
         "\n[[body]]\nname = \"rod\"\ntype = \"flexible\"\nsuperelement = \"" + superelement +
         "\"\naxis = [0, 0, 1]\n" + extra + "[clock]\nend_time = 0.01\n";
}

/// The model linearised at its consistent start.
Linearization linearized_at_rest(Model& model) {
  std::ostringstream sink;
  const Logger log(sink, "test", Verbosity::kQuiet);
  Eigen::VectorXd y, yp;
  model.consistent_initial_state(0.0, y, yp, log);
  return linearize(model, 0.0, y, yp);
}

// ---------------------------------------------------------------- 1. the pinned-free rod
TEST(FlexibleRotor, ClampedRodOnTheAxisHasThePinnedFreeFrequencies) {
  const fs::path dir = temp_dir("blevins");
  write_rod(dir / "rod.h5", true, condense::ReductionMethod::kModal, 24);
  Scene s = parse_scene(rotor_scene("rod.h5", "[0, 0, 0]"), "rod.toml", dir);
  ASSERT_EQ(s.model.bodies[0]->kind(), "flexible-rotor");
  ASSERT_EQ(s.model.bodies[0]->state_count(), 2 * (1 + 24));  // theta, eta and their rates: no multiplier
  const Linearization lin = linearized_at_rest(s.model);

  const double area = kPi * kDiameter * kDiameter / 4, inertia = kPi * std::pow(kDiameter, 4) / 64;
  const Steel steel;
  const double scale = std::sqrt(steel.E * inertia / (steel.rho * area)) / (2 * kPi * kLength * kLength);
  auto nearest = [&](double f) {
    double best = 1e300;
    for (const LinearMode& m : lin.modes)
      if (std::abs(m.frequency_hz() - f) < std::abs(best - f)) best = m.frequency_hz();
    return best;
  };
  double worst_pinned = 0, worst_clamped = 0;
  for (double beta : {3.92660231, 7.06858275, 10.21017612}) {  // in the plane of rotation (x-y)
    const double f = beta * beta * scale, got = nearest(f);
    std::printf("measured: pinned-free  %9.4f Hz against Blevins %9.4f Hz (%+.1e)\n", got, f, got / f - 1);
    worst_pinned = std::max(worst_pinned, std::abs(got / f - 1));
  }
  for (double beta : {1.87510407, 4.69409113, 7.85475744}) {  // out of it (x-z): the axis holds the root
    const double f = beta * beta * scale, got = nearest(f);
    std::printf("measured: clamped-free %9.4f Hz against Blevins %9.4f Hz (%+.1e)\n", got, f, got / f - 1);
    worst_clamped = std::max(worst_clamped, std::abs(got / f - 1));
  }
  // The rod's discretization and the clamped basis truncated at 24 modes (the pinned-free shapes are
  // expanded in cantilever modes): measured 1.4e-5 at most (the third pinned-free mode).
  EXPECT_LT(worst_pinned, 5e-5);
  EXPECT_LT(worst_clamped, 1e-5);
  fs::remove_all(dir);
}

// 1b. `mode_numbers`: the rod twice as stiff in its plane of rotation (Iz = 2 Iy, so the two planes' modes
// separate), only its in-plane bending modes chosen by number (those whose tip moves along y): the
// pinned-free frequencies of the in-plane stiffness stay, and no out-of-plane mode is left (the lowest,
// clamped-free 1.875^2 with Iy, would be at 14.5 Hz).
TEST(FlexibleRotor, ChosenModeNumbersKeepThePlaneOfRotation) {
  const fs::path dir = temp_dir("numbers");
  write_rod(dir / "rod.h5", true, condense::ReductionMethod::kModal, 24, kDiameter, 0.0, 2.0);
  const FlexibleData all = load_flexible_data(dir / "rod.h5");
  const int tip = all.points[0].name == "b" ? 0 : 1;
  std::string numbers;
  int chosen = 0;
  for (int j = 0; j < all.size(); ++j) {
    const Vec3 u = all.points[tip].translation.col(j).cwiseAbs();
    if (u.y() > 10 * u.z() && u.y() > 10 * u.x()) numbers += (chosen++ ? ", " : "") + std::to_string(j + 1);
  }
  ASSERT_GE(chosen, 3);
  Scene s =
      parse_scene(rotor_scene("rod.h5", "[0, 0, 0]", "mode_numbers = [" + numbers + "]\n"), "rod.toml", dir);
  ASSERT_EQ(s.model.bodies[0]->state_count(), 2 * (1 + chosen));
  const Linearization lin = linearized_at_rest(s.model);
  const double area = kPi * kDiameter * kDiameter / 4, iy = kPi * std::pow(kDiameter, 4) / 64;
  const Steel steel;
  const double scale = std::sqrt(steel.E * 2 * iy / (steel.rho * area)) / (2 * kPi * kLength * kLength);
  double worst = 0;
  for (int k = 0; k < 3; ++k) {
    const double beta = std::array<double, 3>{3.92660231, 7.06858275, 10.21017612}[k];
    const double f = beta * beta * scale, got = lin.modes[k].frequency_hz();
    worst = std::max(worst, std::abs(got / f - 1));
  }
  const double out_of_plane = 1.87510407 * 1.87510407 * scale / std::sqrt(2.0);
  std::printf(
      "measured: mode numbers [%s] of 24: pinned-free frequencies within %.1e; lowest mode %.3f Hz "
      "(the out-of-plane clamped-free %.3f Hz is gone)\n",
      numbers.c_str(), worst, lin.modes.front().frequency_hz(), out_of_plane);
  EXPECT_LT(worst, 1e-4);
  EXPECT_GT(lin.modes.front().frequency_hz(), 2 * out_of_plane);
  fs::remove_all(dir);
}

// ---------------------------------------------------------------- 2. the analytic Jacobian
TEST(FlexibleRotor, ModelJacobianMatchesDifferencesOfTheResidual) {
  const fs::path dir = temp_dir("jacobian");
  write_rod(dir / "rod.h5", true, condense::ReductionMethod::kCraigBampton, 4);
  // The rod on its axis, turning, a tip spring to a rigid body, a torque at the tip, gravity off the plane.
  const std::string extra = R"(speed = 3.0
[[body]]
name = "r"
type = "rigid"
mass = 2.0
inertia = [0.05, 0.04, 0.06, 0.001, 0.002, 0.003]
position = [1.05, 0.1, 0.02]
[[body.marker]]
name = "m"
[[force]]
name = "s"
type = "spring-damper"
i = "rod.b"
j = "r.m"
k = 1.0e4
d = 30.0
free_length = 0.1
[[load]]
name = "tq"
type = "torque"
at = "rod.b"
direction = [0.3, 0.2, 1.0]
axes = "marker"
table = [[0.0, 5.0], [1.0, 5.0]]
)";
  double worst = 0;
  for (unsigned seed : {1u, 2u, 3u}) {
    Scene s = parse_scene(rotor_scene("rod.h5", "[0, -9.81, 2.0]", extra), "rod.toml", dir);
    const testing::Comparison r = testing::compare(s, seed, 1.0, 1e-2);
    worst = std::max(worst, r.worst);
    EXPECT_LT(r.worst, 1e-6) << "seed " << seed << ": worst at " << r.where;
    EXPECT_LT(r.outside, 1e-9) << "the differences have entries outside the sparsity pattern";
  }
  std::printf("measured: worst relative error of the model's Jacobian %.2e\n", worst);
  fs::remove_all(dir);
}

// ---------------------------------------------------------------- 3. the pendulum
// The rod falls from the horizontal under gravity, pivoted at its root (about z), and swings through the
// bottom in 0.6 s.
std::string pendulum(bool on_axis, const std::string& superelement) {
  std::string s = "[scene]\ngravity = [0, -9.81, 0]\n";
  if (on_axis) {
    s += "[[body]]\nname = \"rod\"\ntype = \"flexible\"\nsuperelement = \"" + superelement +
         "\"\naxis = [0, 0, 1]\n";
  } else {
    s += "[[body]]\nname = \"ground\"\ntype = \"ground\"\n[[body.marker]]\nname = \"pin\"\n"
         "[[body]]\nname = \"rod\"\ntype = \"flexible\"\nsuperelement = \"" +
         superelement +
         "\"\n"
         "[[joint]]\nname = \"pin\"\ntype = \"revolute\"\ni = \"rod.a\"\nj = \"ground.pin\"\n";
  }
  return s + R"([clock]
end_time = 0.6
[integrator]
rtol = 1e-8
atol = 1e-11
max_step = 1e-4
[output]
sample_rate_hz = 2000
markers = ["rod.b"]
)";
}

// 3a. The same flexible pendulum (the 20 mm rod, undamped) on the fixed axis and as a floating frame on a
// revolute joint at its root. The free Craig-Bampton rod with interfaces at root and tip and 4
// fixed-interface modes has 6 rigid and 12 + 4 - 6 elastic coordinates, of which the joint's 5 equations
// leave 11 motions; the rod clamped at the root, with the tip's interface and the same 4 fixed-interface
// modes, has theta and 6 + 4 coordinates on the axis: 11 again, and the spans agree. The frames differ (the
// free basis's floating frame, the root's own section), which changes the kinematics only at second order in
// the deformation (a sag of 1.8 mm under the rod's weight).
TEST(FlexibleRotor, PendulumFollowsTheFloatingFrameOnARevoluteJoint) {
  const fs::path dir = temp_dir("pendulum");
  write_rod(dir / "clamped.h5", true, condense::ReductionMethod::kCraigBampton, 4);
  write_rod(dir / "free.h5", false, condense::ReductionMethod::kCraigBampton, 4);
  RunSummary sa, sj;
  const fs::path a =
      testing::run_text_at(pendulum(true, "clamped.h5"), "on_axis", dir, dir / "on_axis.h5", &sa);
  const fs::path j =
      testing::run_text_at(pendulum(false, "free.h5"), "on_joint", dir, dir / "on_joint.h5", &sj);
  const Eigen::MatrixXd tip_a = testing::matrix(a, "markers/rod.b/position"),
                        tip_j = testing::matrix(j, "markers/rod.b/position");
  ASSERT_EQ(tip_a.rows(), tip_j.rows());
  EXPECT_LT(tip_a.col(1).minCoeff(), -0.99);  // through the bottom
  const double path = (tip_a - tip_j).rowwise().norm().maxCoeff();
  std::printf(
      "measured: the tip's paths apart by at most %.2e m over 0.6 s; steps %ld on the axis, %ld on "
      "the joint\n",
      path, static_cast<long>(sa.statistics.steps), static_cast<long>(sj.statistics.steps));
  EXPECT_LT(path, 2e-5);  // m, of a 1 m swing
  // Undamped and without contacts, the energy balance closes (the rod's fall releases m g L / 2 = 12.1 J).
  const double balance_a = testing::signal(a, "energy/balance").cwiseAbs().maxCoeff(),
               balance_j = testing::signal(j, "energy/balance").cwiseAbs().maxCoeff();
  std::printf("measured: energy balance at most %.2e J on the axis, %.2e J on the joint\n", balance_a,
              balance_j);
  EXPECT_LT(balance_a, 1e-9 * 12.1);  // J; measured 1.6e-10
  fs::remove_all(dir);
}

// 3c. The same pendulum on the axis by generalized-alpha (20 us, rho_inf 0.8): second order, so the tip's
// path follows IDA's (rtol 1e-8) to the method's error at that step.
TEST(FlexibleRotor, PendulumByGeneralizedAlphaFollowsIda) {
  const fs::path dir = temp_dir("galpha");
  write_rod(dir / "clamped.h5", true, condense::ReductionMethod::kCraigBampton, 4);
  std::string text = pendulum(true, "clamped.h5");
  const std::string ida = "rtol = 1e-8\natol = 1e-11\nmax_step = 1e-4\n";
  text.replace(text.find(ida), ida.size(), "method = \"generalized-alpha\"\nstep = 2e-5\nrho_inf = 0.8\n");
  const fs::path g = testing::run_text_at(text, "galpha", dir, dir / "galpha.h5");
  const fs::path a = testing::run_text_at(pendulum(true, "clamped.h5"), "ida", dir, dir / "ida.h5");
  const Eigen::MatrixXd tip_g = testing::matrix(g, "markers/rod.b/position"),
                        tip_a = testing::matrix(a, "markers/rod.b/position");
  ASSERT_EQ(tip_g.rows(), tip_a.rows());
  const double path = (tip_g - tip_a).rowwise().norm().maxCoeff();
  std::printf("measured: generalized-alpha's tip path against IDA's at most %.2e m over 0.6 s\n", path);
  EXPECT_LT(path, 5e-6);  // m, of a 1 m swing (measured 5.4e-7)
  fs::remove_all(dir);
}

// 3b. The support's reaction against the rigid pendulum's closed form: a stiff rod (60 mm: sag 0.2 mm) with
// 5 % modal damping, whose release transient has died out after 0.05 s, is the uniform rod of mass m pivoted
// at its end: at the angle phi below the horizontal (from the tip's position), phi'^2 = 3 g sin(phi) / L,
// phi'' = 3 g cos(phi) / (2 L), the centre of mass at L/2 (cos phi, -sin phi), and the pivot's force on the
// rod F = m a_cm - m g.
TEST(FlexibleRotor, SupportForceIsTheRigidPendulumsReaction) {
  const fs::path dir = temp_dir("support");
  constexpr double d = 0.06, g = 9.81;
  write_rod(dir / "clamped.h5", true, condense::ReductionMethod::kCraigBampton, 4, d, 0.05);
  const fs::path a = testing::run_text_at(pendulum(true, "clamped.h5"), "on_axis", dir, dir / "on_axis.h5");
  const Eigen::MatrixXd tip = testing::matrix(a, "markers/rod.b/position"),
                        force = testing::matrix(a, "bodies/rod/support_force"),
                        torque = testing::matrix(a, "bodies/rod/support_torque");
  const Eigen::VectorXd time = testing::signal(a, "time");
  const double m = Steel{}.rho * kPi * d * d / 4 * kLength;
  double worst = 0, peak = 0, axial = 0;
  for (Eigen::Index k = 0; k < time.size(); ++k) {
    if (time[k] < 0.05) continue;
    const double phi = std::atan2(-tip(k, 1), tip(k, 0));
    const double w2 = 3 * g * std::sin(phi) / kLength, alpha = 3 * g * std::cos(phi) / (2 * kLength);
    const Eigen::Vector2d a_cm(kLength / 2 * (-std::sin(phi) * alpha - std::cos(phi) * w2),
                               kLength / 2 * (-std::cos(phi) * alpha + std::sin(phi) * w2));
    const Eigen::Vector2d f = m * a_cm + Eigen::Vector2d(0, m * g);
    worst = std::max(worst, (force.row(k).head<2>().transpose() - f).norm());
    peak = std::max(peak, f.norm());
    axial = std::max(axial, std::abs(torque(k, 2)));
  }
  std::printf(
      "measured: support force against the rigid pendulum's %.3e N (peak %.1f N); its moment about "
      "the axis at most %.1e N m\n",
      worst, peak, axial);
  EXPECT_LT(worst, 1e-4 * peak);            // measured 1.3e-5 of it
  EXPECT_LT(axial, 1e-6 * peak * kLength);  // the axis carries no moment about itself
  fs::remove_all(dir);
}

// ---------------------------------------------------------------- 4. errors
TEST(FlexibleRotor, BadScenesAreRefusedWithTheKey) {
  const fs::path dir = temp_dir("errors");
  write_rod(dir / "free.h5", false, condense::ReductionMethod::kCraigBampton, 2);
  write_rod(dir / "clamped.h5", true, condense::ReductionMethod::kCraigBampton, 2);
  auto error = [&](const std::string& text) {
    try {
      parse_scene(text, "bad.toml", dir);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string free_on_axis = error(rotor_scene("free.h5", "[0, 0, 0]"));
  EXPECT_NE(free_on_axis.find(".superelement'"), std::string::npos) << free_on_axis;
  EXPECT_NE(free_on_axis.find("rigid-body modes"), std::string::npos) << free_on_axis;
  EXPECT_NE(free_on_axis.find("[[fix]]"), std::string::npos) << free_on_axis;
  const std::string velocity =
      error(rotor_scene("clamped.h5", "[0, 0, 0]", "angular_velocity = [0, 0, 1]\n"));
  EXPECT_NE(velocity.find(".angular_velocity'"), std::string::npos) << velocity;
  EXPECT_NE(velocity.find("`speed`"), std::string::npos) << velocity;
  const std::string zero =
      error(rotor_scene("clamped.h5", "[0, 0, 0]")
                .replace(rotor_scene("clamped.h5", "[0, 0, 0]").find("[0, 0, 1]"), 9, "[0, 0, 0]"));
  EXPECT_NE(zero.find(".axis'"), std::string::npos) << zero;
  const std::string both = error(rotor_scene("clamped.h5", "[0, 0, 0]", "modes = 1\nmode_numbers = [1]\n"));
  EXPECT_NE(both.find(".mode_numbers'"), std::string::npos) << both;
  const std::string beyond = error(rotor_scene("clamped.h5", "[0, 0, 0]", "mode_numbers = [1, 99]\n"));
  EXPECT_NE(beyond.find(".mode_numbers'"), std::string::npos) << beyond;
  EXPECT_NE(beyond.find("99"), std::string::npos) << beyond;
  const std::string order = error(rotor_scene("clamped.h5", "[0, 0, 0]", "mode_numbers = [2, 1]\n"));
  EXPECT_NE(order.find("ascending"), std::string::npos) << order;
  const std::string speed_alone = error(
      "[scene]\n[[body]]\nname = \"rod\"\ntype = \"flexible\"\nsuperelement = \"clamped.h5\"\nspeed = 2\n");
  EXPECT_NE(speed_alone.find(".speed'"), std::string::npos) << speed_alone;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace nvh::solve
