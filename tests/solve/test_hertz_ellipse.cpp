// Hertz's exact elliptical point contact (solve/elements/hertz_point.hpp, the crowned roller of roller-cam)
// against an independent evaluation in SciPy: testdata/valvetrain/hertz_ellipse_reference.py solves Hertz's
// potential integrals by quadrature (no elliptic integral) and Johnson's eqs. 4.39-4.41 with SciPy's
// ellipk/ellipe, the two agreeing to 4e-13, and tabulates the ellipticity a/b and Harris & Kotzalas's
// dimensionless a*, b*, delta* (Rolling Bearing Analysis, 5th ed. 2007, eqs. 6.39-6.41) against the radius
// ratio r = Rmax/Rmin. Checked here:
// - the exact solve (Newton on the eccentricity) at every tabulated ratio, 1 .. 3000: to 1e-10 (the circular
//   limit r = 1 to 1e-15);
// - its s-derivatives (s = ln r) against central differences of the exact solve: to 1e-7;
// - the element's interpolation table against the exact solve, densely over 1 .. 1e4: to 1e-9 (the measured
//   interpolation error is printed, 1.4e-10);
// - the force law F = K_h delta^1.5 against the reference's delta* at ratios 2.5 .. 300 and both orientations
//   (the major axis along x or y), and dK_h/dRx against a central difference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "solve/elements/hertz_point.hpp"

namespace nvh::solve {
namespace {

constexpr double kPi = std::numbers::pi;

struct Row {
  double ratio, curvature_difference, ellipticity, a_star, b_star, delta_star;
};

std::vector<Row> reference() {
  const std::filesystem::path path =
      std::filesystem::path(NVH_SOURCE_DIR) / "testdata" / "valvetrain" / "hertz_ellipse_reference.csv";
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::vector<Row> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 'r') continue;  // comment, header
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream s(line);
    Row r{};
    s >> r.ratio >> r.curvature_difference >> r.ellipticity >> r.a_star >> r.b_star >> r.delta_star;
    rows.push_back(r);
  }
  EXPECT_EQ(rows.size(), 24u);
  return rows;
}

double rel(double x, double ref) {
  return std::abs(x / ref - 1);
}

TEST(HertzEllipse, ExactSolveAgainstScipyReference) {
  double worst = 0, worst_circular = 0;
  for (const Row& r : reference()) {
    const hertz::EllipseShape e = hertz::ellipse_shape(r.ratio);
    const double err = std::max({rel(e.ellipticity(), r.ellipticity), rel(e.a_star, r.a_star),
                                 rel(e.b_star, r.b_star), rel(e.delta_star, r.delta_star)});
    if (r.ratio == 1) worst_circular = err;
    worst = std::max(worst, err);
    EXPECT_LT(err, r.ratio == 1 ? 1e-15 : 1e-10) << "ratio " << r.ratio;
    // the curvature relation (H1) itself, with the tabulated ellipticity: B/A = ((a/b)^2 E - K) / (K - E)
    const double m = 1 - 1 / (r.ellipticity * r.ellipticity);
    if (m > 1e-3) {
      const double kk = std::comp_ellint_1(std::sqrt(m)), ee = std::comp_ellint_2(std::sqrt(m));
      EXPECT_NEAR((r.ellipticity * r.ellipticity * ee - kk) / (kk - ee), r.ratio, 1e-9 * r.ratio);
    }
  }
  std::printf(
      "measured: exact solve against the SciPy reference (24 ratios 1 .. 3000): worst %.2e, circular "
      "limit %.2e\n",
      worst, worst_circular);
}

TEST(HertzEllipse, DerivativesAgainstCentralDifferences) {
  double worst = 0;
  for (const double r : {1.0, 1.05, 2.5, 10.0, 62.0, 300.0, 5000.0}) {
    const hertz::EllipseShape e = hertz::ellipse_shape(r);
    const double h = 1e-5, s = std::log(r);
    const hertz::EllipseShape up = hertz::ellipse_shape(std::exp(s + h));
    // at r = 1 the shape is even in s (swapping the axes): the one-sided difference of the even part
    const hertz::EllipseShape down = hertz::ellipse_shape(r == 1 ? std::exp(h) : std::exp(s - h));
    const double sign = r == 1 ? -1 : 1;
    auto diff = [&](double hi, double lo) { return (std::log(hi) - sign * std::log(lo)) / (2 * h); };
    // at r = 1: d ln a*/ds = 1/3, d ln b*/ds = -1/3 one-sided (the semi-axes swap), d ln delta*/ds = 0
    const double da = r == 1 ? (std::log(up.a_star)) / h : diff(up.a_star, down.a_star);
    const double db = r == 1 ? (std::log(up.b_star)) / h : diff(up.b_star, down.b_star);
    const double dd = r == 1 ? 0.0 : diff(up.delta_star, down.delta_star);
    const double tol = r == 1 ? 1e-4 : 1e-7;  // one-sided at r = 1: O(h)
    EXPECT_NEAR(e.dln_a, da, tol) << r;
    EXPECT_NEAR(e.dln_b, db, tol) << r;
    EXPECT_NEAR(e.dln_delta, dd, tol) << r;
    if (r > 1)
      worst = std::max({worst, std::abs(e.dln_a - da), std::abs(e.dln_b - db), std::abs(e.dln_delta - dd)});
  }
  std::printf("measured: d/d ln r of ln a*, ln b*, ln delta* against central differences: worst %.2e\n",
              worst);
}

TEST(HertzEllipse, InterpolationTableAgainstExactSolve) {
  const hertz::EllipseTable table;  // 1 .. 1e4, 256 intervals in ln r
  double worst = 0, worst_slope = 0, at = 1;
  const int n = 4000;  // 15.6 samples per interval, never on a node
  for (int i = 0; i <= n; ++i) {
    const double r = std::exp(std::log(table.max_ratio()) * (i + 0.37) / (n + 1));
    const hertz::EllipseShape x = hertz::ellipse_shape(r), t = table(r);
    const double err = std::max({rel(t.a_star, x.a_star), rel(t.b_star, x.b_star),
                                 rel(t.delta_star, x.delta_star), rel(t.ellipticity(), x.ellipticity())});
    if (err > worst) worst = err, at = r;
    worst_slope = std::max({worst_slope, std::abs(t.dln_a - x.dln_a), std::abs(t.dln_b - x.dln_b),
                            std::abs(t.dln_delta - x.dln_delta)});
  }
  std::printf(
      "measured: table (256 intervals in ln r over 1 .. 1e4) against the exact solve: worst relative "
      "%.2e (at r = %.4g), slopes %.2e\n",
      worst, at, worst_slope);
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(worst_slope, 1e-6);
  // exact at the circular node; beyond the table the exact solve
  EXPECT_EQ(table(1.0).a_star, 1.0);
  EXPECT_EQ(table(2e4).delta_star, hertz::ellipse_shape(2e4).delta_star);
}

// The force law against the reference's delta*: delta = delta* s^2 Sigma rho / 2, s = (3 F / (2 Sigma rho
// E*))^(1/3) (Harris & Kotzalas eq. 6.41), i.e. F = (2 Sigma rho E* / 3) (2 delta / (delta* Sigma rho))^1.5.
TEST(HertzEllipse, ForceLawAndSemiAxesAgainstReference) {
  const double e_star = 113.7e9, rmin = 0.0075;
  const hertz::PointLaw law(e_star);
  double worst = 0;
  for (const Row& r : reference()) {
    if (r.ratio < 2.5 || r.ratio > 300) continue;
    for (const bool major_along_y : {true, false}) {
      const double rx = major_along_y ? rmin : rmin * r.ratio, ry = major_along_y ? rmin * r.ratio : rmin;
      const double sigma = 1 / rx + 1 / ry, delta = 12e-6;
      const double f_ref = 2 * sigma * e_star / 3 * std::pow(2 * delta / (r.delta_star * sigma), 1.5);
      const double f = law.stiffness(rx, ry) * std::pow(delta, 1.5);
      const double s = std::cbrt(3 * f_ref / (2 * sigma * e_star));
      const hertz::PointContact c = hertz::point_contact(f_ref, rx, ry, e_star, law.shape(rx, ry));
      const double a = major_along_y ? c.ay : c.ax, b = major_along_y ? c.ax : c.ay;
      const double p_ref = 3 * f_ref / (2 * kPi * r.a_star * r.b_star * s * s);
      const double err =
          std::max({rel(f, f_ref), rel(a, r.a_star * s), rel(b, r.b_star * s), rel(c.p0, p_ref)});
      worst = std::max(worst, err);
      EXPECT_LT(err, 1e-6) << "ratio " << r.ratio
                           << (major_along_y ? " (major along y)" : " (major along x)");
      // dK/drx against a central difference of the law
      const double h = 1e-6 * rx;
      const double fd = (law.stiffness(rx + h, ry) - law.stiffness(rx - h, ry)) / (2 * h);
      EXPECT_NEAR(law.stiffness_derivative(rx, ry), fd,
                  1e-6 * std::abs(fd) + 1e-9 * law.stiffness(rx, ry) / rx);
    }
  }
  std::printf("measured: K_h delta^1.5, a, b, p0 against the reference at ratios 2.5 .. 300: worst %.2e\n",
              worst);
}

TEST(HertzEllipse, RejectsARatioBelowOne) {
  EXPECT_THROW(hertz::ellipse_shape(0.5), std::invalid_argument);
  EXPECT_THROW(hertz::ellipse_shape(std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace nvh::solve
