// The energy balance every run writes (/energy, model.hpp) against closed forms, and the Maxwell element (a
// spring in series with a damper, solve/elements/maxwell.cpp) against its relaxation law.
#include <gtest/gtest.h>

#include <cmath>

#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::run_text;
using testing::signal;

// A mass m on a linear spring-damper (k, d) under gravity, released from the spring's free length: the energy
// kinetic + potential (gravity + spring) + dissipated stays equal to its initial value (the balance), and with
// d = 0 no energy is dissipated. Closed form of the check: E(t) = E(0) exactly; the tolerance 1e-7 of the
// energy scale m g x_static follows from the integrator tolerance (rtol 1e-10).
std::string oscillator(double damping) {
  return R"(
[scene]
gravity = [0, 0, -9.81]
[[body]]
name = "ground"
type = "ground"
[[body.marker]]
name = "top"
at = [0, 0, 0]
[[body]]
name = "mass"
type = "point-mass"
mass = 2.0
position = [0, 0, -0.1]
[[body.marker]]
name = "m"
[[force]]
name = "spring"
type = "spring-damper"
i = "mass.m"
j = "ground.top"
k = 2000.0
d = )" + std::to_string(damping) + R"(
free_length = 0.1
[clock]
end_time = 1.0
[integrator]
rtol = 1e-10
atol = 1e-12
[output]
sample_rate_hz = 2000
)";
}

TEST(EnergyBalance, UndampedOscillatorConservesItsEnergy) {
  const auto file = run_text(oscillator(0.0), "energy_undamped");
  const Eigen::VectorXd balance = signal(file, "energy/balance"), dissipated = signal(file, "energy/dissipated"),
                        kinetic = signal(file, "energy/kinetic"), potential = signal(file, "energy/potential");
  const double scale = 2.0 * 9.81 * (2.0 * 9.81 / 2000.0);  // m g x_static, J
  EXPECT_LT(balance.cwiseAbs().maxCoeff(), 1e-7 * scale);
  EXPECT_LT(dissipated.cwiseAbs().maxCoeff(), 1e-12);
  // the energy moves between kinetic and potential: the kinetic energy peaks at the static position,
  // 1/2 m v^2 = 1/2 k x_s^2 (released from rest at the free length: v_max = g / w)
  const double k = 2000.0, m = 2.0, xs = m * 9.81 / k;
  EXPECT_NEAR(kinetic.maxCoeff(), 0.5 * k * xs * xs, 1e-6 * scale);
  // potential -m g x + 1/2 k x^2 (x down from the free length) runs from 0 (x = 0, 2 x_s) to -1/2 m g x_s
  EXPECT_NEAR(potential.maxCoeff() - potential.minCoeff(), 0.5 * scale, 1e-6 * scale);
}

TEST(EnergyBalance, DampedOscillatorDissipatesWhatItLoses) {
  // d = 20 N s/m: the free response about the static deflection x_s = m g / k from rest at x = 0 is
  //   y = x - x_s = -x_s e^(-zeta w t) (cos w_d t + zeta w / w_d sin w_d t),  v = x_s w^2 / w_d e^(-zeta w t) sin w_d t,
  // and the mechanical energy 1/2 m v^2 - m g x + 1/2 k x^2 = 1/2 m v^2 + 1/2 k y^2 - 1/2 k x_s^2 has dropped from
  // 0 by the dissipated energy D(t) = 1/2 k x_s^2 - 1/2 m v^2 - 1/2 k y^2 (closed form).
  const auto file = run_text(oscillator(20.0), "energy_damped");
  const Eigen::VectorXd t = signal(file, "time"), balance = signal(file, "energy/balance"),
                        dissipated = signal(file, "energy/dissipated");
  const double k = 2000.0, m = 2.0, g = 9.81, d = 20.0, xs = m * g / k;
  const double w = std::sqrt(k / m), zeta = d / (2 * std::sqrt(k * m)), wd = w * std::sqrt(1 - zeta * zeta);
  const double scale = m * g * xs;
  double worst = 0;
  for (Eigen::Index n = 0; n < t.size(); ++n) {
    const double decay = std::exp(-zeta * w * t[n]);
    const double y = -xs * decay * (std::cos(wd * t[n]) + zeta * w / wd * std::sin(wd * t[n]));
    const double v = xs * w * w / wd * decay * std::sin(wd * t[n]);
    worst = std::max(worst, std::abs(dissipated[n] - (0.5 * k * xs * xs - 0.5 * m * v * v - 0.5 * k * y * y)));
  }
  std::printf("measured: damped oscillator, dissipated energy error %.3g J of %.3g J\n", worst, 0.5 * scale);
  EXPECT_LT(worst, 1e-7 * scale);
  EXPECT_LT(balance.cwiseAbs().maxCoeff(), 1e-7 * scale);
}

TEST(EnergyBalance, SpeedDriverInputEqualsTheWorkDone) {
  // A flywheel driven at constant speed against a linear damper (torsional, d): the driver's input work is the
  // damper's dissipation, d w^2 t (closed form), and the balance holds.
  const std::string text = R"(
[[body]]
name = "ground"
type = "ground"
[[body.marker]]
name = "o"
[[body]]
name = "wheel"
type = "rigid"
mass = 1.0
inertia = [0.01, 0.01, 0.02]
angular_velocity = [0, 0, 100.0]
[[body.marker]]
name = "hub"
[[joint]]
name = "bearing"
type = "revolute"
i = "wheel.hub"
j = "ground.o"
[[driver]]
name = "drive"
type = "speed"
i = "wheel.hub"
j = "ground.o"
rpm = 954.9296585513720
[[force]]
name = "damper"
type = "torsional-spring-damper"
i = "wheel.hub"
j = "ground.o"
k = 0.0
d = 0.5
[clock]
end_time = 0.5
[integrator]
rtol = 1e-9
atol = 1e-11
)";
  const auto file = run_text(text, "energy_driver");
  const Eigen::VectorXd t = signal(file, "time"), input = signal(file, "energy/input"),
                        dissipated = signal(file, "energy/dissipated"), balance = signal(file, "energy/balance");
  const double w = 100.0, d = 0.5;  // rad/s (954.93 rpm), N m s
  const double expected = d * w * w * t[t.size() - 1];
  EXPECT_NEAR(input[input.size() - 1], expected, 1e-6 * expected);
  EXPECT_NEAR(dissipated[dissipated.size() - 1], expected, 1e-6 * expected);
  EXPECT_LT(balance.cwiseAbs().maxCoeff(), 1e-6 * expected);
}

// Maxwell element, stress relaxation: marker i on a body moving away at a constant speed V (a 1e9 kg body: the
// element's ~1 N changes its speed by 1e-9 m/s^2), so x = V t and the force obeys c u' = f, f = k (V t - u):
// f(t) = c V (1 - exp(-k t / c)) (closed form), and the damper deflection u = V t - f / k.
TEST(MaxwellElement, RelaxationAgainstTheClosedForm) {
  const double k = 1.0e4, c = 100.0, v = 0.01;  // N/m, N s/m, m/s: tau = c / k = 0.01 s, c V = 1 N
  const std::string text = R"(
[[body]]
name = "ground"
type = "ground"
[[body.marker]]
name = "o"
[[body]]
name = "slider"
type = "point-mass"
mass = 1e9
position = [0.1, 0, 0]
velocity = [)" + std::to_string(v) + R"(, 0, 0]
[[body.marker]]
name = "m"
[[force]]
name = "mount"
type = "maxwell"
i = "slider.m"
j = "ground.o"
k = )" + std::to_string(k) + R"(
c = )" + std::to_string(c) + R"(
[clock]
end_time = 0.05
[integrator]
rtol = 1e-10
atol = 1e-12
[output]
sample_rate_hz = 10000
)";
  const auto file = run_text(text, "maxwell_relaxation");
  const Eigen::VectorXd t = signal(file, "time"), f = signal(file, "forces/mount/tension"),
                        u = signal(file, "forces/mount/states/damper_deflection"),
                        balance = signal(file, "energy/balance"), input = signal(file, "energy/input");
  double ef = 0, eu = 0;
  for (Eigen::Index n = 0; n < t.size(); ++n) {
    const double fe = c * v * (1 - std::exp(-k * t[n] / c));
    ef = std::max(ef, std::abs(f[n] - fe));
    eu = std::max(eu, std::abs(u[n] - (v * t[n] - fe / k)));
  }
  std::printf("measured: Maxwell relaxation, force error %.3g N (c V = %.3g N), damper deflection error %.3g m\n",
              ef, c * v, eu);
  EXPECT_LT(ef, 1e-6 * c * v);
  EXPECT_LT(eu, 1e-6 * c * v / k);
  // no source: the slider's kinetic energy pays for the spring's and the damper's (balance to 1e-6 of c V x)
  EXPECT_EQ(input.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LT(balance.cwiseAbs().maxCoeff(), 1e-6 * c * v * v * t[t.size() - 1]);
}

}  // namespace
}  // namespace nvh::solve
