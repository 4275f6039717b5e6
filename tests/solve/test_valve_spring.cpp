// The valve spring as a chain of masses (force types `valve-spring` and `mass-chain`, solve/elements/
// mass_chain.cpp; issue 13, item 2) against closed forms. Every test writes a scene, runs it through solve's
// library (run_text) and reads the results back. References, each evaluated here from the spring's data:
//   rate k = G d^4 / (8 D^3 n_a)                         (Shigley's Mechanical Engineering Design, 10th ed.,
//                                                         sec. 10-3; Wahl, Mechanical Springs, 1963)
//   active mass m_a = rho (pi d^2 / 4) (pi D n_a)
//   continuous spring, both ends fixed: f = (1/2) sqrt(k / m_a) = d / (2 pi n_a D^2) sqrt(G / (2 rho))
//                                                        (Shigley sec. 10-8, critical frequency; Wahl)
//   N equal masses m = m_a / (N+1), N+1 springs (N+1) k, both ends fixed (Lagrange's loaded string, e.g.
//   Rayleigh, The Theory of Sound, vol. 1, ch. VI): modes phi_k = sin(r k pi / (N+1)),
//   w_r = 2 sqrt((N+1) k / m) sin(r pi / (2 (N+1))), so f_1 = (1/pi) sqrt((N+1)^2 k / m_a) sin(pi / (2
//   (N+1))) coil clash below the solid length L_s = (n_a + 2 n_d) d: F = k (L_free - L) + c k (L_s - L), c =
//   100 (the documented penalty: each segment (N+1) k, its clash stiffness 100 (N+1) k).
// Tolerances at each assertion; measured errors printed ("measured: ...").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::num;
using testing::run_text;
using testing::signal;
constexpr double kPi = std::numbers::pi;

/// The frequency (Hz) of a signal x(t) from its rising zero crossings (linearly interpolated): the mean over
/// all the periods between the first and the last; 0 if there are fewer than `least` crossings (a test
/// failure).
double rising_crossing_hz(const Eigen::VectorXd& t, const Eigen::VectorXd& x, std::size_t least = 10) {
  std::vector<double> up;
  for (Eigen::Index j = 1; j < t.size(); ++j)
    if (x[j - 1] < 0 && x[j] >= 0) up.push_back(t[j - 1] - x[j - 1] / (x[j] - x[j - 1]) * (t[j] - t[j - 1]));
  EXPECT_GE(up.size(), least) << "too few periods";
  return up.size() < std::max<std::size_t>(least, 2) ? 0.0 : (up.size() - 1) / (up.back() - up.front());
}

// A valve spring of an automotive engine: 3.8 mm wire, 24 mm mean diameter, 5.5 active coils, one dead coil
// per end, free length 48 mm, installed at 38 mm; steel (G 79.3 GPa, rho 7850 kg/m^3, the element's
// defaults).
struct Spring {
  double d = 3.8e-3, dm = 24e-3, na = 5.5, nd = 1.0, free = 48e-3, installed = 38e-3;
  double g = 79.3e9, rho = 7850.0;
  double rate() const { return g * std::pow(d, 4) / (8 * std::pow(dm, 3) * na); }
  double active_mass() const { return rho * kPi * d * d / 4 * kPi * dm * na; }
  double solid() const { return (na + 2 * nd) * d; }
  double continuous_hz() const { return d / (2 * kPi * na * dm * dm) * std::sqrt(g / (2 * rho)); }
  double chain_hz(int n) const {
    return std::sqrt((n + 1.0) * (n + 1.0) * rate() / active_mass()) * std::sin(kPi / (2 * (n + 1.0))) / kPi;
  }
  std::string keys() const {
    return "wire_diameter = " + num(d) + "\nmean_diameter = " + num(dm) + "\nactive_coils = " + num(na) +
           "\nfree_length = " + num(free) + "\n";
  }
};

// The spring between the seat (ground, at the origin) and a retainer fixed to the ground at height `length`
// (a fixed joint): both ends fixed.
std::string fixed_scene(double length, const std::string& spring_keys, double end_time, double rate_hz) {
  return R"(
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "seat"
  [[body.marker]]
  name = "top"
  at = [0, 0, )" +
         num(length) + R"(]
[[body]]
name = "retainer"
type = "rigid"
mass = 0.01
inertia = [1e-6, 1e-6, 1e-6]
position = [0, 0, )" +
         num(length) + R"(]
  [[body.marker]]
  name = "r"
[[joint]]
name = "held"
type = "fixed"
i = "retainer.r"
j = "ground.top"
[[force]]
name = "spring"
type = "valve-spring"
i = "retainer.r"
j = "ground.seat"
)" + spring_keys +
         R"(
[clock]
end_time = )" +
         num(end_time) + R"(
[integrator]
rtol = 1e-11
atol = 1e-15
[output]
sample_rate_hz = )" +
         num(rate_hz) + "\n";
}

// Static rate and preload: at the installed length and at other fixed lengths (all above solid), the force on
// the retainer and on the seat is k (L_free - L) at the start and at the end of a short run (the chain starts
// at its static equilibrium and stays there). Tolerance 1e-9 of max(|k dx|, k x 1 mm).
TEST(ValveSpring, StaticRateAndPreload) {
  const Spring s;
  const double k = s.rate();
  double worst = 0;
  for (double length : {s.installed, 44e-3, 32e-3, s.free, 50e-3}) {
    const auto file = run_text(fixed_scene(length, s.keys(), 2e-3, 5000), "valve_spring_static");
    const double expected = k * (s.free - length), scale = std::max(std::abs(expected), k * 1e-3);
    for (const char* channel : {"force_i", "force_j"}) {
      const Eigen::VectorXd f = signal(file, std::string("forces/spring/") + channel);
      const double err = std::max(std::abs(f[0] - expected), std::abs(f[f.size() - 1] - expected)) / scale;
      worst = std::max(worst, err);
      EXPECT_LT(err, 1e-9) << channel << " at L = " << length;
    }
    const Eigen::VectorXd deflection = signal(file, "forces/spring/deflection");
    EXPECT_NEAR(deflection[0], s.free - length, 1e-15);
    if (length == s.installed)
      std::printf(
          "measured: valve spring k = G d^4/(8 D^3 n_a) = %.6g N/m, preload at %.1f mm %.6g N (channel %.12g "
          "N)\n",
          k, 1e3 * length, expected, signal(file, "forces/spring/force_i")[0]);
  }
  std::printf("measured: valve spring static force, worst relative error %.2e (tolerance 1e-9)\n", worst);
}

// Surge: both ends fixed at the installed length, no damping, the masses started in the first mode shape
// (initial_displacement = A sin(k pi / (N+1)), A = 10 um): x_1(t) = A sin(pi/(N+1)) cos(w_1 t) exactly, so
// the period from the upward zero crossings of the channel x_1 over about 20 periods is the first frequency.
// It is compared with the discrete chain's closed form (tolerance 1e-3; measured far below) and its error
// against the continuous spring's frequency reported for N = 1, 3, 5, 10, 20: e_N = (2 (N+1)/pi) sin(pi/(2
// (N+1))) - 1 ~ -pi^2 / (24 (N+1)^2): |e_N| falls at each step, e_N (N+1)^2 is within 5 % of -pi^2/24, and
// the slope of log |e| against log (N+1) from N = 10 to 20 is 2 +- 0.1. The energy balance stays at
// round-off.
TEST(ValveSpring, SurgeFrequencyConvergesToTheContinuousSpring) {
  const Spring s;
  const double fc = s.continuous_hz(), a = 1e-5;
  std::vector<double> errors;
  const std::vector<int> sizes = {1, 3, 5, 10, 20};
  for (int n : sizes) {
    std::string shape = "initial_displacement = [";
    for (int k = 1; k <= n; ++k) shape += (k > 1 ? ", " : "") + num(a * std::sin(k * kPi / (n + 1)));
    const double f_chain = s.chain_hz(n);
    const auto file =
        run_text(fixed_scene(s.installed, s.keys() + "masses = " + std::to_string(n) + "\n" + shape + "]\n",
                             20.0 / f_chain, 500 * f_chain),
                 "valve_spring_surge_" + std::to_string(n));
    const Eigen::VectorXd t = signal(file, "time"), x1 = signal(file, "forces/spring/x_1");
    const double f_measured = rising_crossing_hz(t, x1);
    ASSERT_GT(f_measured, 0.0);
    const double err_chain = f_measured / f_chain - 1, err_continuous = f_measured / fc - 1;
    errors.push_back(err_continuous);
    const Eigen::VectorXd balance = signal(file, "energy/balance"), stored = signal(file, "energy/potential");
    std::printf(
        "measured: surge N = %2d: %.6f Hz, chain closed form %.6f Hz (error %.2e, tolerance 1e-3); "
        "against the continuous spring %.6f Hz: %+.4f %% (x (N+1)^2: %.4f, -pi^2/24 = %.4f); "
        "|energy balance| %.1e J of %.3g J stored\n",
        n, f_measured, f_chain, err_chain, fc, 100 * err_continuous, err_continuous * (n + 1) * (n + 1),
        -kPi * kPi / 24, balance.cwiseAbs().maxCoeff(), stored[0]);
    EXPECT_LT(std::abs(err_chain), 1e-3) << "N = " << n;
    EXPECT_LT(balance.cwiseAbs().maxCoeff(), 1e-9 * stored[0]) << "N = " << n;
    EXPECT_NEAR(err_continuous * (n + 1) * (n + 1), -kPi * kPi / 24, 0.05 * kPi * kPi / 24) << "N = " << n;
  }
  for (std::size_t k = 1; k < errors.size(); ++k) EXPECT_LT(std::abs(errors[k]), std::abs(errors[k - 1]));
  const double slope = std::log(errors[3] / errors[4]) / std::log(21.0 / 11.0);
  std::printf(
      "measured: surge error N = 5 against the continuous spring %+.3f %%; convergence order (N = 10 -> 20) "
      "%.3f\n",
      100 * errors[2], slope);
  EXPECT_NEAR(slope, 2.0, 0.1);
}

// damping_ratio zeta: c_s = 2 zeta k_s / w_1 is stiffness-proportional, so the modes stay uncoupled and the
// first mode started alone decays as x_1 ~ exp(-zeta w_1 t) cos(w_d t), w_d = w_1 sqrt(1 - zeta^2) (Thomson &
// Dahleh, ch. 2): the logarithmic decrement between maxima m periods apart, ln(x_k / x_{k+m}) / m = 2 pi zeta
// / sqrt(1 - zeta^2), gives zeta back (tolerance 1e-3 relative), the period w_d (1e-3).
TEST(ValveSpring, DampingRatioOfTheFirstSurgeMode) {
  const Spring s;
  const int n = 5;
  const double zeta = 0.02, f1 = s.chain_hz(n);
  std::string shape = "initial_displacement = [";
  for (int k = 1; k <= n; ++k) shape += (k > 1 ? ", " : "") + num(1e-5 * std::sin(k * kPi / (n + 1)));
  const auto file = run_text(
      fixed_scene(s.installed, s.keys() + "masses = 5\ndamping_ratio = " + num(zeta) + "\n" + shape + "]\n",
                  15.0 / f1, 2000 * f1),
      "valve_spring_damping");
  const Eigen::VectorXd t = signal(file, "time"), x1 = signal(file, "forces/spring/x_1");
  std::vector<double> tp, xp;  // maxima, refined by a parabola through three samples
  for (Eigen::Index k = 1; k + 1 < t.size(); ++k)
    if (x1[k] > x1[k - 1] && x1[k] >= x1[k + 1] && x1[k] > 0) {
      const double a = x1[k - 1], b = x1[k], c = x1[k + 1], den = a - 2 * b + c, o = 0.5 * (a - c) / den;
      tp.push_back(t[k] + o * (t[k + 1] - t[k]));
      xp.push_back(b - 0.25 * (a - c) * o);
    }
  ASSERT_GE(tp.size(), 10u);
  const double m = static_cast<double>(tp.size() - 1), delta = std::log(xp.front() / xp.back()) / m;
  const double zeta_measured = delta / std::sqrt(4 * kPi * kPi + delta * delta);
  const double fd = m / (tp.back() - tp.front()), fd_expected = f1 * std::sqrt(1 - zeta * zeta);
  std::printf(
      "measured: surge damping ratio %.6f (given %.6f, error %.2e, tolerance 1e-3); damped frequency %.6f Hz "
      "(closed form %.6f Hz, error %.2e, tolerance 1e-3)\n",
      zeta_measured, zeta, zeta_measured / zeta - 1, fd, fd_expected, fd / fd_expected - 1);
  EXPECT_NEAR(zeta_measured / zeta, 1.0, 1e-3);
  EXPECT_NEAR(fd / fd_expected, 1.0, 1e-3);
}

// Coil clash: held below the solid length L_s = (n_a + 2 n_d) d the force is k (L_free - L) + 100 k (L_s - L)
// (every segment in clash by the same amount), above it k (L_free - L); the channel `clash` counts the
// segments in clash. Tolerance 1e-9 of the force. The stiffening: the slope below L_s is 101 k.
TEST(ValveSpring, CoilClashStiffensBelowTheSolidLength) {
  const Spring s;
  const double k = s.rate(), ls = s.solid();
  std::vector<double> lengths = {ls + 0.5e-3, ls - 0.2e-3, ls - 0.5e-3}, forces;
  double worst = 0;
  for (double length : lengths) {
    const auto file = run_text(fixed_scene(length, s.keys(), 1e-3, 5000), "valve_spring_clash");
    const double expected = k * (s.free - length) + (length < ls ? 100 * k * (ls - length) : 0.0);
    const double f = signal(file, "forces/spring/force_i")[0],
                 f_end = signal(file, "forces/spring/force_i")(Eigen::last);
    const double err = std::max(std::abs(f - expected), std::abs(f_end - expected)) / expected;
    worst = std::max(worst, err);
    EXPECT_LT(err, 1e-9) << "L = " << length;
    EXPECT_EQ(signal(file, "forces/spring/clash")[0], length < ls ? 6.0 : 0.0) << "L = " << length;
    forces.push_back(f);
  }
  const double slope = (forces[2] - forces[1]) / (lengths[1] - lengths[2]);
  std::printf(
      "measured: coil clash, worst relative error %.2e (tolerance 1e-9); slope below solid %.6g N/m = %.6f "
      "k\n",
      worst, slope, slope / k);
  EXPECT_NEAR(slope / k, 101.0, 1e-6);
}

// A valve (point mass m = 50 g) on the spring under gravity and a constant 300 N load pressing it down,
// started at the installed length at rest, the surge damped (damping_ratio 0.3): it settles at the static
// equilibrium k (L_free - L) = m g + F, L = L_free - (m g + F) / k (the chain's own weight is not modelled).
// Tolerances: the final height 1e-9 m, the final force 1e-7 relative; the energy balance 1e-7 of the energy
// dissipated.
TEST(ValveSpring, ValveSettlesAtTheStaticEquilibrium) {
  const Spring s;
  const double m = 0.05, g = 9.81, load = 300.0, k = s.rate();
  const double l_eq = s.free - (m * g + load) / k;
  const std::string text = R"(
[scene]
gravity = [0, 0, -9.81]
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "seat"
[[body]]
name = "valve"
type = "point-mass"
mass = )" + num(m) + R"(
position = [0, 0, )" + num(s.installed) +
                           R"(]
  [[body.marker]]
  name = "c"
[[force]]
name = "spring"
type = "valve-spring"
i = "valve.c"
j = "ground.seat"
damping_ratio = 0.3
)" + s.keys() + R"(
[[load]]
name = "press"
type = "force"
at = "valve.c"
direction = [0, 0, -1]
table = [[0, )" + num(load) +
                           "], [10, " + num(load) + R"(]]
[clock]
end_time = 0.6
[integrator]
rtol = 1e-10
atol = 1e-14
[output]
sample_rate_hz = 5000
)";
  const auto file = run_text(text, "valve_spring_valve");
  const Eigen::VectorXd z = signal(file, "bodies/valve/position", 2),
                        f = signal(file, "forces/spring/force_i");
  const Eigen::VectorXd balance = signal(file, "energy/balance"),
                        dissipated = signal(file, "energy/dissipated");
  const double ez = std::abs(z(Eigen::last) - l_eq), ef = std::abs(f(Eigen::last) / (m * g + load) - 1);
  std::printf(
      "measured: valve on the spring settles at %.9f mm (closed form %.9f mm, error %.2e m, tolerance 1e-9); "
      "force error %.2e (tolerance 1e-7); lowest %.4f mm (solid %.4f mm); |balance| %.2e J of %.3g J "
      "dissipated\n",
      1e3 * z(Eigen::last), 1e3 * l_eq, ez, ef, 1e3 * z.minCoeff(), 1e3 * s.solid(),
      balance.cwiseAbs().maxCoeff(), dissipated(Eigen::last));
  EXPECT_LT(ez, 1e-9);
  EXPECT_LT(ef, 1e-7);
  EXPECT_GT(z.minCoeff(), s.solid());  // no clash on the way
  EXPECT_LT(balance.cwiseAbs().maxCoeff(), 1e-7 * dissipated(Eigen::last));
}

// mass-chain with the keys of the valve spring's generated chain (masses, total mass, overall rate, free and
// solid length) gives the same forces and surge as valve-spring when the dead coils are absent: checked on
// the static preload (1e-9) and the first frequency from the mode-shape start (1e-3).
TEST(MassChain, EqualsTheValveSpringWithoutDeadCoils) {
  Spring s;
  s.nd = 0.0;
  const int n = 5;
  const double k = s.rate();
  std::string shape = "initial_displacement = [";
  for (int j = 1; j <= n; ++j) shape += (j > 1 ? ", " : "") + num(1e-5 * std::sin(j * kPi / (n + 1)));
  shape += "]\n";
  const std::string keys = "masses = 5\nmass = " + num(s.active_mass() * n / (n + 1)) +
                           "\nstiffness = " + num(k) + "\nfree_length = " + num(s.free) +
                           "\nsolid_length = " + num(s.na * s.d) + "\n" + shape;
  std::string text = fixed_scene(s.installed, keys, 20 / s.chain_hz(n), 500 * s.chain_hz(n));
  text.replace(text.find("valve-spring"), 12, "mass-chain");
  const auto file = run_text(text, "mass_chain_surge");
  const Eigen::VectorXd t = signal(file, "time"), x1 = signal(file, "forces/spring/x_1");
  const double f_measured = rising_crossing_hz(t, x1);
  ASSERT_GT(f_measured, 0.0);
  const double f_i = signal(file, "forces/spring/force_i")[0],
               expected = k * (s.free - s.installed) + (n + 1) * k * 1e-5 * std::sin(n * kPi / (n + 1));
  std::printf(
      "measured: mass-chain surge %.6f Hz (closed form %.6f Hz, error %.2e, tolerance 1e-3); "
      "initial force error %.2e (tolerance 1e-9)\n",
      f_measured, s.chain_hz(n), f_measured / s.chain_hz(n) - 1, f_i / expected - 1);
  EXPECT_LT(std::abs(f_measured / s.chain_hz(n) - 1), 1e-3);
  EXPECT_LT(std::abs(f_i / expected - 1), 1e-9);
}

// `velocity_atol` governs the chain's masses' velocities as it does the bodies' (solve/model.cpp,
// velocity_tolerance_mask): the free surge of the fixed-fixed chain (mode-shape start, 10 um, about 0.04 m/s)
// with the positions held to atol = 1e-13 m and the velocities to velocity_atol = 1e-13 or 1e-5 m/s. The
// loose velocities must cost fewer steps (before, the key reached no chain state: the step counts were
// equal), and both runs keep the loaded string's frequency (closed form above) within 1e-3.
TEST(MassChain, VelocityToleranceReachesTheMassesVelocities) {
  Spring s;
  const int n = 5;
  std::string shape = "initial_displacement = [";
  for (int j = 1; j <= n; ++j) shape += (j > 1 ? ", " : "") + num(1e-5 * std::sin(j * kPi / (n + 1)));
  shape += "]\n";
  auto run = [&](const std::string& velocity_atol, RunSummary& summary) {
    std::string text =
        fixed_scene(s.installed, s.keys() + "masses = 5\n" + shape, 20 / s.chain_hz(n), 200 * s.chain_hz(n));
    text.replace(text.find("rtol = 1e-11\natol = 1e-15"), 25,
                 "rtol = 1e-8\natol = 1e-13\nvelocity_atol = " + velocity_atol);
    const auto file = run_text(text, "chain_velocity_atol_" + velocity_atol, &summary);
    return rising_crossing_hz(signal(file, "time"), signal(file, "forces/spring/x_1"));
  };
  RunSummary tight, loose;
  const double f_tight = run("1e-13", tight), f_loose = run("1e-5", loose);
  std::printf(
      "measured: %ld steps at velocity_atol 1e-13 m/s (surge error %.2e), %ld at 1e-5 (error %.2e); "
      "tolerance 1e-3, loose < 0.8 x tight steps\n",
      tight.statistics.steps, f_tight / s.chain_hz(n) - 1, loose.statistics.steps,
      f_loose / s.chain_hz(n) - 1);
  EXPECT_LT(loose.statistics.steps, 0.8 * tight.statistics.steps);
  EXPECT_LT(std::abs(f_tight / s.chain_hz(n) - 1), 1e-3);
  EXPECT_LT(std::abs(f_loose / s.chain_hz(n) - 1), 1e-3);
}

// A chain between two free point masses (a pushrod between two moving bodies), no external force: the total
// momentum m_a v_a + m_b v_b + sum m_k v_k (the states are the masses' absolute velocities along the line)
// stays at its initial value - Newton's third law, exact for a chain along a fixed line; a chain integrated
// in the frame of a moving end would lose it at the rate (sum m_k) a_j.
TEST(MassChain, CarriesItsOwnInertiaBetweenTwoMovingBodies) {
  const double ma = 0.4, mb = 0.6, mc = 0.3, va = 2.0;
  const std::string text = R"(
[scene]
name = "free-chain"
gravity = [0, 0, 0]
[[body]]
name = "a"
type = "point-mass"
mass = )" + num(ma) + R"(
position = [0.3, 0, 0]
velocity = [)" + num(va) + R"(, 0, 0]
  [[body.marker]]
  name = "c"
[[body]]
name = "b"
type = "point-mass"
mass = )" + num(mb) + R"(
position = [0, 0, 0]
  [[body.marker]]
  name = "c"
[[force]]
name = "rod"
type = "mass-chain"
i = "a.c"
j = "b.c"
masses = 3
mass = )" + num(mc) + R"(
stiffness = 1e5
[clock]
end_time = 0.05
[integrator]
rtol = 1e-9
atol = 1e-12
[output]
sample_rate_hz = 20000
)";
  const auto file = run_text(text, "mass_chain_free");
  const Eigen::VectorXd vxa = signal(file, "bodies/a/velocity", 0),
                        vxb = signal(file, "bodies/b/velocity", 0);
  Eigen::VectorXd p = ma * vxa + mb * vxb;
  for (int k = 1; k <= 3; ++k) p += mc / 3 * signal(file, "forces/rod/states/velocity_" + std::to_string(k));
  const double p0 = ma * va + mc / 3 * va * (1.0 + 2.0 + 3.0) / 4.0;  // the chain starts interpolated
  const double err = (p.array() - p0).abs().maxCoeff() / p0;
  const double swing = (vxb.maxCoeff() - vxb.minCoeff()) / va;
  std::printf("measured: total momentum drift %.3g relative (b's velocity swings over %.2f of a's)\n", err,
              swing);
  EXPECT_LT(err, 1e-6);
  EXPECT_GT(swing, 0.5);  // the chain does vibrate: the test exercises its inertia
}

}  // namespace
}  // namespace nvh::solve
