// The 1D slider (solve/bearing/slider.hpp) against the exact 1D solutions derived in docs/bearing.md,
// section 13 (none computed with this code).
//
// Geometry (SI): L = 10 mm, h0 = 10 um outside, U = 2 m/s (the Couette flux is U h / 2), mu = 0.02 Pa s,
// p(0) = p(L) = 0, full film at the inlet.
// - Step-pocket slider: an inlet step [0, x1] 5 um deeper (a Rayleigh step, for a positive inlet film
//   pressure) and a pocket [xa, xb] 10 um deep; x1 = 4 mm, xa = 6 mm, xb = 9 mm. JFO: full film on
//   [0, xa] with p(xa) = 0 (rupture at the pocket's edge), cavitated pocket [xa, xc] with fill
//   q / (U h1 / 2), reformation at xc, full film [xc, L]. Swift-Stieber: the same inlet film, but the
//   pocket is pressurized from xa on (mass is created at xa).
// - Parallel pocket slider (no step): JFO carries no load (p = 0, fill h0 / h1 in the pocket); Swift-Stieber
//   carries a triangle of pressure over [xa, L].
// The finite-volume error is first order in the cell size (the rupture and reformation boundaries); the
// tolerances are stated at 400 cells (dx / L = 2.5e-3: JFO 3e-3, Swift-Stieber 1e-2, about twice the
// measured errors) and the measured order is checked on 100 ... 800 cells (1 +- 0.1).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "common/error.hpp"
#include "solve/bearing/slider.hpp"

namespace nvh::bearing {
namespace {

constexpr double kL = 0.01, kH0 = 10e-6, kU = 2.0, kMu = 0.02;
constexpr double kX1 = 0.004, kXa = 0.006, kXb = 0.009, kStep = 5e-6, kDepth = 10e-6;

SliderSpec pocket_slider(bool inlet_step, Cavitation cavitation, int cells) {
  SliderSpec s;
  s.length = kL;
  s.film_inlet = s.film_outlet = kH0;
  s.speed = kU;
  s.viscosity = kMu;
  if (inlet_step) s.pockets.push_back({0, kX1, kStep});
  s.pockets.push_back({kXa, kXb, kDepth});
  s.cavitation = cavitation;
  s.cells = cells;
  return s;
}

/// The exact solution of docs/bearing.md section 13 (K = 12 mu, Um = U / 2, piecewise-constant film).
struct Exact {
  double q;         // m^2/s, flux (JFO: everywhere; Swift-Stieber: upstream of xa)
  double p1;        // Pa, at x1 (the inlet step)
  double p2;        // Pa, at xb (JFO)
  double xc;        // m, reformation (JFO)
  double fill;      // fill ratio in the cavitated pocket (JFO)
  double load;      // N/m (JFO)
  double p2_ss;     // Pa, at xb (Swift-Stieber)
  double q_out_ss;  // m^2/s, downstream of xa (Swift-Stieber)
  double load_ss;   // N/m (Swift-Stieber)
};

Exact exact(bool inlet_step) {
  const double K = 12 * kMu, Um = 0.5 * kU, hA = kH0 + (inlet_step ? kStep : 0.0), h1 = kH0 + kDepth;
  const double lA = inlet_step ? kX1 : 0.0, lB = kXa - lA, lP = kXb - kXa, lC = kL - kXb;
  Exact e{};
  // Full film on [0, xa] with p(0) = p(xa) = 0: sum of (Um h - q) K l / h^3 = 0.
  e.q = Um * (lA / (hA * hA) + lB / (kH0 * kH0)) / (lA / (hA * hA * hA) + lB / (kH0 * kH0 * kH0));
  e.p1 = K * (Um * hA - e.q) * lA / (hA * hA * hA);
  // JFO: the same flux through the cavitated pocket (fill q / (Um h1)) and the full film [xc, L].
  const double slope_pocket = K * (Um * h1 - e.q) / (h1 * h1 * h1);
  const double slope_land = K * (Um * kH0 - e.q) / (kH0 * kH0 * kH0);
  e.p2 = -slope_land * lC;
  e.xc = kXb - e.p2 / slope_pocket;
  e.fill = e.q / (Um * h1);
  e.load = 0.5 * e.p1 * kXa + 0.5 * e.p2 * (kL - e.xc);
  // Swift-Stieber: p = 0 at xa, full film [xa, L]: flux continuity at xb fixes the pocket slope s.
  const double s = K * Um * (h1 - kH0) / (h1 * h1 * h1 + kH0 * kH0 * kH0 * lP / lC);
  e.p2_ss = s * lP;
  e.q_out_ss = Um * h1 - h1 * h1 * h1 * s / K;
  e.load_ss = 0.5 * e.p1 * kXa + 0.5 * e.p2_ss * (kL - kXa);
  return e;
}

double face_pressure_at(const SliderResult& r, double x) {
  const int n = static_cast<int>(r.face_pressure.size()) - 1;
  return r.face_pressure[static_cast<int>(std::lround(x / kL * n))];
}

/// First and last cavitated cell (fill < 1) as the faces that bound them: {rupture, reformation}.
std::pair<double, double> cavitated_zone(const SliderResult& r) {
  const int n = static_cast<int>(r.x.size());
  const double dx = kL / n;
  int first = -1, last = -1;
  for (int i = 0; i < n; ++i)
    if (r.fill_ratio[i] < 1 - 1e-12) {
      if (first < 0) first = i;
      last = i;
    }
  if (first < 0) return {-1, -1};
  return {first * dx, (last + 1) * dx};
}

TEST(bearing_slider, StepPocketJfoAgainstExactSolution) {
  const Exact e = exact(true);
  const SliderResult r = solve_slider(pocket_slider(true, Cavitation::kJfo, 400));
  const double dx = kL / 400;
  const auto [rupture, reformation] = cavitated_zone(r);
  const double p1 = face_pressure_at(r, kX1), p2 = face_pressure_at(r, kXb);
  std::printf(
      "step-pocket JFO, 400 cells: p1 %.6g Pa (exact %.6g, %.2e), p2 %.6g (exact %.6g, %.2e), load %.6g N/m "
      "(exact %.6g, %.2e), flow %.6g m^2/s (exact %.6g, %.2e), in/out - 1 = %.1e, rupture %.4g mm "
      "(exact %.4g), reformation %.4g mm (exact %.4g), fill %.5f (exact %.5f), max p %.6g at %.4g mm\n",
      p1, e.p1, p1 / e.p1 - 1, p2, e.p2, p2 / e.p2 - 1, r.load, e.load, r.load / e.load - 1, r.flow_at_start,
      e.q, r.flow_at_start / e.q - 1, r.flow_at_start / r.flow_at_end - 1, 1e3 * rupture, 1e3 * kXa,
      1e3 * reformation, 1e3 * e.xc, r.fill_ratio[static_cast<int>(0.65 * 400)], e.fill, r.max_pressure,
      1e3 * r.max_pressure_position);
  EXPECT_NEAR(p1 / e.p1, 1.0, 3e-3);  // the pressure peak at the inlet step
  EXPECT_NEAR(r.max_pressure / e.p1, 1.0, 3e-3);
  EXPECT_NEAR(r.max_pressure_position, kX1, 1e-12);
  EXPECT_NEAR(p2 / e.p2, 1.0, 3e-3);  // the second peak, at the pocket's exit
  EXPECT_NEAR(r.load / e.load, 1.0, 3e-3);
  EXPECT_NEAR(r.flow_at_start / e.q, 1.0, 1e-3);
  EXPECT_NEAR(r.flow_at_end / r.flow_at_start, 1.0, 1e-12);  // mass is conserved
  EXPECT_NEAR(rupture, kXa, 1e-9);                           // cavitation starts at the pocket's edge
  EXPECT_NEAR(reformation, e.xc, 2 * dx);
  EXPECT_NEAR(r.fill_ratio[static_cast<int>(0.65 * 400)] / e.fill, 1.0, 1e-3);  // x = 6.5 mm
}

TEST(bearing_slider, StepPocketJfoConvergesAtFirstOrder) {
  const Exact e = exact(true);
  double last_load = 0, last_p1 = 0, last_q = 0;
  for (int n : {100, 200, 400, 800}) {
    const SliderResult r = solve_slider(pocket_slider(true, Cavitation::kJfo, n));
    const double load = std::abs(r.load - e.load), p1 = std::abs(face_pressure_at(r, kX1) - e.p1),
                 q = std::abs(r.flow_at_start - e.q);
    if (last_load > 0) {
      const double o_load = std::log2(last_load / load), o_p1 = std::log2(last_p1 / p1),
                   o_q = std::log2(last_q / q);
      std::printf("step-pocket JFO %4d cells: errors load %.3e, p1 %.3e, flow %.3e; orders %.3f %.3f %.3f\n",
                  n, load / e.load, p1 / e.p1, q / e.q, o_load, o_p1, o_q);
      EXPECT_NEAR(o_load, 1.0, 0.1) << n;
      EXPECT_NEAR(o_p1, 1.0, 0.1) << n;
      EXPECT_NEAR(o_q, 1.0, 0.1) << n;
    }
    last_load = load, last_p1 = p1, last_q = q;
  }
}

TEST(bearing_slider, SwiftStieberPressurizesThePocketAndCreatesMass) {
  const Exact e = exact(true);
  const SliderResult ss = solve_slider(pocket_slider(true, Cavitation::kSwiftStieber, 400));
  const SliderResult jfo = solve_slider(pocket_slider(true, Cavitation::kJfo, 400));
  const double p2 = face_pressure_at(ss, kXb);
  std::printf(
      "step-pocket Swift-Stieber, 400 cells: p2 %.6g Pa (exact %.6g, %.2e), load %.6g N/m (exact %.6g, "
      "%.2e; JFO %.6g), outflow/inflow %.5f (exact %.5f)\n",
      p2, e.p2_ss, p2 / e.p2_ss - 1, ss.load, e.load_ss, ss.load / e.load_ss - 1, jfo.load,
      ss.flow_at_end / ss.flow_at_start, e.q_out_ss / e.q);
  EXPECT_NEAR(p2 / e.p2_ss, 1.0, 1e-2);
  EXPECT_NEAR(ss.load / e.load_ss, 1.0, 1e-2);
  EXPECT_NEAR(ss.flow_at_start / e.q, 1.0, 1e-3);
  EXPECT_NEAR(ss.flow_at_end / e.q_out_ss, 1.0, 1e-3);
  // Different answers for the same pocket: the exact loads differ by 20 %, the outflow by 7 %.
  EXPECT_GT(ss.load / jfo.load - 1, 0.15);
  EXPECT_GT(ss.flow_at_end / ss.flow_at_start - 1, 0.05);
  EXPECT_DOUBLE_EQ(ss.fill_ratio.minCoeff(), 1.0);
}

TEST(bearing_slider, ParallelPocketCarriesNoLoadWithJfo) {
  const Exact e = exact(false);
  const double Um = 0.5 * kU, p_scale = 12 * kMu * kL * Um / (kH0 * kH0);
  const SliderResult jfo = solve_slider(pocket_slider(false, Cavitation::kJfo, 400));
  EXPECT_LT(jfo.max_pressure, 1e-9 * p_scale);
  EXPECT_NEAR(jfo.flow_at_start, Um * kH0, 1e-12 * Um * kH0);
  EXPECT_NEAR(jfo.flow_at_end, Um * kH0, 1e-12 * Um * kH0);
  EXPECT_NEAR(jfo.fill_ratio[static_cast<int>(0.75 * 400)], kH0 / (kH0 + kDepth), 1e-12);
  const SliderResult ss = solve_slider(pocket_slider(false, Cavitation::kSwiftStieber, 400));
  std::printf(
      "parallel pocket: JFO max p %.2e Pa, fill %.15f; Swift-Stieber load %.6g N/m (exact %.6g, %.2e), "
      "peak %.6g Pa (exact %.6g)\n",
      jfo.max_pressure, jfo.fill_ratio[300], ss.load, e.load_ss, ss.load / e.load_ss - 1, ss.max_pressure,
      e.p2_ss);
  EXPECT_NEAR(ss.load / e.load_ss, 1.0, 1e-2);
  EXPECT_NEAR(ss.max_pressure / e.p2_ss, 1.0, 1e-2);
  EXPECT_NEAR(ss.max_pressure_position, kXb, 1e-12);
}

TEST(bearing_slider, BadInputNamesTheField) {
  SliderSpec s = pocket_slider(true, Cavitation::kJfo, 100);
  s.pockets[1].end = 2 * kL;
  try {
    solve_slider(s);
    FAIL() << "no error for a pocket beyond the slider";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("pockets[1]"), std::string::npos) << e.what();
  }
  s = pocket_slider(true, Cavitation::kJfo, 100);
  s.viscosity = 0;
  try {
    solve_slider(s);
    FAIL() << "no error for viscosity 0";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("viscosity"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nvh::bearing
