// Reductions against the unreduced model and against closed-form results.
//
// - The unreduced reference: the full model's eigenproblem solved densely by Eigen's
//   GeneralizedSelfAdjointEigenSolver (a different solver from the Lanczos path condense uses).
// - Guyan's known error: condensing a cantilever onto its tip (v, theta) gives exactly the one-element
//   cubic-Hermite model, because the static deflection under tip loads is cubic; its frequencies are the
//   roots of det(K1 - w^2 M1) = 0 with K1 = EI/L^3 [12 -6L; -6L 4L^2], M1 = rho A L/420 [156 -22L; -22L
//   4L^2]: w = 3.5327 and 34.807 sqrt(EI / (rho A L^4)) (e.g. Petyt, Introduction to Finite Element Vibration
//   Analysis, 2nd ed. 2010, Table 3.2), against the exact 3.5160 and 22.034.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "beam_fixtures.hpp"
#include "common/log.hpp"
#include "condense/beam_model.hpp"
#include "condense/condense.hpp"

namespace nvh::condense {
namespace {

using namespace testing;

const Logger kQuiet{std::cerr, "test", Verbosity::kQuiet};

/// Elastic frequencies of the unreduced free model, Hz (the 6 rigid-body modes dropped).
Eigen::VectorXd unreduced_hz(const Component& c) {
  const FeModel model = build_beam_model(c);
  const Eigen::MatrixXd K(model.stiffness()), M(model.mass());
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(K, M);
  const Eigen::VectorXd lambda = eig.eigenvalues().tail(K.rows() - 6).cwiseMax(0.0);
  return lambda.cwiseSqrt() / (2.0 * kPi);
}

TEST(CraigBampton, ReproducesTheLowestFrequenciesWithinPointOnePercent) {
  Component c = frame();
  const Eigen::VectorXd ref = unreduced_hz(c);
  c.reduction.method = ReductionMethod::kCraigBampton;
  // Fixed-interface modes up to 5 times the band of interest (6th mode). Measured on this frame (only
  // two interface points on a free body): 1.9x the band keeps 10 modes and errs by up to 0.47 %, 3.3x
  // (16 modes) by 0.10 %, 4.6x (20 modes) by 0.05 % (see docs/theory/beams-and-reduction.md).
  c.reduction.fmax_hz = 5.0 * ref(5);
  const Superelement se = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
  ASSERT_GE(se.frequency_hz.size(), 6);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(se.frequency_hz(i) / ref(i), 1.0, 1e-3) << "mode " << i + 1;
  EXPECT_EQ(se.rigid_body_modes_removed, 6);
  // Orthonormalized: B^T M B = I, checked on the nodal shapes through the quadratic invariants
  // (S_xx + S_yy + S_zz = B^T M B, assembled from the element integrals, not from M_r).
  const Eigen::MatrixXd btmb =
      se.invariants.quadratic[0] + se.invariants.quadratic[4] + se.invariants.quadratic[8];
  EXPECT_NEAR((btmb - Eigen::MatrixXd::Identity(se.size(), se.size())).norm(), 0.0, 1e-8);
}

TEST(CraigBampton, ConvergesAsFixedInterfaceModesAreAdded) {
  Component c = frame();
  const Eigen::VectorXd ref = unreduced_hz(c);
  c.reduction.method = ReductionMethod::kCraigBampton;
  double previous = 1e300;
  for (int modes : {1, 2, 4, 8, 16, 32}) {
    c.reduction.modes = modes;
    const Superelement se = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
    double worst = 0.0;
    for (int i = 0; i < 6; ++i) worst = std::max(worst, se.frequency_hz(i) / ref(i) - 1.0);
    // Rayleigh-Ritz: a reduced model never lies below the full one, and more modes never make it worse.
    for (int i = 0; i < 6; ++i) EXPECT_GE(se.frequency_hz(i), ref(i) * (1 - 1e-9));
    EXPECT_LE(worst, previous * (1 + 1e-9)) << modes << " modes";
    previous = worst;
  }
  EXPECT_LT(previous, 2e-4);  // 32 fixed-interface modes: 1.2e-4 measured
}

TEST(CraigBampton, RawBasisKeepsInterfaceDofsAndTheSameFrequencies) {
  Component c = frame();
  c.reduction.method = ReductionMethod::kCraigBampton;
  c.reduction.modes = 10;
  c.reduction.orthonormalize = true;
  const Superelement ortho = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
  c.reduction.orthonormalize = false;
  const Superelement raw = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
  EXPECT_EQ(raw.size(), 12 + 10);
  EXPECT_EQ(raw.coordinates.front(), "a.x");
  EXPECT_EQ(raw.rigid_body_modes_contained, 6);
  ASSERT_EQ(raw.frequency_hz.size(), ortho.frequency_hz.size());
  for (int i = 0; i < raw.frequency_hz.size(); ++i)
    EXPECT_NEAR(raw.frequency_hz(i) / ortho.frequency_hz(i), 1.0, 1e-9);
  // The raw basis keeps the interface node's motion as its own coordinates: unit shape.
  EXPECT_NEAR(raw.interfaces.shapes[0](0, 0), 1.0, 1e-14);
}

TEST(FreeFreeModal, MatchesTheUnreducedModelAndBothEigenSolvers) {
  Component c = frame(30);  // 366 free DOF: above the dense-solver size, so the Lanczos backends run
  const Eigen::VectorXd ref = unreduced_hz(c);
  c.reduction.method = ReductionMethod::kModal;
  c.reduction.modes = 10;
  for (EigenBackend backend : {EigenBackend::kBlockLanczos, EigenBackend::kSpectra, EigenBackend::kArpack}) {
    const Superelement se = condense_component(c, backend, kQuiet);
    ASSERT_EQ(se.frequency_hz.size(), 10);
    for (int i = 0; i < 10; ++i) EXPECT_NEAR(se.frequency_hz(i) / ref(i), 1.0, 1e-8) << to_string(backend);
  }
}

TEST(FreeFreeModal, FmaxSelectsExactlyTheModesBelowIt) {
  Component c = frame();
  const Eigen::VectorXd ref = unreduced_hz(c);
  c.reduction.method = ReductionMethod::kModal;
  c.reduction.fmax_hz = 0.5 * (ref(6) + ref(7));  // between the 7th and 8th elastic modes
  const Superelement se = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
  EXPECT_EQ(se.frequency_hz.size(), 7);
}

TEST(Guyan, ShowsTheKnownErrorOfStaticCondensation) {
  // Slender cantilever, Euler-Bernoulli mass, condensed onto its tip node.
  BeamSection s = circle(0.01);
  s.rotary_inertia = false;
  const double L = 1.0;
  Component c = straight_beam(L, s, 40);
  c.supports = {fixed({0, 0, 0})};
  c.interfaces = {point("tip", {L, 0, 0})};
  c.reduction.method = ReductionMethod::kGuyan;
  const Superelement se = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
  ASSERT_EQ(se.size(), 6);
  const Steel steel;
  const double unit = std::sqrt(steel.E * s.Iz / (steel.rho * s.A * std::pow(L, 4))) / (2 * kPi);
  // One cubic element: det([12 -6; -6 4] - x/420 [156 -22; -22 4]) = 0 (L = 1 in these units).
  const double a = (156.0 * 4 - 22.0 * 22) / (420.0 * 420.0),
               b = -(12.0 * 4 + 4.0 * 156 - 2 * 6.0 * 22) / 420.0, cc = 12.0 * 4 - 36.0;
  const double x1 = (-b - std::sqrt(b * b - 4 * a * cc)) / (2 * a),
               x2 = (-b + std::sqrt(b * b - 4 * a * cc)) / (2 * a);
  EXPECT_NEAR(std::sqrt(x1), 3.5327, 1e-4);  // the textbook values, as a check of this reference
  EXPECT_NEAR(std::sqrt(x2), 34.807, 1e-3);
  EXPECT_NEAR(se.frequency_hz(0) / (std::sqrt(x1) * unit), 1.0, 1e-3);
  EXPECT_NEAR(se.frequency_hz(1) / (std::sqrt(x1) * unit), 1.0, 1e-3);
  EXPECT_NEAR(se.frequency_hz(2) / (std::sqrt(x2) * unit), 1.0, 1e-3);
  // ... which is 0.48 % above the exact first mode and 58 % above the second.
  EXPECT_NEAR(se.frequency_hz(0) / (1.8751040687 * 1.8751040687 * unit), 1.0048, 1e-3);
}

TEST(Reduction, FmaxBelowTheFirstModeIsAnErrorThatNamesIt) {
  Component c = frame();
  c.reduction.method = ReductionMethod::kModal;
  c.reduction.fmax_hz = 1.0;
  try {
    condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("below the first elastic mode"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nvh::condense
