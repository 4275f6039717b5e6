// The piston-skirt film (solve/bearing/skirt_film.hpp) against closed forms not computed with this code.
//
// Squeeze of a centred skirt (e = 0, full film: Cavitation::kNone so that the closed forms hold), h = c,
// dh/dt = -de(y)/dt cos(theta). The Reynolds equation c^3 / (12 mu) lap p = dh/dt separates in
// p = f(y) cos(theta), f'' - f / R^2 = -12 mu de(y)/dt / c^3, f = 0 at both edges x = y - y_c = +-L/2:
// - uniform rate v (lateral translation): f = A (1 - cosh(x / R) / cosh(L / 2R)), A = 12 mu v R^2 / c^3, so
//   F = -pi R A (L - 2 R tanh(L / 2R)) (the separation of docs/bearing.md section 7, done for the journal).
//   Short limit (L << R: Ocvirk's dropping of the circumferential flow; Dubois and Ocvirk, NACA Report 1157,
//   1953): f = 6 mu v (L^2/4 - x^2) / c^3, F = -pi mu R L^3 v / c^3 (the full film; the half-Sommerfeld
//   film carries half of it, as in docs/bearing.md section 10); F_exact / F_short = 1 - (L/R)^2 / 10 + ...
//   Long limit (L >> R, Sommerfeld): f = A away from the edges, F per unit length = -12 pi mu R^3 v / c^3
//   (the long journal's squeeze load 12 pi mu R^3 L v / (c^3 (1 - eps^2)^(3/2)) at eps = 0; Hamrock, Schmid
//   and Jacobson, Fundamentals of Fluid Film Lubrication, 2nd ed., 2004); at the mid-plane
//   f / A = 1 - 1 / cosh(L / 2R).
// - pure tilt rate w about the skirt's centre (de/dt = w x): f = 12 mu w R^2 / c^3 (x - (L/2) sinh(x / R) /
//   sinh(L / 2R)), F = 0, and the moment about the centre M_c = int f x cos^2(theta) R dtheta dx =
//   12 pi mu w R^3 / c^3 (L^3 / 12 - R L^2 coth(L / 2R) / 2 + R^2 L); short limit pi mu R w L^5 / (60 c^3)
//   (exact / short = 1 - (L/R)^2 / 42 + ...). About the pin: M = M_c - y_c F.
// The finite volumes are second order here (smooth film, exact face films): the tolerances come from the
// grid-convergence runs of SqueezeConvergesAtSecondOrder (measured errors in docs/bearing.md section 14).
//
// Infinitely wide inclined slider (Reynolds, Phil. Trans. R. Soc. 177 (1886) 157; the fixed-incline slider
// of Hamrock et al.): per unit width, a film falling linearly from h_in to h_out over L, one surface sliding
// at U towards the thin end:
//   p(h) = 6 mu U L (h_in - h)(h - h_out) / ((h_in^2 - h_out^2) h^2),
//   W = 6 mu U L^2 / (h_out^2 (K - 1)^2) (ln K - 2 (K - 1) / (K + 1)),   K = h_in / h_out,
// and the shear force on the surface at rest, along U (tau = mu U / h - (h / 2) dp/dx integrated; the
// Poiseuille part by parts, int h p' dx = (h_in - h_out) W / L):
//   F = mu U L ln K / (h_in - h_out) - (h_in - h_out) W / (2 L).
// The skirt: a wide arc (R = 0.25 m, +-60 deg: 52 L of arc) tilted so that h = c - e_top cos(theta) s,
// s = (y - y_bottom) / L, the piston moving down (the liner sliding up relative to it, towards the thin end
// at theta = 0): the column of cells at the arc's centre against p(h) and W, the friction against the strip
// sum of F over the arc. The film's variation around (cos theta) makes the centre differ from the infinitely
// wide slider by about 3e-4 (measured against R = 1 m).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <string>

#include "common/error.hpp"
#include "solve/bearing/skirt_film.hpp"

namespace nvh::bearing {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kMu = 0.01, kC = 20e-6;

SkirtSpec full_circle(double R, double L, int axial, int around) {
  SkirtSpec s;
  s.bore_radius = R;
  s.radial_clearance = kC;
  s.skirt_length = L;
  s.skirt_top = 0.6 * L;  // the pin below the skirt's centre: y_c = 0.1 L
  s.arcs = {{-kPi, kPi}};
  s.viscosity = kMu;
  s.cavitation = Cavitation::kNone;
  s.cells_axial = axial;
  s.cells_around = around;
  return s;
}

double squeeze_force_exact(double R, double L, double v) {
  const double A = 12 * kMu * v * R * R / (kC * kC * kC);
  return -kPi * R * A * (L - 2 * R * std::tanh(L / (2 * R)));
}

double tilt_moment_exact(double R, double L, double w) {
  return 12 * kPi * kMu * w * R * R * R / (kC * kC * kC) *
         (L * L * L / 12 - R * L * L / (2 * std::tanh(L / (2 * R))) + R * R * L);
}

struct Squeeze {
  double force_error, moment_error, tilt_error;
};

// Uniform squeeze at v (force, and its moment about the pin: -y_c F) and pure tilt at w (moment), relative to
// the separated solutions.
Squeeze squeeze_errors(double R, double L, int axial, int around) {
  const SkirtSpec s = full_circle(R, L, axial, around);
  const double v = 0.01, w = 1.0, y_c = s.skirt_top - 0.5 * L;
  SkirtFilm film(s);
  SkirtKinematics k;
  k.e_top_dot = k.e_bottom_dot = v;
  const SkirtResult u = film.evaluate(k);
  const double F = squeeze_force_exact(R, L, v);
  k.e_top_dot = 0.5 * w * L, k.e_bottom_dot = -0.5 * w * L;
  const SkirtResult t = film.evaluate(k);
  return {u.side_force / F - 1, u.moment / (-y_c * F) - 1, t.moment / tilt_moment_exact(R, L, w) - 1};
}

TEST(bearing_skirt, SqueezeAgainstSeparatedSolution) {
  // A skirt-like L / D = 0.8 (D = 90 mm), 80 x 144 cells: the errors are second order (next test) and mostly
  // from the axial direction (80 x 72: 4.3e-4 and 1.6e-3). Tolerances about twice the measured errors.
  const Squeeze e = squeeze_errors(0.045, 0.072, 80, 144);
  std::printf("squeeze, L/D 0.8, 80x144: force %.2e, moment about the pin %.2e, tilt moment %.2e\n",
              e.force_error, e.moment_error, e.tilt_error);
  EXPECT_LT(std::abs(e.force_error), 7e-4);
  EXPECT_LT(std::abs(e.moment_error), 7e-4);
  EXPECT_LT(std::abs(e.tilt_error), 3e-3);
}

TEST(bearing_skirt, SqueezeConvergesAtSecondOrder) {
  double last = 0;
  for (int level = 0; level < 3; ++level) {
    const int m = 1 << level;
    const Squeeze e = squeeze_errors(0.045, 0.072, 20 * m, 36 * m);
    std::printf("squeeze, %dx%d: force %.3e, tilt moment %.3e\n", 20 * m, 36 * m, e.force_error,
                e.tilt_error);
    if (level > 0) {
      const double order = std::log2(last / std::abs(e.force_error));
      std::printf("  observed order (force) %.3f\n", order);
      EXPECT_NEAR(order, 2.0, 0.1);
    }
    last = std::abs(e.force_error);
  }
}

TEST(bearing_skirt, SqueezeShortLimitAgainstOcvirk) {
  // L / R = 0.05: the short-bearing closed forms hold to (L/R)^2 / 10 = 2.5e-4 (force) and / 42 = 6e-5 (tilt
  // moment); 160 x 72 cells add about 1e-4 (the grid errors of SqueezeConvergesAtSecondOrder at this axial
  // cell count, of the opposite sign).
  const double R = 0.05, L = 0.0025, v = 0.01, w = 1.0;
  const SkirtSpec s = full_circle(R, L, 160, 72);
  const double y_c = s.skirt_top - 0.5 * L;
  SkirtFilm film(s);
  SkirtKinematics k;
  k.e_top_dot = k.e_bottom_dot = v;
  const SkirtResult u = film.evaluate(k);
  const double F = -kPi * kMu * R * L * L * L * v / (kC * kC * kC);
  k.e_top_dot = 0.5 * w * L, k.e_bottom_dot = -0.5 * w * L;
  const SkirtResult t = film.evaluate(k);
  const double M = kPi * kMu * R * w * std::pow(L, 5) / (60 * kC * kC * kC);
  std::printf(
      "short squeeze: F / (-pi mu R L^3 v / c^3) - 1 = %.2e; M / (pi mu R w L^5 / (60 c^3)) - 1 = %.2e\n",
      u.side_force / F - 1, t.moment / M - 1);
  EXPECT_NEAR(u.side_force / F, 1.0, 5e-4);
  EXPECT_NEAR(u.moment / (-y_c * F), 1.0, 5e-4);
  EXPECT_NEAR(t.moment / M, 1.0, 5e-4);
  EXPECT_LT(std::abs(t.side_force), 1e-9 * std::abs(F));  // antisymmetric in y: no net force
  EXPECT_LT(std::abs(u.pin_force), 1e-9 * std::abs(F));
}

TEST(bearing_skirt, SqueezeLongLimitAgainstSommerfeld) {
  // L / R = 20: at the mid-plane f / A = 1 - 1 / cosh(10) = 1 - 9e-5. The ring of cells at the mid-plane
  // (odd number of cells along the axis) against Sommerfeld's -12 pi mu R^3 v / c^3 per unit length; its grid
  // error is the circumferential one, the discrete Laplacian's (2 - 2 cos dtheta) / dtheta^2 = 1 - dtheta^2 /
  // 12 (6.3e-4 at 72 cells). The total force against the separated solution (161 cells along: 8e-4,
  // 321: 6.5e-4).
  const double R = 0.02, L = 0.4, v = 0.01;
  const SkirtSpec s = full_circle(R, L, 161, 72);
  SkirtFilm film(s);
  SkirtKinematics k;
  k.e_top_dot = k.e_bottom_dot = v;
  const SkirtResult u = film.evaluate(k);
  const Eigen::MatrixXd p = film.pressure(0);
  double per_length = 0;
  for (int j = 0; j < s.cells_around; ++j)
    per_length -= p(80, j) * std::cos(film.angle(0, j)) * R * 2 * kPi / 72;
  const double sommerfeld = -12 * kPi * kMu * R * R * R * v / (kC * kC * kC);
  std::printf("long squeeze: mid-plane F' / Sommerfeld - 1 = %.2e; total F / separated - 1 = %.2e\n",
              per_length / sommerfeld - 1, u.side_force / squeeze_force_exact(R, L, v) - 1);
  EXPECT_NEAR(per_length / sommerfeld, 1.0, 1e-3);
  EXPECT_NEAR(u.side_force / squeeze_force_exact(R, L, v), 1.0, 1.5e-3);
}

// The wide tilted arc of the inclined-slider test.
constexpr double kSliderR = 0.25, kSliderL = 0.01, kETop = 10e-6, kSpeed = -10.0;
SkirtSpec slider_skirt(int axial, int around) {
  SkirtSpec s;
  s.bore_radius = kSliderR;
  s.radial_clearance = kC;
  s.skirt_length = kSliderL;
  s.skirt_top = 0.005;
  s.arcs = {{-kPi / 3, kPi / 3}};
  s.viscosity = kMu;
  s.cells_axial = axial;
  s.cells_around = around;  // odd: a column of cells centred on theta = 0
  return s;
}
SkirtKinematics slider_motion() {
  SkirtKinematics k;
  k.e_top = kETop;  // h = c at the bottom edge, c - e_top cos(theta) at the top
  k.speed = kSpeed;
  return k;
}

double slider_load(double U, double L, double h_in, double h_out) {
  const double K = h_in / h_out;
  return 6 * kMu * U * L * L / (h_out * h_out * (K - 1) * (K - 1)) * (std::log(K) - 2 * (K - 1) / (K + 1));
}
double slider_pressure(double U, double L, double h_in, double h_out, double h) {
  return 6 * kMu * U * L * (h_in - h) * (h - h_out) / ((h_in * h_in - h_out * h_out) * h * h);
}
double slider_friction(double U, double L, double h_in, double h_out) {
  return kMu * U * L * std::log(h_in / h_out) / (h_in - h_out) -
         (h_in - h_out) * slider_load(U, L, h_in, h_out) / (2 * L);
}

TEST(bearing_skirt, InclinedSliderAtTheArcCentreAgainstReynolds) {
  const int axial = 100, around = 121;
  SkirtFilm film(slider_skirt(axial, around));
  const SkirtResult r = film.evaluate(slider_motion());
  const double U = std::abs(kSpeed), h_in = kC, h_out = kC - kETop;
  const Eigen::MatrixXd p = film.pressure(0);
  const int centre = around / 2;
  ASSERT_NEAR(film.angle(0, centre), 0.0, 1e-15);
  double load = 0, worst = 0, peak = 0;
  for (int i = 0; i < axial; ++i) {
    const double y = film.axial_position(i), h = kC - kETop * (y - (0.005 - kSliderL)) / kSliderL;
    const double ref = slider_pressure(U, kSliderL, h_in, h_out, h);
    load += p(i, centre) * kSliderL / axial;
    worst = std::max(worst, std::abs(p(i, centre) - ref));
    peak = std::max(peak, ref);
  }
  const double W = slider_load(U, kSliderL, h_in, h_out);
  // Friction: the strip sum of the 1D closed form over the arc (Simpson, 2000 intervals), along +y on the
  // piston (the liner slides up relative to it).
  double strips = 0;
  const int n = 2000;
  for (int j = 0; j <= n; ++j) {
    const double t = -kPi / 3 + j * (2 * kPi / 3) / n;
    const double wgt = j == 0 || j == n ? 1 : (j % 2 ? 4 : 2);
    strips +=
        wgt * slider_friction(U, kSliderL, kC, kC - kETop * std::cos(t)) * kSliderR * (2 * kPi / 3) / (3 * n);
  }
  std::printf(
      "inclined slider, centre: load/W - 1 = %.2e (W = %.1f N/m), max |p - p_ref| / p_max = %.2e; "
      "friction / strip sum - 1 = %.2e\n",
      load / W - 1, W, worst / peak, r.friction_force / strips - 1);
  // Tolerances: the grid (100 cells along: 3.2e-4 in the load at R = 1 m, second order) plus the film's
  // variation around (3e-4, of the opposite sign here).
  EXPECT_NEAR(load / W, 1.0, 1e-3);
  EXPECT_LT(worst / peak, 1.5e-3);
  EXPECT_NEAR(r.friction_force / strips, 1.0, 1e-3);
  EXPECT_LT(r.side_force, 0);  // the film pushes the piston away from the thrust side
  EXPECT_GT(film.fill_ratio(0).minCoeff(), 1 - 1e-12);  // p > 0 everywhere: JFO keeps the full film
}

TEST(bearing_skirt, JfoConservesMassWithCavitationAndSqueeze) {
  // Tilted, sliding up, squeezing, with barrel and ovality, starved at the top (the inlet when V > 0): on the
  // thrust side the film diverges along the flow (cavitated), on the anti-thrust side it converges. The two
  // panels (side leakage), then the full circle (none). Continuity of the discrete fluxes:
  // flow_bottom + flow_top = flow_sides + stored_flow to round-off.
  for (bool panels : {true, false}) {
    SkirtSpec s;
    s.bore_radius = 0.045;
    s.radial_clearance = kC;
    s.skirt_length = 0.04;
    s.skirt_top = 0.012;
    s.viscosity = kMu;
    s.fill_top = 0.8;
    s.cells_axial = 40;
    s.cells_around = panels ? 30 : 72;
    if (!panels) s.arcs = {{-kPi, kPi}};
    s.barrel = {{-0.028, -0.008, 0.012}, {15e-6, 0.0, 10e-6}};
    s.ovality = {{-kPi / 2, 0, kPi / 2}, {20e-6, 0.0, 20e-6}};
    SkirtFilm film(s);
    SkirtKinematics k;
    k.e_top = 0.6 * kC, k.e_bottom = -0.3 * kC;
    k.e_top_dot = 0.05, k.e_bottom_dot = -0.02;
    k.speed = 8;
    const SkirtResult r = film.evaluate(k);
    const double in = r.flow_bottom + r.flow_top, out = r.flow_sides + r.stored_flow;
    const double scale =
        std::abs(r.flow_bottom) + std::abs(r.flow_top) + std::abs(r.flow_sides) + std::abs(r.stored_flow);
    std::printf(
        "JFO continuity (%s): in %.6e, out through the sides %.6e, stored %.6e m^3/s; |in - out| / "
        "scale = %.1e\n",
        panels ? "panels" : "full circle", in, r.flow_sides, r.stored_flow, std::abs(in - out) / scale);
    EXPECT_LT(std::abs(in - out), 1e-10 * scale);
    EXPECT_GT(std::abs(r.stored_flow), 0.05 * scale);  // the squeeze counts
    if (!panels) {
      EXPECT_EQ(r.flow_sides, 0.0);
    }
    double least = 1;
    for (int a = 0; a < film.arcs(); ++a) least = std::min(least, film.fill_ratio(a).minCoeff());
    EXPECT_LT(least, 0.9);  // there is a cavitated zone
    EXPECT_GE(least, 0.0);
  }
}

// Partial flooding. A wedge along the axis that is the same all around (a linear barrel profile: h falls from
// h_in = 20 um at the bottom edge to h_out = 10 um at the top, e = 0) on the wide arc, the piston moving
// down: the arc's centre is the infinitely wide slider, starved at its inlet with the fill ratio f. With JFO
// (derived as in docs/bearing.md section 13.1): the film enters cavitated (p = 0) carrying q = f U h_in / 2
// and reforms at h_r, from where a full inclined slider with p = 0 at h_r and at h_out carries U h_m / 2, h_m
// = 2 h_r h_out / (h_r + h_out) (the film at its peak). So h_r = f h_in h_out / (2 h_out - f h_in), the load
// is the slider's W over L_r = L (h_r - h_out) / (h_in - h_out) with K = h_r / h_out, and the inflow is f U
// h_in / 2 per unit width - while h_r < h_in, i.e. f < 2 h_out / (h_in + h_out) = 2/3. Above it the flooded
// slider cannot take what is offered: the excess goes back out through the inlet (inflow < f x Couette), and
// the load is the flooded one. The reformation is first order in the cell size (section 13): at 200
// cells 1.2e-3 at f = 0.55, 4e-4 at 0.6; the over-supplied inlet (f >= 2/3) 4.6e-3 at f = 0.7 (halving with
// the cell size).
TEST(bearing_skirt, StarvedInletLowersTheLoadAndMetersTheInflow) {
  const int axial = 200, around = 61;
  const double h_in = 20e-6, h_out = 10e-6, U = std::abs(kSpeed);
  SkirtSpec s = slider_skirt(axial, around);
  s.radial_clearance = h_out;
  s.barrel = {{0.005 - kSliderL, 0.005}, {h_in - h_out, 0.0}};
  SkirtKinematics k;
  k.speed = kSpeed;
  SkirtFilm flooded(s);
  const SkirtResult full = flooded.evaluate(k);
  s.cavitation = Cavitation::kNone;
  SkirtFilm none(s);
  const SkirtResult linear = none.evaluate(k);
  // Fill 1 is the flooded film: the same as the full film (p > 0 everywhere), to the Newton tolerance.
  std::printf("flooded (fill 1, JFO) / full film - 1 = %.1e\n", full.side_force / linear.side_force - 1);
  EXPECT_NEAR(full.side_force / linear.side_force, 1.0, 1e-9);
  s.cavitation = Cavitation::kJfo;
  const double couette = 0.5 * U * h_in * kSliderR * 2 * kPi / 3;
  double last = std::abs(full.side_force);
  for (double fill : {0.9, 0.8, 0.7, 0.65, 0.6, 0.55}) {
    s.fill_bottom = fill;
    SkirtFilm starved(s);
    const SkirtResult r = starved.evaluate(k);
    const Eigen::MatrixXd p = starved.pressure(0);
    const double centre = p.col(around / 2).sum() * kSliderL / axial;
    const double h_r = fill * h_in * h_out / (2 * h_out - fill * h_in);
    const bool metered = fill < 2 * h_out / (h_in + h_out);
    const double W = metered ? slider_load(U, kSliderL * (h_r - h_out) / (h_in - h_out), h_r, h_out)
                             : slider_load(U, kSliderL, h_in, h_out);
    const double load = std::abs(r.side_force);
    std::printf(
        "fill %.2f: load %.1f N (%.4f of flooded); centre %.2f N/m, closed form %.2f (%.1e); inflow / "
        "(fill x Couette) - 1 = %.1e\n",
        fill, load, load / std::abs(full.side_force), centre, W, centre / W - 1,
        r.flow_bottom / (fill * couette) - 1);
    EXPECT_LT(load, last);  // monotone
    if (metered) {
      EXPECT_NEAR(r.flow_bottom / (fill * couette), 1.0, 1e-12);
      EXPECT_NEAR(centre / W, 1.0, 3e-3);
    } else {
      EXPECT_LT(r.flow_bottom, fill * couette);
      EXPECT_NEAR(centre / W, 1.0, 1e-2);
    }
    last = load;
  }
}

TEST(bearing_skirt, ConcentricSlidingFrictionAgainstPetroff) {
  // e = 0, no profile: a uniform film, no pressure; tau = -mu V / h on the piston. Full circle: F = -2 pi R L
  // mu V / c, power mu V^2 2 pi R L / c, no moment; one +-60 deg panel: the moment R int tau cos(theta) dA
  // with the midpoint rule's sum of cos (exact for the discrete film; against the integral 2 sin(60 deg)
  // within 3e-4).
  const double R = 0.045, L = 0.04, V = 12.0;
  SkirtSpec s = full_circle(R, L, 20, 36);
  s.cavitation = Cavitation::kJfo;
  SkirtFilm film(s);
  SkirtKinematics k;
  k.speed = V;
  const SkirtResult r = film.evaluate(k);
  const double F = -2 * kPi * R * L * kMu * V / kC;
  EXPECT_NEAR(r.friction_force / F, 1.0, 1e-12);
  EXPECT_NEAR(r.power_loss / (-F * V), 1.0, 1e-12);
  EXPECT_LT(std::abs(r.side_force), 1e-12 * std::abs(F));
  EXPECT_LT(std::abs(r.moment), 1e-12 * std::abs(F) * R);
  s.arcs = {{-kPi / 3, kPi / 3}};
  SkirtFilm panel(s);
  const SkirtResult q = panel.evaluate(k);
  const double M = R * (-kMu * V / kC) * R * L * 2 * std::sin(kPi / 3);
  std::printf("Petroff: full circle F / F_ref - 1 = %.1e; panel moment / M_ref - 1 = %.1e\n",
              r.friction_force / F - 1, q.moment / M - 1);
  EXPECT_NEAR(q.moment / M, 1.0, 1e-3);
  EXPECT_NEAR(q.friction_force / (F / 3), 1.0, 1e-12);
}

TEST(bearing_skirt, WarmStartGivesTheColdSolution) {
  // The warm start (the last solution, rescaled) is a starting guess only: after a sequence of states with
  // the sliding reversed and the film cavitated, the same state solved cold gives the same film.
  SkirtSpec s;
  s.bore_radius = 0.045;
  s.radial_clearance = kC;
  s.skirt_length = 0.04;
  s.skirt_top = 0.012;
  s.viscosity = kMu;
  s.fill_bottom = 0.7;
  s.cells_axial = 30;
  s.cells_around = 24;
  SkirtFilm warm(s);
  SkirtKinematics k;
  for (int step = 0; step < 6; ++step) {
    k.e_top = (0.5 - 0.1 * step) * kC, k.e_bottom = (-0.4 + 0.15 * step) * kC;
    k.e_top_dot = 0.02 * (step - 2), k.e_bottom_dot = -0.01;
    k.speed = 9 - 3.5 * step;
    warm.evaluate(k);
  }
  const SkirtResult a = warm.evaluate(k);
  SkirtFilm cold(s);
  const SkirtResult b = cold.evaluate(k);
  const double scale = warm.pressure(0).cwiseAbs().maxCoeff() + warm.pressure(1).cwiseAbs().maxCoeff();
  const double dp = std::max((warm.pressure(0) - cold.pressure(0)).cwiseAbs().maxCoeff(),
                             (warm.pressure(1) - cold.pressure(1)).cwiseAbs().maxCoeff());
  std::printf("warm against cold: max |dp| / p_max = %.1e, side force %.1e\n", dp / scale,
              a.side_force / b.side_force - 1);
  EXPECT_LT(dp, 1e-8 * scale);
  EXPECT_NEAR(a.side_force / b.side_force, 1.0, 1e-8);
  EXPECT_NEAR(a.moment / b.moment, 1.0, 1e-8);
}

TEST(bearing_skirt, BadInputNamesTheField) {
  auto message = [](const std::function<void(SkirtSpec&)>& change) {
    SkirtSpec s = full_circle(0.045, 0.04, 10, 12);
    change(s);
    try {
      SkirtFilm film(s);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message([](SkirtSpec& s) { s.radial_clearance = 0; }).find("'radial_clearance'"),
            std::string::npos);
  EXPECT_NE(message([](SkirtSpec& s) { s.fill_top = 1.5; }).find("'fill_top'"), std::string::npos);
  EXPECT_NE(message([](SkirtSpec& s) { s.arcs = {{0, 1}, {0.5, 2}}; }).find("overlap"), std::string::npos);
  EXPECT_NE(message([](SkirtSpec& s) {
              s.arcs = {{0, 2 * kPi}, {0.5, 2}};
            }).find("full circle"),
            std::string::npos);
  EXPECT_NE(message([](SkirtSpec& s) {
              s.barrel = {{0.0, -0.01}, {0.0, 1e-6}};
            }).find("'barrel.at'"),
            std::string::npos);
  EXPECT_NE(message([](SkirtSpec& s) {
              s.ovality = {{0.0, 7.0}, {0.0, 1e-6}};
            }).find("'ovality.at'"),
            std::string::npos);
  EXPECT_NE(message([](SkirtSpec& s) { s.cells_around = 2; }).find("'cells_around'"), std::string::npos);
  // Contact: the film closes.
  SkirtFilm film(full_circle(0.045, 0.04, 10, 12));
  SkirtKinematics k;
  k.e_top = 1.1 * kC;
  EXPECT_THROW(film.evaluate(k), Error);
}

}  // namespace
}  // namespace nvh::bearing
