// The displacement driver (docs/scene-format.md section 3; constraint.hpp (D1)) against a closed form: a bar
// on a revolute joint whose tip is driven harmonically along global y, started at t0 != 0.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::num;
using testing::run_text;
using testing::scene_error;
using testing::signal;
constexpr double kPi = std::numbers::pi;

// A bar of length L = 0.3 m turning about z at the origin (centre of mass there, Izz = J), its tip starting
// on the x axis at t0 = 0.1 s and driven so that z_j . (p_tip - p_j) = offset + s(t), z_j = global y,
// s(t) = A sin(2 pi f t + phase): the tip's height is u(t) = s(t) - s(t0) and the bar's angle
//   theta = asin(u / L),  theta' = u' / sqrt(L^2 - u^2),  theta'' = u'' / c + u u'^2 / c^3,  c = sqrt(L^2 -
//   u^2).
// No gravity: the only torque about the pivot is the driver's force F_y at the tip's arm L cos(theta), so
// F_y = J theta'' / (L cos(theta)) (the reaction written for the driver is the force on the tip).
TEST(DisplacementDriver, DrivenBarFollowsTheClosedForm) {
  const double len = 0.3, amp = 0.05, hz = 2.0, phase = kPi / 6, t0 = 0.1, inertia = 0.02;
  const double w = 2 * kPi * hz;
  auto s = [&](double t) { return amp * std::sin(w * t + phase); };
  const std::string scene = R"(
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "o"
  [[body.marker]]
  name = "y"
  z = [0, 1, 0]
  x = [1, 0, 0]
[[body]]
name = "bar"
type = "rigid"
mass = 2.0
inertia = [0.001, )" + num(inertia) +
                            ", " + num(inertia) + R"(]
  [[body.marker]]
  name = "pivot"
  [[body.marker]]
  name = "tip"
  at = [)" + num(len) + R"(, 0, 0]
[[joint]]
name = "pivot"
type = "revolute"
i = "bar.pivot"
j = "ground.o"
[[driver]]
name = "shaker"
type = "displacement"
i = "bar.tip"
j = "ground.y"
amplitude = )" + num(amp) + R"(
frequency_hz = )" + num(hz) +
                            R"(
phase_deg = 30
[clock]
start_time = 0.1
end_time = 0.6
[integrator]
rtol = 1e-10
atol = 1e-12
[output]
sample_rate_hz = 200
)";
  const auto out = run_text(scene, "displacement_driver");
  const auto t = signal(out, "time");
  const auto y_tip = signal(out, "markers/bar.tip/position", 1);
  const auto wz = signal(out, "bodies/bar/angular_velocity", 2);
  const auto fy = signal(out, "joints/shaker/reaction_force", 1);
  ASSERT_GT(t.size(), 90);
  EXPECT_EQ(t[0], t0);
  for (Eigen::Index k = 0; k < t.size(); ++k) {
    const double u = s(t[k]) - s(t0), du = amp * w * std::cos(w * t[k] + phase), ddu = -w * w * (s(t[k]));
    const double c = std::sqrt(len * len - u * u);
    const double dth = du / c, ddth = ddu / c + u * du * du / (c * c * c);
    EXPECT_NEAR(y_tip[k], u, 1e-10) << "t = " << t[k];  // dense output between steps
    EXPECT_NEAR(wz[k], dth, 1e-9 * std::abs(amp * w / len)) << "t = " << t[k];
    const double f = inertia * ddth / c;  // L cos(theta) = c; a multiplier: known less well (measured 2.5e-6)
    EXPECT_NEAR(fy[k], f, 1e-5 * inertia * amp * w * w / (len * len)) << "t = " << t[k];
  }
}

TEST(DisplacementDriver, ErrorsNameTheKey) {
  const std::string bodies = R"(
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "o"
[[body]]
name = "m"
type = "point-mass"
mass = 1
  [[body.marker]]
  name = "c"
[[driver]]
name = "shaker"
type = "displacement"
i = "m.c"
j = "ground.o"
)";
  const std::string missing = scene_error(bodies + "frequency_hz = 10\n");
  EXPECT_NE(missing.find("bad.toml:"), std::string::npos) << missing;
  EXPECT_NE(missing.find("amplitude"), std::string::npos) << missing;
  const std::string unknown = scene_error(bodies + "amplitude = 0.1\nfrequency_hz = 10\nrpm = 3\n");
  EXPECT_NE(unknown.find("rpm"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("bad.toml:"), std::string::npos) << unknown;
  const std::string negative = scene_error(bodies + "amplitude = 0.1\nfrequency_hz = -1\n");
  EXPECT_NE(negative.find("frequency_hz"), std::string::npos) << negative;
}

}  // namespace
}  // namespace nvh::solve
