// solve --advise (solve/advise.hpp, linearize.hpp, stability.hpp) against references computed without it:
//   1. the linearised modes of a free two-mass spring: omega = sqrt(k (m1 + m2) / (m1 m2)), kinetic energy
//      shares m2 / (m1 + m2) and m1 / (m1 + m2), all the elastic energy in the spring;
//   2. the BDF stability theory against Hairer & Wanner's published figures: the undamped unstable bands
//      (BDF3 0..1.94, BDF4 0..4.71, BDF5 0.71..9.39, docs/verification.md) and the A(alpha) angles 86.03,
//      73.35, 51.84 deg; generalized-alpha's radius rho_inf at infinite step and BDF2's roots at rho_inf = 0;
//   3. the warnings: a mode at omega h inside BDF3's band for the scene's max_step warns, outside it does
//   not;
//      a step above the band's resolution; rho_inf = 1 with joint reactions; contacts -> generalized-alpha;
//   4. the recommended step resolves the band by the stated rule (20 steps per period of its top frequency);
//   5. a flexible body: the reported modes are the superelement's stored ones (read by common's reader), a
//   free
//      floating body's linearised frequencies equal them, and a clamped beam's first frequency is the
//      Euler-Bernoulli cantilever's (1.8751^2 / (2 pi L^2)) sqrt(E I / (rho A));
//   6. the split: its coupling mode's omega_c = sqrt(k (m1 + m2) / (m1 m2)) times macro_step against the
//      stability map's limit of 1 without the coupling correction.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <string>

#include "common/superelement.hpp"
#include "condense/component_reader.hpp"
#include "condense/condense.hpp"
#include "solve/advise.hpp"
#include "solve/stability.hpp"
#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;

const Logger& quiet() {
  static std::ostringstream sink;
  static const Logger log(sink, "solve", Verbosity::kQuiet);
  return log;
}

/// Two point masses on the x axis joined by a spring-damper (free-free), with an [integrator] table.
std::string two_masses(double m1, double m2, double k, double d, const std::string& integrator,
                       double sample_rate = 1000) {
  std::ostringstream s;
  s << std::setprecision(17) << "[scene]\nname = \"two-masses\"\n"
    << "[[body]]\nname = \"ground\"\ntype = \"ground\"\n"
    << "[[body]]\nname = \"m1\"\ntype = \"point-mass\"\nmass = " << m1
    << "\nposition = [0, 0, 0]\n  [[body.marker]]\n  name = \"c\"\n"
    << "[[body]]\nname = \"m2\"\ntype = \"point-mass\"\nmass = " << m2
    << "\nposition = [0.1, 0, 0]\n  [[body.marker]]\n  name = \"c\"\n"
    << "[[force]]\nname = \"coupling\"\ntype = \"spring-damper\"\ni = \"m2.c\"\nj = \"m1.c\"\nk = " << k
    << "\nd = " << d << "\n[clock]\nend_time = 0.1\n"
    << integrator << "[output]\nsample_rate_hz = " << sample_rate << "\n";
  return s.str();
}

Advice advice_of(const std::string& text, AdviceOptions options = {}, const fs::path& base = ".") {
  Scene scene = parse_scene(text, "advise.toml", base);
  return advise(scene, options, quiet());
}

bool any_contains(const std::vector<std::string>& lines, const std::string& what) {
  for (const auto& l : lines)
    if (l.find(what) != std::string::npos) return true;
  return false;
}

TEST(Advise, TwoMassSpringModeAgainstClosedForm) {
  const double m1 = 1.0, m2 = 3.0, k = 4e6;
  const Advice a = advice_of(two_masses(m1, m2, k, 0.0, "[integrator]\nmethod = \"ida\"\n"));
  // Point masses in 3D: the spring's transverse directions are free (zero eigenvalues, dropped).
  ASSERT_EQ(a.linear.modes.size(), 1u);
  const LinearMode& mode = a.linear.modes[0];
  EXPECT_NEAR(mode.omega / std::sqrt(k * (m1 + m2) / (m1 * m2)), 1.0, 1e-6);
  EXPECT_NEAR(mode.damping_ratio, 0.0, 1e-9);
  // Momentum is conserved: v1 / v2 = -m2 / m1, so m1's kinetic share is m2 / (m1 + m2).
  ASSERT_EQ(mode.kinetic.size(), 2u);
  EXPECT_EQ(mode.kinetic[0].first, "m1");
  EXPECT_NEAR(mode.kinetic[0].second, m2 / (m1 + m2), 1e-6);
  EXPECT_NEAR(mode.kinetic[1].second, m1 / (m1 + m2), 1e-6);
  ASSERT_EQ(mode.elastic.size(), 1u);
  EXPECT_EQ(mode.elastic[0].first, "coupling");
  EXPECT_NEAR(mode.elastic[0].second, 1.0, 1e-6);
}

TEST(Advise, DampingRatioAgainstClosedForm) {
  // zeta = d / (2 sqrt(k m_r)), m_r = m1 m2 / (m1 + m2): the relative motion's reduced mass.
  const double m1 = 2.0, m2 = 0.5, k = 1e5, d = 40;
  const Advice a = advice_of(two_masses(m1, m2, k, d, ""));
  ASSERT_EQ(a.linear.modes.size(), 1u);
  const double mr = m1 * m2 / (m1 + m2);
  EXPECT_NEAR(a.linear.modes[0].omega / std::sqrt(k / mr), 1.0, 1e-6);
  EXPECT_NEAR(a.linear.modes[0].damping_ratio / (d / (2 * std::sqrt(k * mr))), 1.0, 1e-6);
}

TEST(Advise, BdfBandsAgainstHairerWanner) {
  // Undamped modes (docs/verification.md "Stability map", theory; Hairer & Wanner II, sec. V.2).
  const auto b3 = bdf_unstable_band(3, 0.0), b4 = bdf_unstable_band(4, 0.0), b5 = bdf_unstable_band(5, 0.0);
  ASSERT_TRUE(b3 && b4 && b5);
  EXPECT_EQ(b3->first, 0.0);
  EXPECT_NEAR(b3->second, 1.94, 0.01);
  EXPECT_LT(b4->first, 0.02);  // BDF4 grows by O((omega h)^5) per step: below 1e-12 under 0.012
  EXPECT_NEAR(b4->second, 4.71, 0.01);
  EXPECT_NEAR(b5->first, 0.71, 0.01);
  EXPECT_NEAR(b5->second, 9.39, 0.01);
  EXPECT_FALSE(bdf_unstable_band(1, 0.0));
  EXPECT_FALSE(bdf_unstable_band(2, 0.0));
  // A(alpha): stable at every step just above cos(alpha), a band just below.
  const double alpha_deg[] = {86.03, 73.35, 51.84};
  for (int k = 3; k <= 5; ++k) {
    const double c = std::cos(alpha_deg[k - 3] * kPi / 180);
    EXPECT_NEAR(bdf_critical_damping(k), c, 1e-12);
    EXPECT_FALSE(bdf_unstable_band(k, c + 2e-3)) << "BDF" << k;
    EXPECT_TRUE(bdf_unstable_band(k, c - 2e-3)) << "BDF" << k;
  }
  // BDF3 at small omega h grows by (omega h)^4 / 4 per step (leading term).
  EXPECT_NEAR((bdf_growth(3, mode_z(1, 0, 0.05)) - 1) / (std::pow(0.05, 4) / 4), 1.0, 0.02);
}

TEST(Advise, GeneralizedAlphaRadius) {
  // At infinite step both roots meet at -rho_inf (a double root: at finite z they differ by O(z^-1/2)).
  for (double rho : {0.0, 0.5, 0.8, 1.0})
    EXPECT_NEAR(generalized_alpha_growth(rho, mode_z(1, 0, 1e14)), rho, 1e-6);
  // rho_inf = 0 has BDF2's roots (docs/verification.md), damped and undamped.
  for (double zeta : {0.0, 0.1})
    for (double wh : {0.3, 3.0})
      EXPECT_NEAR(generalized_alpha_growth(0.0, mode_z(1, zeta, wh)), bdf_growth(2, mode_z(1, zeta, wh)),
                  1e-12);
}

TEST(Advise, BdfBandWarningForTheScenesMaxStep) {
  const double m1 = 1.0, m2 = 1.0, k = 1e6, omega = std::sqrt(k * (m1 + m2) / (m1 * m2));
  const auto warns = [&](double omega_h) {
    const std::string integrator =
        "[integrator]\nmethod = \"ida\"\nmax_order = 3\nmax_step = " + testing::num(omega_h / omega) + "\n";
    const Advice a = advice_of(two_masses(m1, m2, k, 0.0, integrator, 1e6));
    return any_contains(a.warnings, "BDF3's unstable band");
  };
  EXPECT_TRUE(warns(1.0));  // inside 0 .. 1.94
  EXPECT_TRUE(warns(1.8));
  EXPECT_FALSE(warns(2.5));  // above the band
  // max_order 2 is A-stable: no warning at any step
  const Advice a2 = advice_of(two_masses(
      m1, m2, k, 0.0, "[integrator]\nmax_order = 2\nmax_step = " + testing::num(1.0 / omega) + "\n", 1e6));
  EXPECT_FALSE(any_contains(a2.warnings, "unstable band"));
  // damped above cos(alpha_3) = 0.0698: no band (zeta = d / (2 sqrt(k m_r)), m_r = 0.5 kg)
  const double d = 2 * 0.08 * std::sqrt(k * 0.5);
  const Advice a3 = advice_of(two_masses(
      m1, m2, k, d, "[integrator]\nmax_order = 3\nmax_step = " + testing::num(1.0 / omega) + "\n", 1e6));
  EXPECT_FALSE(any_contains(a3.warnings, "unstable band"));
}

// The split (method = "split"): the two free masses are two groups (no joint between them), and their one
// mode, omega = sqrt(k (m1 + m2) / (m1 m2)), moves both. Without the coupling correction the exchange
// diverges above omega_c H of about 1 (the split's stability map, verification.md): a warning there, none
// below it, none with the correction; and no generalized-alpha step warnings for a split scene (its groups
// run IDA).
TEST(Advise, SplitWarnsOfAnUncorrectedCouplingAboveOmegaH1) {
  const double m1 = 1.0, m2 = 1.0, k = 1e6, omega = std::sqrt(k * (m1 + m2) / (m1 * m2));
  const auto advice = [&](double omega_h, bool correction) {
    const std::string integrator =
        "[integrator]\nmethod = \"split\"\nmacro_step = " + testing::num(omega_h / omega) +
        "\ncoupling_correction = " + (correction ? "true" : "false") + "\n";
    return advice_of(two_masses(m1, m2, k, 0.0, integrator, 1e3));
  };
  const Advice above = advice(2.0, false);
  EXPECT_TRUE(any_contains(above.warnings, "split without the coupling correction"));
  EXPECT_TRUE(any_contains(above.warnings, "omega_c H = 2"));
  EXPECT_TRUE(any_contains(above.warnings, "macro_step <= 0.0007071 s"));  // 1 / omega, 4 digits
  EXPECT_FALSE(any_contains(above.warnings, "generalized-alpha"));
  EXPECT_FALSE(any_contains(above.notes, "generalized-alpha"));
  const Advice below = advice(0.5, false);
  EXPECT_FALSE(any_contains(below.warnings, "coupling correction"));
  EXPECT_TRUE(any_contains(below.notes, "omega_c H = 0.5"));
  const Advice corrected = advice(2.0, true);
  EXPECT_FALSE(any_contains(corrected.warnings, "coupling correction"));
  EXPECT_TRUE(any_contains(corrected.notes, "tested to omega_c H = 14"));
}

TEST(Advise, StepResolvesTheBand) {
  // Band from the output rate: Nyquist; 20 steps per period of the band's top.
  const Advice a = advice_of(two_masses(1, 1, 1e4, 1, "", 4000));
  EXPECT_EQ(a.band_source, "output.sample_rate_hz / 2");
  EXPECT_DOUBLE_EQ(a.band_hz, 2000);
  EXPECT_DOUBLE_EQ(a.step, 1.0 / (20 * 2000));
  EXPECT_EQ(a.method, "ida");  // no contacts
  // An explicit band; a scene's max_step above the band's resolution is a warning, one below is not.
  AdviceOptions o;
  o.band_hz = 500;
  const Advice b = advice_of(two_masses(1, 1, 1e4, 1, "[integrator]\nmax_step = 2e-4\n", 4000), o);
  EXPECT_EQ(b.band_source, "--band");
  EXPECT_DOUBLE_EQ(b.step, 1.0 / (20 * 500));
  EXPECT_TRUE(any_contains(b.warnings, "above the band's resolution"));
  const Advice c = advice_of(two_masses(1, 1, 1e4, 1, "[integrator]\nmax_step = 5e-5\n", 4000), o);
  EXPECT_FALSE(any_contains(c.warnings, "above the band's resolution"));
  // A band above the output's Nyquist frequency cannot be shown by the samples.
  o.band_hz = 3000;
  EXPECT_TRUE(any_contains(advice_of(two_masses(1, 1, 1e4, 1, "", 4000), o).warnings, "Nyquist"));
}

TEST(Advise, ContactsAndReactions) {
  // A ball resting on a closed contact: generalized-alpha recommended.
  const std::string ball =
      "[[body]]\nname = \"ground\"\ntype = \"ground\"\n  [[body.marker]]\n  name = \"floor\"\n"
      "[[body]]\nname = \"ball\"\ntype = \"point-mass\"\nmass = 1\nposition = [0, 0, -1e-4]\n"
      "  [[body.marker]]\n  name = \"c\"\n"
      "[[force]]\nname = \"floor\"\ntype = \"contact\"\ni = \"ball.c\"\nj = \"ground.floor\"\nstiffness = "
      "1e7\n"
      "exponent = 1\n[clock]\nend_time = 0.1\n[output]\nsample_rate_hz = 1000\n";
  EXPECT_EQ(advice_of(ball).method, "generalized-alpha");
  // rho_inf = 1 with joints and reactions written: warned; rho_inf = 0.8: not.
  const auto with = [&](const std::string& rho) {
    const std::string text = testing::shipped_scene(
        "scenes/slider_crank.toml", {{"[integrator]\nmethod = \"ida\"",
                                      "[integrator]\nmethod = \"generalized-alpha\"\nrho_inf = " + rho}});
    return advice_of(text, {}, fs::path(NVH_SOURCE_DIR) / "testdata" / "scenes");
  };
  EXPECT_TRUE(any_contains(with("1").warnings, "rho_inf = 1"));
  EXPECT_FALSE(any_contains(with("0.8").warnings, "rho_inf = 1"));
}

/// testdata/scenes/flexible_beam.toml condensed into a temporary folder (its Craig-Bampton superelement).
fs::path condensed_beam() {
  const fs::path file = testing::temp_path("advise_beam.h5");
  if (!fs::exists(file)) {
    const condense::Component c =
        condense::read_component(fs::path(NVH_SOURCE_DIR) / "testdata" / "scenes" / "flexible_beam.toml");
    const condense::Superelement se =
        condense::condense_component(c, condense::EigenBackend::kBlockLanczos, quiet());
    condense::write_superelement(file, se, make_provenance("test", 0, nullptr, {}));
  }
  return file;
}

TEST(Advise, FlexibleBodyModesAreTheSuperelementsStoredOnes) {
  const fs::path beam = condensed_beam();
  const SuperelementFile se = read_superelement(beam);  // common's reader, not solve's
  const Eigen::VectorXd stored = se.frequency_hz;
  ASSERT_GT(stored.size(), 3);
  // A free floating body (no joints, no spin): its linearised elastic modes are the file's free-free modes.
  const std::string free_beam =
      "[scene]\nname = \"free-beam\"\n[[body]]\nname = \"ground\"\ntype = \"ground\"\n"
      "[[body]]\nname = \"beam\"\ntype = \"flexible\"\nsuperelement = \"advise_beam.h5\"\n"
      "[clock]\nend_time = 0.01\n[output]\nsample_rate_hz = 2000\n";
  const Advice a = advice_of(free_beam, {}, beam.parent_path());
  ASSERT_EQ(a.flexible.size(), 1u);
  EXPECT_EQ(a.flexible[0].modes_in_file, stored.size());
  EXPECT_NEAR(a.flexible[0].highest_in_file_hz / stored.maxCoeff(), 1.0, 1e-12);
  ASSERT_EQ(static_cast<Eigen::Index>(a.linear.modes.size()), stored.size());
  for (Eigen::Index i = 0; i < stored.size(); ++i)
    EXPECT_NEAR(a.linear.modes[static_cast<std::size_t>(i)].frequency_hz() / stored[i], 1.0, 1e-6) << i;
  // Mode counts: the file's modes up to 2 x the band (here 1 kHz, cut-off 2 kHz).
  const Eigen::Index needed = (stored.array() <= 2000.0).count();
  EXPECT_EQ(a.flexible[0].modes_needed, std::max<Eigen::Index>(1, needed));
}

// `mode_numbers`: a choice that leaves out modes below the cut-off is named in a warning (which ones), and
// the count advice does not ask for `modes = N` instead; a choice of every mode below the cut-off is not
// warned of.
TEST(Advise, ChosenModeNumbersNameTheModesLeftOut) {
  const fs::path beam = condensed_beam();
  const Eigen::VectorXd stored = read_superelement(beam).frequency_hz;
  const Eigen::Index needed = (stored.array() <= 2000.0).count();  // the band 1 kHz, cut-off 2 kHz
  ASSERT_GE(needed, 2);
  auto scene = [](const std::string& numbers) {
    return "[scene]\nname = \"free-beam\"\n[[body]]\nname = \"ground\"\ntype = \"ground\"\n"
           "[[body]]\nname = \"beam\"\ntype = \"flexible\"\nsuperelement = \"advise_beam.h5\"\nmode_numbers "
           "= [" +
           numbers + "]\n[clock]\nend_time = 0.01\n[output]\nsample_rate_hz = 2000\n";
  };
  const Advice a = advice_of(scene("2"), {}, beam.parent_path());
  ASSERT_EQ(a.flexible.size(), 1u);
  EXPECT_EQ(a.flexible[0].modes_used, 1);
  EXPECT_TRUE(any_contains(a.warnings, "leaves out its modes 1"))
      << (a.warnings.empty() ? "" : a.warnings[0]);
  EXPECT_FALSE(any_contains(a.warnings, "modes = "));
  std::string all;
  for (Eigen::Index j = 1; j <= needed; ++j) all += (j > 1 ? ", " : "") + std::to_string(j);
  const Advice b = advice_of(scene(all), {}, beam.parent_path());
  EXPECT_FALSE(any_contains(b.warnings, "leaves out"));
}

// A superelement whose basis holds static correction (testdata/scenes/flexible_beam.toml reduced modal, 4
// modes, with the residual modes of its two interfaces): the file says how many (/reduced static_correction);
// a scene that takes fewer coordinates than the file has gets a warning naming the body, the file and the
// key, and the advice asks for all of them; a scene that takes them all gets none.
TEST(Advise, TruncatingAStaticallyCorrectedSuperelementIsWarned) {
  const fs::path file = testing::temp_path("advise_beam_residual.h5");
  {
    condense::Component c =
        condense::read_component(fs::path(NVH_SOURCE_DIR) / "testdata" / "scenes" / "flexible_beam.toml");
    c.reduction.method = condense::ReductionMethod::kModal;
    c.reduction.modes = 4;
    c.reduction.residual_modes = true;
    c.reduction.residual_modes_given = true;
    condense::write_superelement(
        file, condense::condense_component(c, condense::EigenBackend::kBlockLanczos, quiet()),
        make_provenance("test", 0, nullptr, {}));
  }
  const SuperelementFile se = read_superelement(file);
  ASSERT_GT(se.static_correction, 0);
  EXPECT_EQ(se.size(), 4 + se.static_correction);
  auto scene = [](const std::string& modes) {
    return "[scene]\nname = \"free-beam\"\n[[body]]\nname = \"ground\"\ntype = \"ground\"\n"
           "[[body]]\nname = \"beam\"\ntype = \"flexible\"\nsuperelement = \"advise_beam_residual.h5\"\n" +
           modes + "[clock]\nend_time = 0.01\n[output]\nsample_rate_hz = 2000\n";
  };
  const Scene truncated = parse_scene(scene("modes = 4\n"), "truncated.toml", file.parent_path());
  ASSERT_EQ(truncated.warnings.size(), 1u);
  EXPECT_NE(truncated.warnings[0].find("truncated.toml:"), std::string::npos) << truncated.warnings[0];
  EXPECT_NE(truncated.warnings[0].find("'beam' uses 4 of the " + std::to_string(se.size())),
            std::string::npos)
      << truncated.warnings[0];
  const Advice a = advice_of(scene("modes = 4\n"), {}, file.parent_path());
  EXPECT_TRUE(any_contains(a.warnings, "static-correction"));
  ASSERT_EQ(a.flexible.size(), 1u);
  EXPECT_EQ(a.flexible[0].modes_needed, se.size());
  const Scene whole = parse_scene(scene(""), "whole.toml", file.parent_path());
  EXPECT_TRUE(whole.warnings.empty());
  std::printf("measured: %d static-correction vectors in %d coordinates; the warning: %s\n",
              se.static_correction, se.size(), truncated.warnings[0].c_str());
}

TEST(Advise, ClampedBeamFirstModeIsEulerBernoulli) {
  const fs::path beam = condensed_beam();
  std::string text =
      testing::shipped_scene("scenes/flexible_cantilever.toml",
                             {{"superelement = \"flexible_beam.h5\"", "superelement = \"advise_beam.h5\""}});
  const Advice a = advice_of(text, {}, beam.parent_path());
  ASSERT_GE(a.linear.modes.size(), 2u);
  // Steel bar L = 1 m, d = 20 mm (flexible_beam.toml): f1 = (1.8751^2 / (2 pi L^2)) sqrt(E I / (rho A)),
  // I / A = d^2 / 16; two equal bending planes.
  const double e = 210e9, rho = 7850, d = 0.02, length = 1.0;
  const double f1 = 1.87510407 * 1.87510407 / (2 * kPi * length * length) * std::sqrt(e * d * d / 16 / rho);
  EXPECT_NEAR(a.linear.modes[0].frequency_hz() / f1, 1.0, 1e-3);
  EXPECT_NEAR(a.linear.modes[1].frequency_hz() / f1, 1.0, 1e-3);
  EXPECT_EQ(a.linear.modes[0].elastic.at(0).first, "beam (elastic)");
}

}  // namespace
}  // namespace nvh::solve
