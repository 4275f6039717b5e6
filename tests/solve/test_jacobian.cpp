// The analytic Jacobian of the model (model.hpp) against central differences of the residual, per element
// type, joint and body type, at random states (issue 12: "a test per element type compares its analytic
// Jacobian with finite differences, 1e-6 relative").
//
// Oracle: J_fd(:, c) = [F(y + h e_c, y' + cj h e_c) - F(y - h e_c, y' - cj h e_c)] / (2 h), central differences
// of the residual alone (truncation O(h^2), h = 1e-6 relative), so J = dF/dy + cj dF/dy' is checked whole.
// Tolerance: |J - J_fd| <= 1e-6 * (largest |J_fd| of that row) + 1e-9 for every entry, and no entry of J_fd
// outside the sparsity pattern. Excluded by design (model.hpp): the energy integrals' rows (their powers feed
// nothing back) - and mu = 0 in the states (d(C^T mu)/dq is left out; mu = 0 on the solution).
#include <gtest/gtest.h>

#include <random>
#include <sstream>

#include "common/log.hpp"
#include "jacobian_check.hpp"
#include "solve/scene.hpp"

namespace nvh::solve {
namespace {

using testing::compare;
using testing::Comparison;

// Two rigid bodies with offset markers, joined by the element of `element` (TOML of its [[force]] table).
std::string two_bodies(const std::string& element, const std::string& extra = "") {
  return R"(
[scene]
gravity = [0, -9.81, 0]
[[body]]
name = "ground"
type = "ground"
[[body.marker]]
name = "o"
at = [0.0, 0.0, 0.0]
[[body]]
name = "a"
type = "rigid"
mass = 2.0
inertia = [0.02, 0.03, 0.04, 0.001, 0.002, 0.003]
position = [0.1, 0.2, 0.0]
angular_velocity = [1.0, 2.0, 3.0]
[[body.marker]]
name = "m"
at = [0.05, -0.02, 0.03]
z = [0.2, 0.3, 1.0]
[[body]]
name = "b"
type = "rigid"
mass = 3.0
inertia = [0.05, 0.04, 0.06]
position = [0.15, 0.25, 0.02]
orientation = [0.9, 0.1, 0.2, 0.3]
velocity = [0.5, -0.2, 0.1]
[[body.marker]]
name = "m"
at = [-0.03, 0.01, 0.04]
z = [0.1, -0.2, 1.0]
x = [1.0, 0.1, 0.0]
)" + element + extra + R"(
[clock]
end_time = 0.01
)";
}

Scene scene_of(const std::string& text) {
  return parse_scene(text, "jacobian.toml", std::filesystem::path(NVH_SOURCE_DIR) / "testdata/scenes");
}

void expect_exact(const std::string& text, const std::string& what, double tol = 1e-6) {
  for (unsigned seed : {1u, 2u, 3u}) {
    Scene s = scene_of(text);
    const Comparison c = compare(s, seed);
    EXPECT_LT(c.worst, tol) << what << " (seed " << seed << "): worst at " << c.where;
    EXPECT_LT(c.outside, 1e-9) << what << ": the differences have entries outside the sparsity pattern";
  }
}

TEST(AnalyticJacobian, RigidBodiesAndGravityAlone) {
  expect_exact(two_bodies(""), "two free rigid bodies");
}

TEST(AnalyticJacobian, LinearSpringDamper) {
  expect_exact(two_bodies(R"(
[[force]]
name = "s"
type = "spring-damper"
i = "a.m"
j = "b.m"
k = 1.0e5
d = 300.0
free_length = 0.02
preload = 40.0
)"), "spring-damper");
}

TEST(AnalyticJacobian, NonLinearSpringDamper) {
  expect_exact(two_bodies(R"(
[[force]]
name = "s"
type = "spring-damper"
i = "a.m"
j = "b.m"
k = 1.0e5
d = 300.0
kB = 2.0e5
dB = 100.0
xB = 0.01
free_length = 0.02
)"), "non-linear spring-damper");
}

TEST(AnalyticJacobian, Bushing) {
  expect_exact(two_bodies(R"(
[[force]]
name = "bush"
type = "bushing"
i = "a.m"
j = "b.m"
stiffness = [1e5, 2e5, 3e5, 1e3, 2e3, 3e3]
damping = [10, 20, 30, 0.1, 0.2, 0.3]
)"), "bushing");
}

TEST(AnalyticJacobian, TorsionalSpringDamperWithItsState) {
  expect_exact(two_bodies(R"(
[[force]]
name = "t"
type = "torsional-spring-damper"
i = "a.m"
j = "b.m"
k = 500.0
d = 2.0
angle0_deg = 10.0
)"), "torsional spring-damper");
}

// The contact law's keys (contact and point-set-contact): a negative clearance keeps the points in contact at
// every random state (marker a.m lies 1 mm beyond the plane of b.m).
const char* kContactLaw = R"(
stiffness = 1.0e8
exponent = 1.5
restitution = 0.6
clearance = -0.2
mu_static = 0.3
mu_dynamic = 0.2
stribeck_speed = 0.5
regularization_speed = 1.0
)";

TEST(AnalyticJacobian, ContactWithFrictionInContact) {
  expect_exact(two_bodies(std::string("[[force]]\nname = \"c\"\ntype = \"contact\"\ni = \"a.m\"\nj = \"b.m\"\n") + kContactLaw),
               "contact");
}

TEST(AnalyticJacobian, PointSetContactWithFriction) {
  // three points on body a (a.m and two more) against the plane of b.m
  std::string text = two_bodies(std::string("[[force]]\nname = \"skirt\"\ntype = \"point-set-contact\"\n"
                                            "points = [\"a.m\", \"a.m2\", \"a.m3\"]\nj = \"b.m\"\n") + kContactLaw);
  const std::string body_b = "[[body]]\nname = \"b\"";
  text.insert(text.find(body_b), R"([[body.marker]]
name = "m2"
at = [-0.04, 0.03, -0.02]
[[body.marker]]
name = "m3"
at = [0.02, 0.05, 0.01]
)");
  expect_exact(text, "point-set contact");
}

// The valve seat: a.m (the valve, at [0.15, 0.18, 0.03]) 50 mm into the seat of a ground marker along z, so
// that every random state (positions +-10 mm, rotations +-0.1 rad) is in contact; alpha = 0.15 s/m keeps the
// random speeds (a few m/s) out of the clamp.
TEST(AnalyticJacobian, ValveSeatInContact) {
  std::string text = two_bodies(R"(
[[force]]
name = "seat"
type = "valve-seat"
i = "a.m"
j = "ground.seat"
seat_diameter = 0.03
face_radius = 0.05
seat_angle_deg = 30.0
restitution = 0.9
)");
  const std::string body_a = "[[body]]\nname = \"a\"";
  text.insert(text.find(body_a), "[[body.marker]]\nname = \"seat\"\nat = [0.15, 0.18, 0.08]\n");
  expect_exact(text, "valve seat");
}

TEST(AnalyticJacobian, TableForceAndMotor) {
  expect_exact(two_bodies(R"(
[[force]]
name = "tab"
type = "table-force"
i = "a.m"
j = "b.m"
table = [[-1.0, 1.0e4], [0.0, 0.0], [1.0, -3.0e4]]
[[driver]]
name = "motor"
type = "motor"
i = "a.m"
j = "b.m"
table = [[-1000.0, 20.0], [0.0, 10.0], [3000.0, -5.0]]
)"), "table force and motor");
}

TEST(AnalyticJacobian, LoadsAgainstTimeCrankAngleAndHarmonic) {
  const std::string loads = R"(
[[load]]
name = "gas"
type = "force"
at = "a.m"
direction = [0.0, 1.0, 0.5]
axes = "marker"
abscissa = "crank-angle"
table = [[0.0, 0.0], [180.0, 100.0], [360.0, 20.0], [720.0, 0.0]]
[[load]]
name = "ft"
type = "torque"
at = "b.m"
direction = [1.0, 0.0, 0.0]
table = [[0.0, 1.0], [1.0, 3.0]]
[[load]]
name = "h"
type = "force"
at = "b.m"
direction = [0.0, 0.0, 1.0]
axes = "marker"
amplitude = 5.0
frequency_hz = 30.0
)";
  std::string text = two_bodies(loads);
  // a clock for the crank-angle load: a's rotation about the ground marker's z
  text.replace(text.find("[clock]"), 7, "[clock]\ni = \"a.m\"\nj = \"ground.o\"");
  expect_exact(text, "loads");
}

TEST(AnalyticJacobian, JournalBearingShortModel) {
  // a short bearing (closed form): journal a.m in shell b.m with a 50 um clearance; the markers coincide
  // (eccentricity 0 at the start; the random moves keep it below the clearance)
  std::string text = two_bodies(R"(
[[force]]
name = "jb"
type = "journal-bearing"
i = "a.m"
j = "b.m"
model = "short"
diameter = 0.05
width = 0.02
radial_clearance = 5.0e-3
viscosity = 0.01
)");
  text.replace(text.find("position = [0.15, 0.25, 0.02]"), 29, "position = [0.1, 0.2, 0.0]");
  text.replace(text.find("at = [-0.03, 0.01, 0.04]"), 24, "at = [0.05, -0.02, 0.03]");
  text.replace(text.find("orientation = [0.9, 0.1, 0.2, 0.3]"), 34, "");
  text.replace(text.find("z = [0.1, -0.2, 1.0]"), 20, "z = [0.2, 0.3, 1.0]");
  for (unsigned seed : {1u, 2u, 3u}) {
    Scene s = scene_of(text);
    const Comparison c = compare(s, seed, 0.02);
    // the surface-speed and torque columns come from forward differences inside the element: 1e-5
    EXPECT_LT(c.worst, 1e-5) << "journal bearing (seed " << seed << "): worst at " << c.where;
  }
}

TEST(AnalyticJacobian, JournalBearingFiniteModel) {
  // The finite (JFO) bearing: its whole film Jacobian by the implicit function theorem, no differences inside
  // the element. This checks the assembly into the model (kinematics, both markers); the film's own columns
  // (the torque's and the speeds' among them, small against a body's inertia rows here) are checked one by one
  // in tests/bearing/test_finite.cpp, FullJacobianWithTorqueAndSpeedsMatchesDifferencesOfSolves.
  std::string text = two_bodies(R"(
[[force]]
name = "jb"
type = "journal-bearing"
i = "a.m"
j = "b.m"
model = "finite"
grid = [40, 10]
diameter = 0.05
width = 0.02
radial_clearance = 5.0e-3
viscosity = 0.01
)");
  text.replace(text.find("position = [0.15, 0.25, 0.02]"), 29, "position = [0.1, 0.2, 0.0]");
  text.replace(text.find("at = [-0.03, 0.01, 0.04]"), 24, "at = [0.05, -0.02, 0.03]");
  text.replace(text.find("orientation = [0.9, 0.1, 0.2, 0.3]"), 34, "");
  text.replace(text.find("z = [0.1, -0.2, 1.0]"), 20, "z = [0.2, 0.3, 1.0]");
  for (unsigned seed : {1u, 2u, 3u}) {
    Scene s = scene_of(text);
    const Comparison c = compare(s, seed, 0.02);
    EXPECT_LT(c.worst, 1e-5) << "finite journal bearing (seed " << seed << "): worst at " << c.where;
  }
}

std::string jointed(const std::string& joint) {
  return two_bodies(R"(
[[joint]]
name = "j"
)" + joint + R"(
i = "a.m"
j = "b.m"
)");
}

TEST(AnalyticJacobian, JointsAndTheirReactions) {
  for (const std::string type : {"revolute", "spherical", "prismatic", "cylindrical", "in-line", "fixed"})
    expect_exact(jointed("type = \"" + type + "\""), type + " joint");
}

TEST(AnalyticJacobian, SpeedDriverAndClock) {
  std::string text = two_bodies(R"(
[[joint]]
name = "bearing"
type = "revolute"
i = "a.m"
j = "ground.o"
[[driver]]
name = "drive"
type = "speed"
i = "a.m"
j = "ground.o"
rpm = 1500.0
[[force]]
name = "s"
type = "spring-damper"
i = "b.m"
j = "a.m"
k = 1.0e4
d = 10.0
)");
  text.replace(text.find("[clock]"), 7, "[clock]\ni = \"a.m\"\nj = \"ground.o\"");
  expect_exact(text, "speed driver and clock");
}

TEST(AnalyticJacobian, PointMassOnASpring) {
  expect_exact(R"(
[scene]
gravity = [0, 0, -9.81]
[[body]]
name = "ground"
type = "ground"
[[body.marker]]
name = "o"
[[body]]
name = "p"
type = "point-mass"
mass = 0.5
position = [0.01, 0.02, 0.1]
velocity = [0.3, 0.0, -0.1]
[[body.marker]]
name = "m"
[[force]]
name = "s"
type = "spring-damper"
i = "p.m"
j = "ground.o"
k = 2.0e3
d = 3.0
free_length = 0.08
[clock]
end_time = 0.01
)", "point mass");
}

}  // namespace
}  // namespace nvh::solve
