// The integrators' amplification per step against the closed forms of their schemes (issue 16, the stability
// map: bench/stability_map.py, docs/verification.md "Stability map"). An undamped oscillator - 1 kg on a
// bushing, k = w^2 along x - whose modal amplitude hypot(x, v / w) a linear method multiplies by |xi| per
// step, xi the dominant root of the scheme's characteristic polynomial at z = i w h, once the start-up's
// other roots have died away. A bushing and not a spring: its force is -k x from the displacement itself, so
// the motion keeps its relative precision over a decay of many decades.
// IDA runs at a forced step: max_step = initial_step = h with tolerances so loose (rtol 0.5, atol 1 against
// motions of 1e-5 m) that the error test never shortens it. IDA still picks the order itself (up to
// max_order): the tests check from /solver/statistics steps_at_order_k that it used the order under test.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::num;
using testing::run_text;
using testing::signal;
using cd = std::complex<double>;

constexpr double kW = 10.0;   // rad/s
constexpr double kX0 = 1e-5;  // m

/// The largest |root| of the polynomial sum_k c[k] xi^k (c[n] != 0): eigenvalues of its companion matrix.
double largest_root(const std::vector<cd>& c) {
  const int n = static_cast<int>(c.size()) - 1;
  Eigen::MatrixXcd m = Eigen::MatrixXcd::Zero(n, n);
  for (int k = 0; k < n; ++k) m(0, k) = -c[n - 1 - k] / c[n];
  for (int k = 1; k < n; ++k) m(k, k - 1) = 1.0;
  return Eigen::ComplexEigenSolver<Eigen::MatrixXcd>(m).eigenvalues().cwiseAbs().maxCoeff();
}

/// BDF-k on y' = lambda y, z = lambda h: sum_{j=1..k} (1/j) (1 - 1/xi)^j = z, times xi^k:
///   k = 1: (1 - z) xi - 1 = 0
///   k = 2: (3/2 - z) xi^2 - 2 xi + 1/2 = 0
///   k = 3: (11/6 - z) xi^3 - 3 xi^2 + 3/2 xi - 1/3 = 0
double bdf_radius(int k, cd z) {
  if (k == 1) return largest_root({-1.0, 1.0 - z});
  if (k == 2) return largest_root({0.5, -2.0, 1.5 - z});
  return largest_root({-1.0 / 3.0, 1.5, -3.0, 11.0 / 6.0 - z});
}

/// Generalized-alpha of Jansen, Whiting & Hulbert (2000), the scheme solve implements, on y' = lambda y:
/// y1 = y0 + h v0 + h gamma (v1 - v0), v0 + am (v1 - v0) = lambda (y0 + af (y1 - y0)); its roots solve
/// det(B - xi A) = 0, A = [[1, -gamma], [-af z, am]], B = [[1, 1 - gamma], [(1 - af) z, -(1 - am)]]:
///   (am - gamma af z) xi^2 + (1 - 2 am - z ((1 - gamma) af + gamma (1 - af))) xi
///     - (1 - am) - z (1 - gamma)(1 - af) = 0.
double jwh_radius(cd z, double rho) {
  const double am = (3 - rho) / (2 * (1 + rho)), af = 1 / (1 + rho), g = 0.5 + am - af;
  const cd c2 = am - g * af * z;
  const cd c1 = 1 - 2 * am - z * ((1 - g) * af + g * (1 - af));
  const cd c0 = -(1 - am) - z * (1 - g) * (1 - af);
  return largest_root({c0, c1, c2});
}

/// Chung & Hulbert's (1993) second-order generalized-alpha on x'' + w^2 x = 0 at the same rho_inf: the
/// spectral radius of its 3 x 3 amplification matrix (for comparison only).
double chung_hulbert_radius(double wh, double rho) {
  const double am = (2 * rho - 1) / (rho + 1), af = rho / (rho + 1), g = 0.5 - am + af;
  const double b = 0.25 * (1 - am + af) * (1 - am + af), w2 = wh * wh;
  Eigen::Matrix3d lhs, rhs;
  lhs << w2 * (1 - af), 0, 1 - am, 1, 0, -b, 0, 1, -g;
  rhs << -w2 * af, 0, -am, 1, 1, 0.5 - b, 0, 1, 1 - g;
  return Eigen::EigenSolver<Eigen::Matrix3d>(lhs.inverse() * rhs).eigenvalues().cwiseAbs().maxCoeff();
}

struct Decay {
  std::vector<double> amplitude;  // hypot(x, v / w) at every step (one sample per step)
  RunSummary summary;
  std::filesystem::path file;
};

Decay oscillator(int steps, double h, const std::string& integrator, const std::string& name) {
  std::ostringstream s;
  s << "[[body]]\nname = \"ground\"\ntype = \"ground\"\n  [[body.marker]]\n  name = \"a\"\n"
       "[[body]]\nname = \"m\"\ntype = \"point-mass\"\nmass = 1.0\nposition = ["
    << num(kX0) << ", 0, 0]\n  [[body.marker]]\n  name = \"c\"\n"
    << "[[force]]\nname = \"k\"\ntype = \"bushing\"\ni = \"m.c\"\nj = \"ground.a\"\nstiffness = ["
    << num(kW * kW) << ", 0, 0, 0, 0, 0]\ndamping = [0, 0, 0, 0, 0, 0]\n"
    << "[clock]\nend_time = " << num(steps * h) << "\n"
    << integrator << "[output]\nsample_rate_hz = " << num(1 / h)
    << "\nmarkers = [\"m.c\"]\nbodies = false\nforces = false\n";
  Decay d;
  d.file = run_text(s.str(), name, &d.summary);
  const auto& file = d.file;
  const Eigen::VectorXd x = signal(file, "markers/m.c/position", 0),
                        v = signal(file, "markers/m.c/velocity", 0);
  for (Eigen::Index i = 0; i < x.size(); ++i) d.amplitude.push_back(std::hypot(x[i], v[i] / kW));
  return d;
}

std::string ida_forced(int max_order, double h) {
  return "[integrator]\nmethod = \"ida\"\nmax_order = " + std::to_string(max_order) +
         "\nmax_step = " + num(h) + "\ninitial_step = " + num(h) +
         "\nrtol = 0.5\natol = 1.0\njacobian_cj_change = 1e-6\n";
}

/// The measured growth per step between steps a and b.
double per_step(const Decay& d, int a, int b) {
  return std::pow(d.amplitude.at(b) / d.amplitude.at(a), 1.0 / (b - a));
}

TEST(SolveIntegratorStability, IdaForcedStepBackwardEulerDecaysByItsClosedForm) {
  // max_order = 1 at w h = 0.5: |1 / (1 - i w h)| = 1 / sqrt(1.25) per step, from the first step on.
  const double wh = 0.5, h = wh / kW;
  const int n = 40;
  const Decay d = oscillator(n, h, ida_forced(1, h), "stab_bdf1");
  ASSERT_EQ(d.amplitude.size(), static_cast<std::size_t>(n + 1));
  EXPECT_EQ(d.summary.statistics.steps, n) << "the step was not held at h";
  EXPECT_EQ(d.summary.statistics.rejected_steps, 0);
  EXPECT_EQ(d.summary.statistics.steps_at_order[0], n);
  const double expected = std::pow(1.0 + wh * wh, -0.5 * n);  // 0.0115
  const double ratio = d.amplitude[n] / d.amplitude[0];
  std::printf("measured: IDA order 1, w h = 0.5, 40 steps: amplitude ratio %.15g, closed form %.15g\n", ratio,
              expected);
  EXPECT_NEAR(ratio / expected, 1.0, 1e-9);
}

TEST(SolveIntegratorStability, IdaForcedStepBdf2DampsByItsRootMagnitude) {
  // max_order = 2 at w h = 0.1: IDA runs order 2 after its first two steps; per step the amplitude falls by
  // the largest |root| of (3/2 - z) xi^2 - 2 xi + 1/2 at z = 0.1 i, 0.999975609 (the other root, 0.33, has
  // died away by step 100: 0.33^100).
  const double wh = 0.1, h = wh / kW;
  const Decay d = oscillator(200, h, ida_forced(2, h), "stab_bdf2");
  ASSERT_EQ(d.amplitude.size(), 201u);
  EXPECT_GE(d.summary.statistics.steps_at_order[1], 195) << "IDA left order 2";
  const double measured = per_step(d, 100, 200), expected = bdf_radius(2, {0, wh});
  std::printf("measured: IDA order 2, w h = 0.1: %.15f per step, BDF2 root %.15f (%.1e)\n", measured,
              expected, measured - expected);
  EXPECT_NEAR(measured, expected, 1e-10);
  EXPECT_LT(measured, 1.0);  // A-stable: damps
}

TEST(SolveIntegratorStability, IdaForcedStepBdf3GrowsOnAnUndampedMode) {
  // BDF3 is not A-stable (A(86.03 deg)): on the imaginary axis its largest root exceeds 1 for 0 < w h < 1.94.
  // At w h = 0.5: 1.01097 per step - the undamped oscillator grows 1.1 % per step, 15 % per period.
  const double wh = 0.5, h = wh / kW;
  const Decay d = oscillator(200, h, ida_forced(3, h), "stab_bdf3");
  ASSERT_EQ(d.amplitude.size(), 201u);
  EXPECT_EQ(d.summary.statistics.rejected_steps, 0);
  EXPECT_GE(d.summary.statistics.steps_at_order[2], 195) << "IDA left order 3";
  // The results file's count per order (docs/results-format.md): they add up to the steps.
  const h5::File f = h5::File::open_read(d.file);
  std::int64_t counted = 0;
  for (int k = 1; k <= 5; ++k)
    counted += f.root().int_attribute("steps_at_order_" + std::to_string(k), "solver/statistics");
  EXPECT_EQ(counted, d.summary.statistics.steps);
  EXPECT_EQ(f.root().int_attribute("steps_at_order_3", "solver/statistics"),
            d.summary.statistics.steps_at_order[2]);
  const double measured = per_step(d, 100, 200), expected = bdf_radius(3, {0, wh});
  std::printf("measured: IDA order 3, w h = 0.5: %.15f per step, BDF3 root %.15f (%.1e)\n", measured,
              expected, measured - expected);
  EXPECT_NEAR(measured, expected, 1e-9);
  EXPECT_GT(measured, 1.01);
}

TEST(SolveNumericalDamping, GeneralizedAlphaAtLargeStepsFollowsJansenWhitingHulbert) {
  // Beyond the small steps of GeneralizedAlphaDecayMatchesItsSpectralRadius (w h 0.16, 0.31): at w h = 3 and
  // 10, the measured radius per step against the closed form of the first-order scheme (JWH 2000). Chung and
  // Hulbert's second-order algorithm at the same rho_inf damps more (0.54 against 0.61 at rho_inf 0, w h 3):
  // solve's scheme is the first-order one, which the test tells apart.
  for (const double rho : {0.0, 0.5}) {
    for (const double wh : {3.0, 10.0}) {
      const double h = wh / kW;
      const std::string settings = "[integrator]\nmethod = \"generalized-alpha\"\nstep = " + num(h) +
                                   "\nadaptive = false\nrho_inf = " + num(rho) +
                                   "\nrtol = 1e-9\natol = 1e-10\n";
      const Decay d = oscillator(200, h, settings, "stab_ga");
      ASSERT_EQ(d.amplitude.size(), 201u);
      const double measured = per_step(d, 100, 200), jwh = jwh_radius({0, wh}, rho);
      const double ch = chung_hulbert_radius(wh, rho);
      std::printf(
          "measured: generalized-alpha rho_inf %.1f, w h %.0f: %.12f per step; JWH %.12f (%.1e), "
          "Chung-Hulbert %.12f\n",
          rho, wh, measured, jwh, measured - jwh, ch);
      EXPECT_NEAR(measured, jwh, 1e-9) << "rho_inf " << rho << " w h " << wh;
      EXPECT_GT(std::abs(measured - ch), 0.03) << "rho_inf " << rho << " w h " << wh;
    }
  }
}

}  // namespace
}  // namespace nvh::solve
