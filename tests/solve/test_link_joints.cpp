// The one-equation joints of a kinematic chain against closed forms: the distance joint (a rigid link) as a
// large-amplitude pendulum, the in-plane joint (point on plane) as a block on a frictionless incline. Both
// integrators.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::num;
using testing::run_text;
using testing::signal;
constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.81;

const char* kIda = "[integrator]\nrtol = 1e-10\natol = 1e-12\nmax_step = 1e-3\n";
const char* kAlpha = "[integrator]\nmethod = \"generalized-alpha\"\nstep = 2e-5\nrho_inf = 0.8\n";

// ------------------------------------------------------------------ distance joint: a pendulum
// A 2 kg point mass on a massless link of L = 0.8 m to a ground point, released at rest at theta0 = 60 deg
// from the vertical. Exact period T = 4 sqrt(L/g) K(k), k = sin(theta0/2), K the complete elliptic integral
// of the first kind (e.g. Landau & Lifshitz, Mechanics, section 11, problem 1); the mass first passes the
// bottom at T/4, at speed sqrt(2 g L (1 - cos theta0)) with the link's tension m g (3 - 2 cos theta0).
TEST(DistanceJoint, PendulumQuarterPeriodSpeedAndTensionAtTheBottom) {
  const double m = 2.0, len = 0.8, th0 = kPi / 3;
  const double quarter = std::sqrt(len / kG) * std::comp_ellint_1(std::sin(th0 / 2));
  const double v_bottom = std::sqrt(2 * kG * len * (1 - std::cos(th0)));
  const double tension = m * kG * (3 - 2 * std::cos(th0));
  const std::string scene = R"(
[scene]
gravity = [0, -9.81, 0]
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "pin"
[[body]]
name = "bob"
type = "point-mass"
mass = 2.0
position = [)" + num(len * std::sin(th0)) + ", " + num(-len * std::cos(th0)) + R"(, 0]
  [[body.marker]]
  name = "c"
[[joint]]
name = "link"
type = "distance"
i = "bob.c"
j = "ground.pin"
[output]
sample_rate_hz = 20000
[clock]
end_time = )" + num(1.2 * quarter) + "\n";
  for (const char* integ : {kIda, kAlpha}) {
    SCOPED_TRACE(integ);
    const auto out = run_text(scene + integ, "distance_pendulum");
    const auto t = signal(out, "time"), x = signal(out, "bodies/bob/position", 0);
    const auto vx = signal(out, "bodies/bob/velocity", 0);
    const auto fy = signal(out, "joints/link/reaction_force", 1);
    int k = 1;
    while (k < x.size() && x[k] > 0) ++k;
    ASSERT_LT(k, x.size()) << "the bob never reached the bottom";
    const double s = x[k - 1] / (x[k - 1] - x[k]);  // linear interpolation of the crossing
    const double t_cross = t[k - 1] + s * (t[k] - t[k - 1]);
    EXPECT_NEAR(t_cross, quarter, 2e-6 * quarter);  // 0.4 ms of 0.33 s: dense output at 20 kHz, interpolated
    const double v = vx[k - 1] + s * (vx[k] - vx[k - 1]);
    EXPECT_NEAR(-v, v_bottom, 1e-5 * v_bottom);
    // The reaction on the bob at the bottom points up (towards the pin) and equals the tension.
    const double f = fy[k - 1] + s * (fy[k] - fy[k - 1]);
    EXPECT_NEAR(f, tension, 1e-4 * tension);
    // The link holds its length throughout.
    const auto y = signal(out, "bodies/bob/position", 1);
    for (int n = 0; n < x.size(); n += 50) EXPECT_NEAR(std::hypot(x[n], y[n]), len, 1e-8);
  }
}

// ------------------------------------------------------------------ in-plane joint: a block on an incline
// A 3 kg point mass held on a frictionless plane tilted by alpha = 25 deg about z (the plane's normal
// (-sin alpha, cos alpha, 0)), 2 mm above it (offset), released at rest: it slides down the slope with
// a = g sin(alpha), so s(t) = g sin(alpha) t^2 / 2 along the slope, and the plane pushes with m g cos(alpha)
// along its normal (any elementary mechanics text).
TEST(InPlaneJoint, BlockSlidesDownAFrictionlessIncline) {
  const double m = 3.0, alpha = 25 * kPi / 180, t_end = 0.3, offset = 0.002;
  const double nx = -std::sin(alpha), ny = std::cos(alpha);
  const std::string scene = R"(
[scene]
gravity = [0, -9.81, 0]
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "slope"
  z = [)" + num(nx) + ", " + num(ny) + R"(, 0]
[[body]]
name = "block"
type = "point-mass"
mass = 3.0
position = [)" + num(offset * nx) + ", " + num(offset * ny) + R"(, 0]
  [[body.marker]]
  name = "c"
[[joint]]
name = "on_slope"
type = "in-plane"
i = "block.c"
j = "ground.slope"
offset = 0.002
[output]
sample_rate_hz = 1000
[clock]
end_time = )" + num(t_end) + "\n";
  for (const char* integ : {kIda, kAlpha}) {
    SCOPED_TRACE(integ);
    const auto out = run_text(scene + integ, "in_plane_incline");
    const auto t = signal(out, "time");
    const auto x = signal(out, "bodies/block/position", 0), y = signal(out, "bodies/block/position", 1);
    const auto f = testing::matrix(out, "joints/on_slope/reaction_force");
    const int n = static_cast<int>(t.size()) - 1;
    ASSERT_NEAR(t[n], t_end, 1e-9);
    // Down the slope: direction (-cos alpha, -sin alpha) from the start point.
    const double s = -(x[n] - offset * nx) * std::cos(alpha) - (y[n] - offset * ny) * std::sin(alpha);
    const double s_exact = 0.5 * kG * std::sin(alpha) * t_end * t_end;
    EXPECT_NEAR(s, s_exact, 1e-7 * s_exact);
    EXPECT_NEAR(x[n] * nx + y[n] * ny, offset, 1e-10);  // still 2 mm above the plane
    EXPECT_NEAR(f(n, 0) * nx + f(n, 1) * ny, m * kG * std::cos(alpha), 1e-6 * m * kG);
    EXPECT_NEAR(f(n, 0) * std::cos(alpha) + f(n, 1) * std::sin(alpha), 0.0, 1e-6 * m * kG);  // no friction
  }
}

TEST(LinkJoints, BadInputNamesTheKey) {
  const std::string two_bodies = R"(
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
name = "link"
i = "p.c"
j = "ground.a"
)";
  // Both markers at the origin: no length to take from the drawing.
  EXPECT_NE(testing::scene_error(two_bodies + "type = \"distance\"\n").find("'length'"), std::string::npos);
  EXPECT_NE(testing::scene_error(two_bodies + "type = \"distance\"\nlength = -1\n").find("length"),
            std::string::npos);
  EXPECT_NE(testing::scene_error(two_bodies + "type = \"in-plane\"\noffset = inf\n").find("offset"),
            std::string::npos);
}

}  // namespace
}  // namespace nvh::solve
