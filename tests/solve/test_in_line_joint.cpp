// The in-line joint (point on line) as a piston's guidance without redundant equations: a slider-crank whose
// piston is held on its bore axis by an `in-line` joint at the pin and against tilting about the pin by an
// `in-plane` joint at a point of its axis, with a cylindrical small end (the pin free to float along its
// axis) and a revolute big end. Its kinematics and the guide's reactions against the closed-form slider-crank
// and the force balance of the piston; the Gruebler count (no redundant equation) against the classic
// prismatic/revolute guidance (3 redundant equations).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::num;
constexpr double kPi = std::numbers::pi;

// The engine's cylinder (docs/engine.md): crank radius r, conrod centres l, conrod mass m_c with its centre
// of mass a from the big end and the inertia m_c a (l - a) about its swing axis (dynamically two point
// masses: m_c (l - a) / l at the big end, m_c a / l at the small end), piston m_p; 2000 rpm.
constexpr double kR = 0.043, kL = 0.145, kA = 0.0456, kRodMass = 0.674, kPistonMass = 0.465;
constexpr double kRpm = 2000, kOmega = kRpm * 2 * kPi / 60;
// A constant gas force F on the crown along -y, applied delta off the axis (at height h above the pin): it
// turns the piston about its pin, which only the tilt stop holds.
constexpr double kGas = 1.0e4, kDelta = 0.002, kH = 0.030;

// Ground: the crank bearing (z the crank axis), the bore (z the cylinder axis +y, x the crank axis, so y_j
// is the lateral direction +x) and the tilt-stop plane (normal +x through the cylinder axis). Crank angle 0:
// the crank pin at +y (TDC); the crank turns about +z, so its pin is at r (-sin theta, cos theta).
std::string slider_crank(const std::string& guidance, const std::string& small_end) {
  const double iz = kRodMass * kA * (kL - kA);
  return R"(
[scene]
gravity = [0, 0, 0]
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "main"
  [[body.marker]]
  name = "bore"
  z = [0, 1, 0]
  x = [0, 0, 1]
  [[body.marker]]
  name = "tilt_plane"
  z = [1, 0, 0]
  x = [0, 1, 0]
[[body]]
name = "crank"
type = "rigid"
mass = 4.0
inertia = [0.01, 0.01, 0.02]
  [[body.marker]]
  name = "main"
  [[body.marker]]
  name = "pin"
  at = [0, )" +
         num(kR) + R"(, 0]
[[body]]
name = "conrod"
type = "rigid"
mass = )" +
         num(kRodMass) + R"(
inertia = [)" +
         num(iz) + ", 1.5e-4, " + num(iz) + R"(]
position = [0, )" +
         num(kR + kA) + R"(, 0]
  [[body.marker]]
  name = "big_end"
  at = [0, )" +
         num(-kA) + R"(, 0]
  [[body.marker]]
  name = "small_end"
  at = [0, )" +
         num(kL - kA) + R"(, 0]
[[body]]
name = "piston"
type = "rigid"
mass = )" +
         num(kPistonMass) + R"(
inertia = [3.5e-4, 4.3e-4, 3.5e-4]
position = [0, )" +
         num(kR + kL) + R"(, 0]
  [[body.marker]]
  name = "pin"
  [[body.marker]]
  name = "slide"
  z = [0, 1, 0]
  x = [0, 0, 1]
  [[body.marker]]
  name = "axis_top"
  at = [0, )" +
         num(kH) + R"(, 0]
  [[body.marker]]
  name = "crown"
  at = [)" +
         num(kDelta) + ", " + num(kH) + R"(, 0]
[[joint]]
name = "main_bearing"
type = "revolute"
i = "crank.main"
j = "ground.main"
[[joint]]
name = "big_end"
type = "revolute"
i = "conrod.big_end"
j = "crank.pin"
[[joint]]
name = "small_end"
type = ")" +
         small_end + R"("
i = "piston.pin"
j = "conrod.small_end"
)" + guidance +
         R"(
[[driver]]
name = "speed"
type = "speed"
i = "crank.main"
j = "ground.main"
rpm = )" +
         num(kRpm) + R"(
[[load]]
name = "gas"
type = "force"
at = "piston.crown"
direction = [0, -1, 0]
abscissa = "time"
table = [[0, 1], [1, 1]]
scale = )" +
         num(kGas) + R"(
[clock]
end_time = 0.03
[integrator]
rtol = 1e-10
atol = 1e-12
max_step = 1e-4
[output]
sample_rate_hz = 20000
)";
}

const char* kInLineGuidance = R"(
[[joint]]
name = "guide"
type = "in-line"
i = "piston.slide"
j = "ground.bore"
[[joint]]
name = "tilt_stop"
type = "in-plane"
i = "piston.axis_top"
j = "ground.tilt_plane"
)";

const char* kPrismaticGuidance = R"(
[[joint]]
name = "guide"
type = "prismatic"
i = "piston.slide"
j = "ground.bore"
)";

// Run the scene; return the results file and the number of equations found redundant (and removed).
std::filesystem::path run(const std::string& text, const std::string& name, int& redundant) {
  Scene scene = parse_scene(text, name + ".toml", std::filesystem::path(NVH_SOURCE_DIR) / "testdata/scenes");
  std::ostringstream sink;
  const Logger log(sink, "solve", Verbosity::kQuiet);
  RunOptions options;
  options.output = testing::temp_path(name + ".h5");
  options.progress = Progress::Style::kNone;
  run_scene(scene, options, make_provenance("solve-test", 0, nullptr, {}), log);
  redundant = 0;
  for (const auto& c : scene.model.constraints)
    for (char a : c.active) redundant += a ? 0 : 1;
  return options.output;
}

// Gruebler: crank, conrod, piston 18 coordinates; main bearing 5 + driver 1 + big end 5 leave the conrod's
// small end on a circle of the crank angle. Revolute small end (5) + prismatic guide (5) = 21 equations: 3
// redundant (the crank-axis translation and the two tilts out of the plane are held twice: by the bore and
// through the pin and conrod by the crank). Cylindrical small end (4) + in-line (2) + tilt stop (1) = 18:
// none redundant, every direction held once.
TEST(InLineJoint, PistonGuidanceHasNoRedundantEquations) {
  int redundant = -1;
  run(slider_crank(kPrismaticGuidance, "revolute"), "guidance_prismatic", redundant);
  EXPECT_EQ(redundant, 3);
  run(slider_crank(kInLineGuidance, "cylindrical"), "guidance_in_line", redundant);
  EXPECT_EQ(redundant, 0);
}

// The closed-form slider-crank at constant omega (e.g. Heywood, Internal Combustion Engine Fundamentals,
// 1988, eq. 2.5; Taylor vol. 2 ch. 8): the pin at y(theta) = r cos(theta) + s, s = sqrt(l^2 - r^2 sin^2),
// y'' = omega^2 (-r cos(theta) - r^2 cos(2 theta) / s - r^4 sin^2 cos^2 / s^3). With the conrod as its two
// point masses, the rod between them carries only its compression S along e = (r sin(theta), s) / l (crank
// pin -> piston pin), and on the piston with the small-end mass (M = m_p + m_c a / l):
//   along y:  M y'' = -F + S e_y
//   about the pin (z):  -F delta - h T = 0      (T: the tilt stop's force along x at height h)
//   along x:  0 = N + T + S e_x                 (N: the in-line guide's lateral force at the pin)
//   along z:  the guide's force 0 (nothing acts along the crank axis).
TEST(InLineJoint, SliderCrankKinematicsAndGuideReactionsAgainstTheClosedForm) {
  int redundant = -1;
  const auto out = run(slider_crank(kInLineGuidance, "cylindrical"), "guidance_reactions", redundant);
  const auto t = testing::signal(out, "time");
  const auto y = testing::signal(out, "bodies/piston/position", 1);
  const auto xp = testing::signal(out, "bodies/piston/position", 0);
  const Eigen::MatrixXd guide = testing::matrix(out, "joints/guide/reaction_force");
  const Eigen::MatrixXd stop = testing::matrix(out, "joints/tilt_stop/reaction_force");
  const double m = kPistonMass + kRodMass * kA / kL;
  const double t_scale = -kGas * kDelta / kH;  // T, constant
  double worst_x = 0, worst_y = 0, worst_n = 0, worst_t = 0, worst_z = 0, peak_n = 0;
  for (int k = 0; k < t.size(); ++k) {
    const double th = kOmega * t[k], sn = std::sin(th), cs = std::cos(th);
    const double s = std::sqrt(kL * kL - kR * kR * sn * sn);
    const double ydd =
        kOmega * kOmega *
        (-kR * cs - kR * kR * std::cos(2 * th) / s - std::pow(kR, 4) * sn * sn * cs * cs / std::pow(s, 3));
    const double ex = kR * sn / kL, ey = s / kL;
    const double compression = (m * ydd + kGas) / ey;
    const double n = -t_scale - compression * ex;
    worst_y = std::max(worst_y, std::abs(y[k] - (kR * cs + s)));
    worst_n = std::max(worst_n, std::abs(guide(k, 0) - n));
    worst_t = std::max(worst_t, std::abs(stop(k, 0) - t_scale));
    worst_z = std::max(
        {worst_z, std::abs(guide(k, 2)), std::abs(guide(k, 1)), std::abs(stop(k, 1)), std::abs(stop(k, 2))});
    worst_x = std::max(worst_x, std::abs(xp[k]));
    peak_n = std::max(peak_n, std::abs(n));
  }
  std::printf("worst: y %.3g m, N %.3g N, T %.3g N, z %.3g N, x %.3g m; peak N %.4g N\n", worst_y, worst_n,
              worst_t, worst_z, worst_x, peak_n);
  ASSERT_NEAR(t[t.size() - 1], 0.03, 1e-12);  // a whole revolution (30 ms at 2000 rpm)
  EXPECT_GT(peak_n, 1e3);                     // the side force is large (several kN): a real check
  EXPECT_LT(worst_y, 1e-9);                   // m, of 0.188 m
  EXPECT_LT(worst_n, 1e-6 * kGas);            // N: reactions to 1e-6 of the gas force
  EXPECT_LT(worst_t, 1e-6 * kGas);
  EXPECT_LT(worst_z, 1e-6 * kGas);  // no force along the bore axis or the crank axis
  EXPECT_LT(worst_x, 1e-9);         // m: the pin stays on the bore axis
}

TEST(InLineJoint, AnUnknownJointTypeListsInLine) {
  const std::string text = R"(
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "a"
[[body]]
name = "p"
type = "point-mass"
mass = 1.0
  [[body.marker]]
  name = "c"
[[joint]]
name = "guide"
i = "p.c"
j = "ground.a"
type = "inline"
)";
  EXPECT_NE(testing::scene_error(text).find("in-line"), std::string::npos) << testing::scene_error(text);
}

}  // namespace
}  // namespace nvh::solve
