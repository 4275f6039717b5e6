// Asperity contact (solve/bearing/asperity_contact.hpp) and the skirt film's transition from a full film to
// hard contact (the film floor of skirt_film.hpp), against references not computed with this code.
//
// Greenwood-Tripp with the fit of Hu et al. (Tribol. Trans. 37 (1994) 445; Arcoumanis et al., SAE 970630,
// eq. 10): F_5/2(H) = 4.4086e-5 (4 - H)^6.804, H < 4. The reference values below are worked by hand from that
// closed form (s = 4 - H):
//   H = 3: s = 1, F = 4.4086e-5, dF/dH = -6.804 * 4.4086e-5 = -2.99961144e-4
//   H = 2: s^6.804 = exp(6.804 ln 2) = 111.7403, F = 4.92616e-3, dF/dH = -6.804 * 4.4086e-5 * 2^5.804
//          = -1.675881e-2
//   H = 0: s^6.804 = exp(6.804 ln 4) = 12485.7, F = 0.550449, dF/dH = -6.804 * 4.4086e-5 * 4^5.804 =
//   -0.936313 H = -1: s^6.804 = exp(6.804 ln 5) = 56990.0, F = 2.512422, dF/dH = -3.418904
// and the energy per area u = K E' sigma 4.4086e-5 s^7.804 / 7.804 (H = 2: 1.262471e-3 K E' sigma). The
// roughness constant K = (16 sqrt(2) pi / 15) (sigma beta eta)^2 sqrt(sigma / beta) (Greenwood and Tripp
// 1970, eq. 12): sigma beta eta = 0.04, sigma / beta = 1e-3 gives 4.7394 * 1.6e-3 * 0.0316228 = 2.39780e-4.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "common/error.hpp"
#include "solve/bearing/asperity_contact.hpp"
#include "solve/bearing/skirt_film.hpp"

namespace nvh::bearing {
namespace {

TEST(AsperityContact, F52AgainstHandValues) {
  struct Row {
    double H, F, dF;
  };
  // relative tolerance 1e-6: the hand values carry 7 significant digits
  for (const Row& r : {Row{3.0, 4.4086e-5, -2.99961144e-4}, Row{2.0, 4.92616e-3, -1.675881e-2},
                       Row{0.0, 0.550449, -0.936313}, Row{-1.0, 2.512422, -3.418904}}) {
    const F52 f = f52(r.H);
    EXPECT_NEAR(f.value, r.F, 1e-6 * std::abs(r.F)) << "H = " << r.H;
    EXPECT_NEAR(f.derivative, r.dF, 1e-6 * std::abs(r.dF)) << "H = " << r.H;
  }
  EXPECT_EQ(f52(4.0).value, 0.0);
  EXPECT_EQ(f52(4.0).derivative, 0.0);
  EXPECT_EQ(f52(7.5).value, 0.0);
}

TEST(AsperityContact, PressureDerivativeAndEnergy) {
  GreenwoodTripp law;
  law.sigma = 0.8e-6;
  law.K = roughness_constant(0.04, 1e-3);
  law.modulus = 1.1e11;
  EXPECT_NEAR(law.K, 2.39780e-4, 1e-5 * 2.39780e-4);  // hand value above
  const double ke = law.K * law.modulus;
  // H = 2: p = K E' F, dp/dh = K E' F' / sigma, u = 1.262471e-3 K E' sigma (hand values, 1e-6)
  const AsperityPressure a = asperity_pressure(law, 2 * law.sigma);
  EXPECT_NEAR(a.p, ke * 4.92616e-3, 1e-6 * ke * 4.92616e-3);
  EXPECT_NEAR(a.dp_dh, ke * -1.675881e-2 / law.sigma, 1e-6 * ke * 1.675881e-2 / law.sigma);
  EXPECT_NEAR(a.energy, 1.262471e-3 * ke * law.sigma, 1e-6 * 1.262471e-3 * ke * law.sigma);
  // dp/dh and p = -du/dh against central differences (step 1e-5 sigma: relative truncation < 1e-8) from no
  // contact through h = 0 to h = -2 sigma
  double previous = -1;
  for (double H = 4.5; H >= -2.0; H -= 0.0625) {
    const double h = H * law.sigma, step = 1e-5 * law.sigma;
    const AsperityPressure c = asperity_pressure(law, h), hi = asperity_pressure(law, h + step),
                           lo = asperity_pressure(law, h - step);
    const double scale = ke * 1e-6;  // against the largest values (ke * O(1)) of the range
    EXPECT_NEAR(c.dp_dh, (hi.p - lo.p) / (2 * step), 1e-6 * (std::abs(c.dp_dh) + scale / law.sigma))
        << "H = " << H;
    EXPECT_NEAR(c.p, -(hi.energy - lo.energy) / (2 * step), 1e-6 * (c.p + scale)) << "H = " << H;
    // monotone: the pressure grows as the gap closes, strictly once in contact
    if (H < 4) {
      EXPECT_GT(c.p, previous) << "H = " << H;
    }
    EXPECT_GE(c.p, 0.0);
    previous = c.p;
  }
  EXPECT_EQ(asperity_pressure(GreenwoodTripp{}, -1e-6).p, 0.0);  // inactive law
}

TEST(FilmFloor, EffectiveFilmIsSmoothMonotoneAndTendsToTheFilm) {
  const double hf = 1e-6;
  double previous = 0;
  for (double h = -20e-6; h <= 30e-6; h += 0.05e-6) {
    const EffectiveFilm e = effective_film(h, hf);
    EXPECT_GT(e.h, hf) << h;  // the floor
    EXPECT_GT(e.h, previous) << h;
    EXPECT_GT(e.dh, 0.0);
    EXPECT_LT(e.dh, 1.0 + 1e-15);
    EXPECT_GE(e.h, h);
    const double step = 1e-4 * hf;
    EXPECT_NEAR(e.dh, (effective_film(h + step, hf).h - effective_film(h - step, hf).h) / (2 * step), 1e-7)
        << h;
    previous = e.h;
  }
  // h_eff - h = h_f ln(1 + exp(-(h - h_f) / h_f)): at h = 3 h_f, ln(1 + e^-2) = 0.126928 h_f; at 10
  // h_f 1.2340e-4
  EXPECT_NEAR(effective_film(3 * hf, hf).h - 3 * hf, 0.126928 * hf, 1e-6 * hf);
  EXPECT_NEAR(effective_film(10 * hf, hf).h - 10 * hf, 1.2340e-4 * hf, 1e-7 * hf);
  EXPECT_EQ(effective_film(-3.0, 0.0).h, -3.0);  // no floor: the film itself
}

// The skirt from full film to hard contact: the piston translated towards the thrust side (e_top = e_bottom =
// e) at a constant small squeeze speed, V = 0, from e = 0 to e = c + 2 um (the nominal film < 0 over a band
// of the skirt): the side force on the piston (negative: pushed back) grows in magnitude monotonically, and
// no step of the sweep jumps: each increment of |F| within a factor 2 of the previous one (the curve's own
// growth per step of c / 400 stays below 1.4; a switch between laws would show as a jump).
struct Sweep {
  std::vector<double> e, force, asperity;
};
Sweep sweep(SkirtSpec s, double tilt_top = 0.0) {
  SkirtFilm film(s);
  Sweep out;
  const double c = s.radial_clearance;
  for (int k = 0; k <= 432; ++k) {
    const double e = k * c / 400;
    SkirtKinematics kin;
    kin.e_bottom = e;
    kin.e_top = e + tilt_top;
    kin.e_bottom_dot = kin.e_top_dot = 1e-4;  // m/s, closing the thrust side
    const SkirtResult r = film.evaluate(kin);
    out.e.push_back(e);
    out.force.push_back(-r.side_force);
    out.asperity.push_back(-r.asperity_side_force);
  }
  return out;
}

void expect_monotone_without_jumps(const Sweep& w, const char* what) {
  double worst_ratio = 0;
  for (std::size_t k = 1; k < w.force.size(); ++k) {
    const double d = w.force[k] - w.force[k - 1];
    EXPECT_GT(d, 0.0) << what << ": e = " << w.e[k];
    if (k >= 2) {
      const double ratio = d / (w.force[k - 1] - w.force[k - 2]);
      worst_ratio = std::max(worst_ratio, ratio);
      EXPECT_LT(ratio, 2.0) << what << ": a jump at e = " << w.e[k];
    }
  }
  for (std::size_t k = 1; k < w.asperity.size(); ++k)
    EXPECT_GE(w.asperity[k], w.asperity[k - 1]) << what << ": asperity force, e = " << w.e[k];
  EXPECT_GT(w.asperity.back(), 0.0) << what << ": the asperities take part in the hard contact";
  EXPECT_EQ(w.asperity.front(), 0.0) << what << ": no asperity contact at the centre";
  std::printf(
      "measured: %s: |F| from %.4g N (centred) to %.4g N (e = c + 2 um), asperities %.4g N; largest "
      "ratio of successive increments %.3f (tolerance 2)\n",
      what, w.force.front(), w.force.back(), w.asperity.back(), worst_ratio);
}

SkirtSpec piston_skirt() {
  SkirtSpec s;
  s.bore_radius = 0.04;
  s.radial_clearance = 30e-6;
  s.skirt_length = 0.05;
  s.skirt_top = 0.02;
  s.viscosity = 0.01;
  s.cells_axial = 24;
  s.cells_around = 16;
  s.film_floor = 0.5e-6;
  s.asperity.sigma = 1e-6;
  s.asperity.K = roughness_constant(0.04, 1e-3);
  s.asperity.modulus = 1.1e11;
  return s;
}

TEST(FilmFloor, SideForceContinuousAndMonotoneFromFullFilmToHardContact) {
  SkirtSpec s = piston_skirt();
  expect_monotone_without_jumps(sweep(s), "thrust panels, JFO, straight skirt");
  s.barrel = {{-0.03, -0.005, 0.02}, {12e-6, 0.0, 18e-6}};  // a barrel: crown at 5 mm below the pin
  expect_monotone_without_jumps(sweep(s), "thrust panels, JFO, barrel");
  s.arcs = {{-std::numbers::pi, std::numbers::pi}};
  s.cavitation = Cavitation::kNone;
  expect_monotone_without_jumps(sweep(s, 3e-6), "full circle, full film, barrel, tilted 3 um");
}

TEST(FilmFloor, OffByDefaultAndContactIsThenAnError) {
  SkirtSpec s = piston_skirt();
  s.film_floor = 0;
  SkirtFilm film(s);
  SkirtKinematics k;
  k.e_top = k.e_bottom = 31e-6;
  EXPECT_THROW(film.evaluate(k), Error);
  s.film_floor = 40e-6;  // not below the clearance
  EXPECT_THROW(SkirtFilm{s}, Error);
}

}  // namespace
}  // namespace nvh::bearing
