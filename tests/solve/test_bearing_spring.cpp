// bearing-spring (solve/elements/bearing_spring.cpp): a rigid journal held in a ground bore by the element
// alone, against the closed forms of its three undamped oscillators, x = (v0 / w) sin(w t) (e.g. Inman,
// Engineering Vibration, section 1.1) with w = sqrt(k_r / m) radially, sqrt(k_a / m) axially and sqrt(k_t /
// I_x) in tilt (small angle); and spinning at 300 rad/s about the bore's axis for 95 turns, where it must
// neither push nor tilt (a bushing's rotation vector flips at half a turn) and the energy stays.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

constexpr double kMass = 2.0, kIx = 0.01, kKr = 2e6, kKa = 5e5, kKt = 400.0;

std::string journal(const std::string& motion, double end_time, const std::string& damping = "") {
  return R"([scene]
name = "journal-on-bearing-spring"
gravity = [0, 0, 0]

[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "bore"

[[body]]
name = "journal"
type = "rigid"
mass = 2.0
inertia = [0.01, 0.01, 0.004]
)" + motion +
         R"(
  [[body.marker]]
  name = "centre"

[[force]]
name = "bearing"
type = "bearing-spring"
i = "journal.centre"
j = "ground.bore"
radial_stiffness = 2e6
axial_stiffness = 5e5
tilt_stiffness = 400
)" + damping +
         R"(
[clock]
end_time = )" +
         std::to_string(end_time) +
         R"(

[integrator]
rtol = 1e-10
atol = 1e-13

[output]
sample_rate_hz = 5000
)";
}

TEST(BearingSpring, RadialAxialAndTiltFrequenciesAreTheClosedForms) {
  const double v0 = 1e-3, w0 = 1e-3;  // m/s along y and z, rad/s about x
  const auto file = testing::run_text(
      journal("velocity = [0, 1e-3, 1e-3]\nangular_velocity = [1e-3, 0, 0]", 0.05), "bearing_spring_modes");
  const Eigen::VectorXd t = testing::signal(file, "time");
  const Eigen::VectorXd y = testing::signal(file, "bodies/journal/position", 1),
                        z = testing::signal(file, "bodies/journal/position", 2),
                        tilt = testing::signal(file, "forces/bearing/misalignment");
  const double wr = std::sqrt(kKr / kMass), wa = std::sqrt(kKa / kMass), wt = std::sqrt(kKt / kIx);
  double err_r = 0, err_a = 0, err_t = 0;
  for (Eigen::Index k = 0; k < t.size(); ++k) {
    err_r = std::max(err_r, std::abs(y[k] - v0 / wr * std::sin(wr * t[k])));
    err_a = std::max(err_a, std::abs(z[k] - v0 / wa * std::sin(wa * t[k])));
    err_t = std::max(err_t, std::abs(tilt[k] - std::abs(w0 / wt * std::sin(wt * t[k]))));
  }
  std::printf("radial %.2e of %.2e m, axial %.2e of %.2e m, tilt %.2e of %.2e rad\n", err_r, v0 / wr, err_a,
              v0 / wa, err_t, w0 / wt);
  EXPECT_LT(err_r, 1e-6 * v0 / wr);
  EXPECT_LT(err_a, 1e-6 * v0 / wa);
  EXPECT_LT(err_t,
            1e-5 * w0 / wt);  // the tilt law is sin(alpha): the amplitude 5e-6 rad makes it linear to 1e-11
}

TEST(BearingSpring, SpinAboutTheAxisIsFree) {
  const auto file = testing::run_text(
      journal("angular_velocity = [0, 0, 300]", 2.0, "radial_damping = 50\ntilt_damping = 0.1\n"),
      "bearing_spring_spin");
  const Eigen::VectorXd radial = testing::signal(file, "forces/bearing/radial_displacement"),
                        tilt = testing::signal(file, "forces/bearing/misalignment"),
                        spin = testing::signal(file, "bodies/journal/angular_velocity", 2);
  std::printf("95 turns: radial displacement up to %.1e m, misalignment up to %.1e rad, spin %.12f rad/s\n",
              radial.cwiseAbs().maxCoeff(), tilt.cwiseAbs().maxCoeff(), spin[spin.size() - 1]);
  EXPECT_LT(radial.cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(tilt.cwiseAbs().maxCoeff(), 1e-12);
  // No damping torque about the axis: tilt_damping 0.1 N m s/rad on the spin would stop it within 0.2 s. What
  // is left is BDF's drift of a free rotor's kinetic energy at rtol 1e-10 (measured 4e-7 rad/s).
  EXPECT_NEAR(spin[spin.size() - 1], 300.0, 1e-5);
}

TEST(BearingSpring, MissingRadialStiffnessIsNamed) {
  std::string text = journal("", 0.01);
  text.replace(text.find("radial_stiffness = 2e6\n"), 23, "");
  const std::string e = testing::scene_error(text);
  EXPECT_NE(e.find("radial_stiffness"), std::string::npos) << e;
}

}  // namespace
}  // namespace nvh::solve
