// The error estimate of a reduction in a band (condense/frf_error.hpp) and the cut-off chosen from it.
//
// References, none computed by the estimate's own path:
// - the full model's receptance by a dense LU solve of (K - w^2 M) on the free DOF (Eigen, n ~ 400);
// - the Euler-Bernoulli cantilever's tip receptance in closed form (Bishop and Johnson, The Mechanics of
//   Vibration, 1960; Blevins, Formulas for Natural Frequency and Mode Shape, 1979, table 8-1):
//     u(L) / F = (sin bL cosh bL - cos bL sinh bL) / (EI b^3 (1 + cos bL cosh bL)),  b^4 = rho A w^2 / EI;
// - the reduced model's receptance as solve would form it from the file: the interface shapes S (6 x n)
//   and the reduced matrices, G_r = S (K_r - w^2 M_r)^-1 S^T.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <filesystem>

#include "beam_fixtures.hpp"
#include "common/hdf5.hpp"
#include "common/log.hpp"
#include "common/provenance.hpp"
#include "condense/beam_model.hpp"
#include "condense/component_reader.hpp"
#include "condense/condense.hpp"
#include "condense/frf_error.hpp"
#include "condense/static_solve.hpp"

namespace nvh::condense {
namespace {

using namespace testing;

const Logger kQuiet{std::cerr, "test", Verbosity::kQuiet};

constexpr double kLength = 0.6;
constexpr double kDiameter = 0.02;

/// Steel round bar along x, clamped at x = 0, interface at the tip; Euler-Bernoulli stiffness and mass
/// (no shear, no rotary inertia) so that the closed form applies.
Component cantilever(int elements = 60) {
  BeamSection s = circle(kDiameter);
  s.rotary_inertia = false;
  Component c = straight_beam(kLength, s, elements);
  c.supports = {fixed({0, 0, 0})};
  c.interfaces = {point("tip", {kLength, 0, 0})};
  c.reduction.method = ReductionMethod::kCraigBampton;
  return c;
}

/// Closed-form Euler-Bernoulli tip receptance of the cantilever, m/N.
double tip_receptance(double omega) {
  const Steel steel;
  const BeamSection s = circle(kDiameter);
  const double EI = steel.E * s.Iz;
  const double b = std::pow(steel.rho * s.A * omega * omega / EI, 0.25);
  const double bl = b * kLength;
  return (std::sin(bl) * std::cosh(bl) - std::cos(bl) * std::sinh(bl)) /
         (EI * b * b * b * (1.0 + std::cos(bl) * std::cosh(bl)));
}

/// The full model's 6 x 6 receptance at node `node` (nodal DOF ux .. rz), dense LU on the free DOF.
Eigen::MatrixXd full_receptance(const FeModel& model, int node, double omega) {
  const Eigen::MatrixXd K(model.stiffness()), M(model.mass());
  const Eigen::MatrixXd T = Eigen::MatrixXd(model.transform).middleRows(6 * node, 6);  // 6 x n_free
  const Eigen::MatrixXd x = (K - omega * omega * M).partialPivLu().solve(Eigen::MatrixXd(T.transpose()));
  return T * x;
}

/// The reduced model's receptance at interface p, as solve forms it from the file's contents.
Eigen::MatrixXd reduced_receptance(const Superelement& se, int p, double omega) {
  const Eigen::MatrixXd& S = se.interfaces.shapes[p];
  const Eigen::MatrixXd d = se.stiffness - omega * omega * se.mass;
  return S * d.partialPivLu().solve(Eigen::MatrixXd(S.transpose()));
}

/// The estimate's measure (frf_error.hpp), computed here from the two receptances: rotations times l.
double relative_error(const Eigen::MatrixXd& reduced, const Eigen::MatrixXd& full, double l) {
  Eigen::VectorXd s(6);
  s << 1, 1, 1, l, l, l;
  return (s.asDiagonal() * (reduced - full) * s.asDiagonal()).norm() /
         (s.asDiagonal() * full * s.asDiagonal()).norm();
}

int tip_node(const Component& c) {
  return c.beam.elements_per_segment;
}

TEST(FrfError, SampleFrequenciesAvoidResonances) {
  Eigen::VectorXd resonances(4);
  resonances << 100.0, 400.0, 410.0, 2000.0;  // a close pair, and one above the band
  const std::vector<double> f = frf_sample_frequencies(1000.0, resonances, 10);
  // Intervals 0-100 (1 sample, at 50 Hz), 100-400 (3, equal ratios), 400-410 (none: closer than 5 %),
  // 410-1000 (6, equal ratios up to 1000 / (1000/410)^(1/12)).
  ASSERT_EQ(f.size(), 10u);
  for (std::size_t i = 0; i < f.size(); ++i) {
    EXPECT_GT(f[i], 0.0);
    EXPECT_LT(f[i], 1000.0);
    if (i) {
      EXPECT_GT(f[i], f[i - 1]);
    }
    for (int k = 0; k < 3; ++k) EXPECT_GT(std::abs(f[i] / resonances(k) - 1.0), 0.07) << f[i];
  }
  EXPECT_DOUBLE_EQ(f[0], 50.0);
  EXPECT_NEAR(f[2], 200.0, 1e-9);  // 100 * 4^(1/2)
  EXPECT_NEAR(f.back(), 1000.0 / std::pow(1000.0 / 410.0, 1.0 / 12.0), 1e-9);
}

// The deflated solve of (K - w^2 M) X = R on a free-free bar (rigid modes in the deflation) between its
// elastic modes, against a dense LU solve: 1e-9 relative.
TEST(FrfError, DeflatedSolveEqualsDenseSolve) {
  Component c = straight_beam(1.0, circle(0.03, 0.9), 30);
  const FeModel model = build_beam_model(c);
  const SparseMatrix K = model.stiffness(), M = model.mass();
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense{Eigen::MatrixXd(K), Eigen::MatrixXd(M)};
  const Eigen::VectorXd lambda = dense.eigenvalues();
  // Deflate every mode below 3 kHz (6 rigid + the elastic ones), solve at 2.2 kHz.
  const double bound = std::pow(2.0 * kPi * 3000.0, 2);
  int m = 0;
  while (lambda(m) < bound) ++m;
  ASSERT_GT(m, 8);
  const Eigen::MatrixXd phi = dense.eigenvectors().leftCols(m);
  const Eigen::VectorXd lam = lambda.head(m);
  ConstrainedFactor preconditioner;  // unconstrained: the plain factor
  const double sigma = -std::pow(2.0 * kPi * 100.0, 2);
  ASSERT_TRUE(preconditioner.factorize(SparseMatrix(K - sigma * M)));
  DeflatedShiftedSolver solver(K, M, false, phi, lam, lambda(m), preconditioner);
  const double w2 = std::pow(2.0 * kPi * 2200.0, 2);
  const Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(K.rows(), 4);
  const Eigen::MatrixXd x = solver.solve(w2, rhs);
  const Eigen::MatrixXd reference = (Eigen::MatrixXd(K) - w2 * Eigen::MatrixXd(M)).partialPivLu().solve(rhs);
  EXPECT_LT((x - reference).norm() / reference.norm(), 1e-9);
  EXPECT_LT(solver.iterations(), 30);
  // Below the bound only: a mode missing from the deflation is reported, not hidden.
  DeflatedShiftedSolver short_of_modes(K, M, false, phi.leftCols(m - 2), lam.head(m - 2), lambda(m),
                                       preconditioner);
  EXPECT_THROW(short_of_modes.solve(w2, rhs), Error);
}

// The full model the estimate compares with is the beam of the closed form: the tip translational
// receptance of the FE cantilever (60 elements) at the estimate's own sample frequencies equals
// Euler-Bernoulli's to 1e-4 below 1 kHz (the mesh's discretization error, not the estimate's).
TEST(FrfError, FullModelMatchesClosedFormCantilever) {
  const Component c = cantilever();
  const FeModel model = build_beam_model(c);
  for (double f : {20.0, 150.0, 400.0, 700.0, 950.0}) {
    const double omega = 2.0 * kPi * f;
    const double fe = full_receptance(model, tip_node(c), omega)(1, 1);  // uy under Fy
    EXPECT_NEAR(fe / tip_receptance(omega), 1.0, 1e-4) << f << " Hz";
  }
}

// The estimate written by a Craig-Bampton reduction with a given cut-off equals the error computed here
// independently (dense full model, reduced model from the file's shapes), sample by sample, to 1e-3 of
// its value plus 1e-6 (the floor set by the eigen-solves' and the solves' round-off: below it both
// measures are noise); and the error is large when the cut-off is low.
TEST(FrfError, CraigBamptonEstimateEqualsIndependentError) {
  for (double fmax : {1200.0, 3000.0}) {
    Component c = cantilever();
    c.reduction.fmax_hz = fmax;
    c.reduction.band_hz = 1000.0;
    const Superelement se = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
    const FrfErrorEstimate& e = se.reduction_error.estimate;
    ASSERT_FALSE(e.empty());
    ASSERT_EQ(e.points.size(), 1u);
    EXPECT_EQ(e.points[0], "tip");
    EXPECT_NEAR(e.length_scale, 0.5 * kLength, 1e-12);
    const FeModel model = build_beam_model(c);
    for (Eigen::Index s = 0; s < e.frequency_hz.size(); ++s) {
      const double omega = 2.0 * kPi * e.frequency_hz(s);
      const double truth = relative_error(reduced_receptance(se, 0, omega),
                                          full_receptance(model, tip_node(c), omega), e.length_scale);
      EXPECT_NEAR(e.point_error(0, s), truth, 1e-3 * truth + 1e-6) << fmax << " Hz cut-off, " << omega;
      EXPECT_NEAR(e.interface_error(s), truth, 1e-3 * truth + 1e-6);
    }
    if (fmax < 2000.0) {
      EXPECT_GT(e.max_error(), 1e-3);
    }
  }
}

// Band alone: condense chooses the cut-off. The chosen reduction meets the tolerance by the independent
// measure, and the pass before it (if any) did not; the cut-offs rise.
TEST(FrfError, CutoffChosenFromBandMeetsTolerance) {
  for (double tolerance : {1e-2, 2e-3}) {
    Component c = cantilever();
    c.reduction.band_hz = 1000.0;
    c.reduction.frf_tolerance = tolerance;
    check_reduction(c);
    const Superelement se = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
    const ReductionErrorRecord& rec = se.reduction_error;
    ASSERT_FALSE(rec.passes.empty());
    EXPECT_LE(rec.estimate.max_error(), tolerance);
    EXPECT_DOUBLE_EQ(rec.cutoff_hz, rec.passes.back().first);
    EXPECT_DOUBLE_EQ(rec.passes.front().first, 1500.0);
    for (std::size_t k = 0; k + 1 < rec.passes.size(); ++k) {
      EXPECT_GT(rec.passes[k].second, tolerance);
      EXPECT_GT(rec.passes[k + 1].first, rec.passes[k].first);
    }
    const FeModel model = build_beam_model(c);
    double worst = 0.0;
    for (Eigen::Index s = 0; s < rec.estimate.frequency_hz.size(); ++s) {
      const double omega = 2.0 * kPi * rec.estimate.frequency_hz(s);
      worst = std::max(worst, relative_error(reduced_receptance(se, 0, omega),
                                             full_receptance(model, tip_node(c), omega), 0.5 * kLength));
    }
    EXPECT_LE(worst, tolerance * (1.0 + 1e-6));
    std::printf("tolerance %g: cut-off %.1f Hz after %zu passes, %d coordinates, error %.3g\n", tolerance,
                rec.cutoff_hz, rec.passes.size(), se.size(), rec.estimate.max_error());
  }
}

// A free-free modal reduction: the rigid-body part is exact in both models and left out of the measure.
// Residual modes remove the static truncation error at the interfaces: with them the error at the same
// cut-off is at least 10 times smaller, and both equal the independent measure.
TEST(FrfError, ModalFreeFreeWithAndWithoutResidualModes) {
  double errors[2] = {0.0, 0.0};
  for (int with = 0; with < 2; ++with) {
    Component c = straight_beam(1.0, circle(0.03, 0.9), 40);
    c.interfaces = {point("a", {0, 0, 0}), point("b", {1.0, 0, 0})};
    c.reduction.method = ReductionMethod::kModal;
    c.reduction.fmax_hz = 1500.0;
    c.reduction.band_hz = 1000.0;
    c.reduction.residual_modes = with == 1;
    const Superelement se = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
    const FrfErrorEstimate& e = se.reduction_error.estimate;
    ASSERT_EQ(e.points.size(), 2u);
    errors[with] = e.max_error();
    // Independent: dense full model minus its rigid-body part (from the geometry's rigid field) against
    // the reduced elastic model of the file.
    const FeModel model = build_beam_model(c);
    const Eigen::MatrixXd K(model.stiffness()), M(model.mass());
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense(K, M);
    const Eigen::MatrixXd T0 = Eigen::MatrixXd(model.transform).middleRows(0, 6);
    const Eigen::MatrixXd rigid0 = T0 * dense.eigenvectors().leftCols(6);
    for (Eigen::Index s = 0; s < e.frequency_hz.size(); s += 3) {
      const double omega = 2.0 * kPi * e.frequency_hz(s);
      const Eigen::MatrixXd full = full_receptance(model, 0, omega);
      const Eigen::MatrixXd elastic = full + rigid0 * rigid0.transpose() / (omega * omega);
      const double truth = relative_error(reduced_receptance(se, 0, omega), elastic, e.length_scale);
      EXPECT_NEAR(e.point_error(0, s), truth, 1e-3 * truth + 1e-6) << e.frequency_hz(s) << " Hz";
    }
  }
  EXPECT_LT(errors[1], 0.1 * errors[0]);
  std::printf("modal, cut-off 1.5 x band: error %.3g without residual modes, %.3g with\n", errors[0],
              errors[1]);
}

// Band alone on a modal reduction: residual modes are added unless the file says no (their static
// correction is what brings the axial and torsional receptance at the ends within reach), and the chosen
// cut-off meets the tolerance.
TEST(FrfError, ModalCutoffChosenFromBand) {
  Component c = straight_beam(1.0, circle(0.03, 0.9), 40);
  c.interfaces = {point("a", {0, 0, 0}), point("b", {1.0, 0, 0})};
  c.reduction.method = ReductionMethod::kModal;
  c.reduction.band_hz = 1000.0;
  apply_options(c, {});  // the command line's defaults: residual modes on for a band alone
  EXPECT_TRUE(c.reduction.residual_modes);
  const Superelement se = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
  EXPECT_LE(se.reduction_error.estimate.max_error(), 0.01);
  EXPECT_GE(se.reduction_error.cutoff_hz, 1500.0);
  std::printf("modal, band alone: cut-off %.1f Hz after %zu passes, %d coordinates, error %.3g\n",
              se.reduction_error.cutoff_hz, se.reduction_error.passes.size(), se.size(),
              se.reduction_error.estimate.max_error());
}

// The file: band in [reduction], /reduction_error with its attributes; errors name the key.
TEST(FrfError, ComponentFileAndRecord) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "nvh_frf_error_test";
  std::filesystem::create_directories(dir);
  const std::filesystem::path file = dir / "bar.toml";
  {
    std::FILE* f = std::fopen(file.string().c_str(), "w");
    std::fputs(R"([component]
name = "bar"
kind = "beam"
[material.steel]
E = 210e9
nu = 0.3
rho = 7850.0
[beam]
material = "steel"
points = [[0, 0, 0], [0.6, 0, 0]]
elements_per_segment = 30
[[beam.section]]
segments = [1, 1]
A = 3.14159e-4
Iy = 7.854e-9
Iz = 7.854e-9
J = 1.5708e-8
[[fix]]
at = [0, 0, 0]
dofs = "x y z rx ry rz"
[[interface]]
name = "tip"
at = [0.6, 0, 0]
[reduction]
method = "craig-bampton"
band = 800.0
)",
               f);
    std::fclose(f);
  }
  Component c = read_component(file);
  EXPECT_DOUBLE_EQ(c.reduction.band_hz, 800.0);
  EXPECT_DOUBLE_EQ(c.reduction.frf_tolerance, 0.01);
  EXPECT_NO_THROW(check_reduction(c));
  const Superelement se = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
  const std::filesystem::path out = dir / "bar.h5";
  write_superelement(out, se, make_provenance("test", 0, nullptr, {}));
  const h5::File h5 = h5::File::open_read(out);
  const h5::Group g = h5.root().open_group("reduction_error");
  EXPECT_DOUBLE_EQ(g.double_attribute("band_hz"), 800.0);
  EXPECT_NEAR(g.double_attribute("max_error"), se.reduction_error.estimate.max_error(), 1e-15);
  EXPECT_LE(g.double_attribute("max_error"), 0.01);
  EXPECT_EQ(g.read_strings("points"), std::vector<std::string>{"tip"});

  // A modal reduction with a band but no interface: nothing to estimate at, an error naming the key.
  Component no_interface = c;
  no_interface.interfaces.clear();
  no_interface.reduction.method = ReductionMethod::kModal;
  try {
    condense_component(no_interface, EigenBackend::kBlockLanczos, kQuiet);
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("reduction.band"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace nvh::condense
