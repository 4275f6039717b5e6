// Distributing (RBE3) couplings in multiplier form (constrained_factor.hpp, [volume] rbe3_form): the
// constrained solves against a dense saddle-point solve, the reduced models against the elimination form,
// the defining property of an RBE3 (no stiffness, no mass) against the bare model's dense eigenvalues, and
// a cantilever's tip deflection under a load at an RBE3 point against Timoshenko beam theory.
#include <gtest/gtest.h>

#include <unistd.h>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/error.hpp"
#include "common/log.hpp"
#include "condense/condense.hpp"
#include "condense/constrained_factor.hpp"
#include "condense/volume_model.hpp"
#include "structured_mesh.hpp"

namespace fs = std::filesystem;

namespace nvh::condense {
namespace {

const Logger kQuiet{std::cerr, "test", Verbosity::kQuiet};

/// A random symmetric positive definite sparse matrix (a 1D Laplacian plus random couplings) and random
/// dense constraints.
TEST(ConstrainedFactor, SolvesTheSaddlePointSystem) {
  const int n = 60, m = 5;
  std::srand(7);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    a(i, i) = 4.0;
    if (i + 1 < n) a(i, i + 1) = a(i + 1, i) = -1.0;
    if (i + 7 < n) a(i, i + 7) = a(i + 7, i) = 0.3 * (i % 3 - 1);
  }
  const Eigen::MatrixXd c = Eigen::MatrixXd::Random(m, n);
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(n, 3), r = Eigen::MatrixXd::Random(m, 3);
  // Reference: the dense saddle-point matrix [A C^T; C 0] by full-pivoting LU (Eigen).
  Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(n + m, n + m);
  kkt.topLeftCorner(n, n) = a;
  kkt.topRightCorner(n, m) = c.transpose();
  kkt.bottomLeftCorner(m, n) = c;
  Eigen::MatrixXd rhs(n + m, 3);
  rhs << b, r;
  const Eigen::MatrixXd reference = kkt.fullPivLu().solve(rhs).topRows(n);

  ConstrainedFactor factor;
  factor.set_constraints(SparseMatrix(c.sparseView()));
  ASSERT_TRUE(factor.factorize(SparseMatrix(a.sparseView())));
  const Eigen::MatrixXd x = factor.solve(b, r);
  EXPECT_LT((x - reference).norm() / reference.norm(), 1e-12);
  EXPECT_LT((c * x - r).norm() / r.norm(), 1e-12);
  // r = 0, and the two halves: backward(forward(b)) is the constrained solve, forward M backward
  // symmetric.
  Eigen::MatrixXd rhs0(n + m, 3);
  rhs0 << b, Eigen::MatrixXd::Zero(m, 3);
  const Eigen::MatrixXd reference0 = kkt.fullPivLu().solve(rhs0).topRows(n);
  EXPECT_LT((factor.solve(b) - reference0).norm() / reference0.norm(), 1e-12);
  EXPECT_LT((factor.backward(factor.forward(b)) - reference0).norm() / reference0.norm(), 1e-12);
  const Eigen::MatrixXd g = factor.backward(factor.forward(Eigen::MatrixXd::Identity(n, n)));
  EXPECT_LT((g - g.transpose()).norm() / g.norm(), 1e-13);

  // Dependent constraint rows are refused.
  Eigen::MatrixXd dependent = c;
  dependent.row(4) = 2.0 * c.row(1) - c.row(3);
  ConstrainedFactor bad;
  bad.set_constraints(SparseMatrix(dependent.sparseView()));
  EXPECT_THROW(bad.factorize(SparseMatrix(a.sparseView())), Error);
}

/// A steel bar 0.4 x 0.04 x 0.04 m (C3D20) with a rigid coupling on its left face and distributing ones
/// on its middle section and its right face.
class Rbe3Bar : public ::testing::Test {
 protected:
  static constexpr double L = 0.4, h = 0.04, E = 210e9, nu = 0.3, rho = 7850.0;
  void write(std::array<int, 3> cells, const std::string& name) {
    Mesh mesh = testing::BoxMesher({L, h, h}, cells).hex20();
    for (int n = 0; n < static_cast<int>(mesh.nodes.size()); ++n) {
      const double x = mesh.nodes[n].x();
      if (x < 1e-12) mesh.node_sets["LEFT"].push_back(n);
      if (std::abs(x - L / 2) < 1e-12) mesh.node_sets["MIDDLE"].push_back(n);
      if (x > L - 1e-12) mesh.node_sets["RIGHT"].push_back(n);
    }
    std::ofstream out(dir_ / name);
    write_abaqus_mesh(mesh, out);
  }
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nvh_rbe3_multiplier_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    write({10, 2, 2}, "bar.inp");
    write({6, 1, 1}, "coarse.inp");
  }
  void TearDown() override { fs::remove_all(dir_); }

  static NamedPoint point(const std::string& name, double x, const std::string& set, bool distributing) {
    NamedPoint p;
    p.name = name;
    p.at = {x, h / 2, h / 2};
    p.surface = set;
    p.distributing = distributing;
    return p;
  }
  Component bar(DistributingForm form, const std::string& mesh = "bar.inp") const {
    Component c;
    c.name = "bar";
    c.kind = "volume";
    c.materials["steel"] = Material{"steel", E, nu, rho};
    c.volume.mesh = dir_ / mesh;
    c.volume.material = "steel";
    c.volume.rbe3_form = form;
    c.interfaces = {point("left", -0.01, "LEFT", false), point("middle", L / 2, "MIDDLE", true),
                    point("right", L, "RIGHT", true)};
    c.reduction.method = ReductionMethod::kCraigBampton;
    c.reduction.modes = 10;
    return c;
  }
  fs::path dir_;
};

double relative_difference(const Eigen::MatrixXd& x, const Eigen::MatrixXd& reference) {
  return (x - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff();
}

TEST_F(Rbe3Bar, CraigBamptonMatchesTheEliminationForm) {
  // The same constrained space, two parametrizations: the reduced eigenproblem and the fixed-interface
  // frequencies agree to round-off (1e-9), orthonormalized (free-free: 6 rigid-body modes) and raw.
  for (const bool orthonormalize : {true, false}) {
    Component a = bar(DistributingForm::kElimination), b = bar(DistributingForm::kMultiplier);
    a.reduction.orthonormalize = b.reduction.orthonormalize = orthonormalize;
    const Superelement ea = condense_component(a, EigenBackend::kBlockLanczos, kQuiet);
    const Superelement eb = condense_component(b, EigenBackend::kBlockLanczos, kQuiet);
    EXPECT_EQ(eb.free_dof_count, ea.free_dof_count + 12) << "the multiplier form keeps 2 x 6 DOF more";
    ASSERT_EQ(ea.frequency_hz.size(), eb.frequency_hz.size());
    double worst = 0.0;
    for (Eigen::Index i = 0; i < ea.frequency_hz.size(); ++i) {
      EXPECT_NEAR(eb.frequency_hz(i) / ea.frequency_hz(i), 1.0, 1e-9) << "mode " << i + 1;
      worst = std::max(worst, std::abs(eb.frequency_hz(i) / ea.frequency_hz(i) - 1.0));
    }
    std::printf("[ RBE3 CB ] orthonormalize %d: %d frequencies, worst relative difference %.2e\n",
                orthonormalize, static_cast<int>(ea.frequency_hz.size()), worst);
    ASSERT_EQ(ea.fixed_interface_hz.size(), 10);
    for (Eigen::Index i = 0; i < 10; ++i)
      EXPECT_NEAR(eb.fixed_interface_hz(i) / ea.fixed_interface_hz(i), 1.0, 1e-9) << "fixed mode " << i + 1;
    if (orthonormalize) {
      EXPECT_EQ(eb.rigid_body_modes_removed, 6);
      EXPECT_LT(relative_difference(eb.stiffness, ea.stiffness), 1e-9);
    } else {
      // The boundary blocks (18 DOF) depend on the constraint modes only: equal as matrices.
      EXPECT_EQ(eb.rigid_body_modes_contained, 6);
      EXPECT_LT(relative_difference(eb.stiffness.topLeftCorner(18, 18), ea.stiffness.topLeftCorner(18, 18)),
                1e-9);
      EXPECT_LT(relative_difference(eb.mass.topLeftCorner(18, 18), ea.mass.topLeftCorner(18, 18)), 1e-9);
      for (int p = 0; p < 3; ++p) {
        EXPECT_LT(
            relative_difference(eb.interfaces.shapes[p].leftCols(18), ea.interfaces.shapes[p].leftCols(18)),
            1e-9)
            << "interface " << p;
      }
    }
    EXPECT_NEAR(eb.inertia.mass / ea.inertia.mass, 1.0, 1e-12);
  }
}

TEST_F(Rbe3Bar, GuyanMatchesTheEliminationForm) {
  // Guyan: the reduced matrices are unique (constraint modes only), so K_r and M_r agree entry by entry.
  Component a = bar(DistributingForm::kElimination), b = bar(DistributingForm::kMultiplier);
  for (Component* c : {&a, &b}) {
    c->reduction.method = ReductionMethod::kGuyan;
    c->reduction.modes = 0;
    c->reduction.orthonormalize = false;
  }
  const Superelement ea = condense_component(a, EigenBackend::kBlockLanczos, kQuiet);
  const Superelement eb = condense_component(b, EigenBackend::kBlockLanczos, kQuiet);
  ASSERT_EQ(eb.stiffness.rows(), 18);
  EXPECT_LT(relative_difference(eb.stiffness, ea.stiffness), 1e-9);
  EXPECT_LT(relative_difference(eb.mass, ea.mass), 1e-9);
  for (Eigen::Index i = 0; i < ea.frequency_hz.size(); ++i)
    EXPECT_NEAR(eb.frequency_hz(i) / ea.frequency_hz(i), 1.0, 1e-9) << "mode " << i + 1;
  // The observation of the right face's centre through the surface: the shapes of its point.
  EXPECT_LT(relative_difference(eb.interfaces.shapes[2], ea.interfaces.shapes[2]), 1e-9);
}

TEST_F(Rbe3Bar, AnRbe3AddsNoStiffnessAndNoMass) {
  // The defining property: the free bar with its rigid left coupling has the same frequencies with the
  // two distributing couplings as without them, and its 6 rigid-body frequencies stay zero. Reference: all
  // eigenvalues of the model without RBE3 (Eigen's dense generalized solver on T^T K T, T^T M T); a
  // Craig-Bampton basis with every fixed-interface mode is exact, so the reduced model must match it.
  Component plain = bar(DistributingForm::kElimination, "coarse.inp");
  plain.interfaces.resize(1);
  const FeModel bare = build_volume_model(plain);
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> reference(Eigen::MatrixXd(bare.stiffness()),
                                                                            Eigen::MatrixXd(bare.mass()));
  const Eigen::VectorXd lambda = reference.eigenvalues();
  const int n = static_cast<int>(lambda.size());

  Component c = bar(DistributingForm::kMultiplier, "coarse.inp");
  // The multiplier form's free DOF: the bare model's n plus the two distributing points' 12. Interior: less
  // the 18 boundary DOF, n - 6; on the 12 constraints, n - 18 fixed-interface modes: the reduced model has
  // n coordinates, which span the whole constrained space.
  c.reduction.modes = n - 18;
  c.reduction.orthonormalize = false;
  const Superelement se = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
  EXPECT_EQ(se.free_dof_count, n + 12);
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> reduced(se.stiffness, se.mass);
  const Eigen::VectorXd mu = reduced.eigenvalues();
  ASSERT_EQ(mu.size(), n);
  double worst = 0.0, rigid = 0.0;
  for (int i = 0; i < 6; ++i) {
    EXPECT_LT(std::abs(mu(i)), 1e-9 * lambda(6)) << "rigid mode " << i + 1;
    rigid = std::max(rigid, std::abs(mu(i)) / lambda(6));
  }
  for (int i = 6; i < n; ++i) {
    EXPECT_NEAR(mu(i) / lambda(i), 1.0, 1e-9) << "mode " << i + 1;
    worst = std::max(worst, std::abs(mu(i) / lambda(i) - 1.0));
  }
  std::printf("[ RBE3 free ] %d eigenvalues: rigid |lambda| / lambda_7 <= %.1e, elastic within %.1e\n", n,
              rigid, worst);
}

TEST_F(Rbe3Bar, TipLoadAtAnRbe3PointBendsTheCantileverAsBeamTheory) {
  // The bar clamped at its left face (its rigid coupling's point held), a transverse force F at the
  // right face's RBE3 point: the Guyan stiffness of the tip point gives the tip deflection, against
  // Timoshenko's cantilever delta = F L^3 / (3 E I) + F L / (kappa G A) with Cowper's (1966) shear
  // coefficient of a square, kappa = 10 (1 + nu) / (12 + 11 nu) - within 2 %: the clamp (a rigid coupling)
  // also holds the root section's Poisson contraction, which stiffens it (1.5 % here) - and equal in both
  // forms to round-off.
  const auto tip_flexibility = [&](DistributingForm form) {
    Component c = bar(form);
    c.interfaces = {point("left", -0.01, "LEFT", false), point("right", L, "RIGHT", true)};
    Support hold;
    hold.box = std::array<double, 6>{-0.011, h / 2 - 1e-3, h / 2 - 1e-3, -0.009, h / 2 + 1e-3, h / 2 + 1e-3};
    hold.dofs.fill(true);
    c.supports = {hold};
    c.reduction.method = ReductionMethod::kGuyan;
    c.reduction.modes = 0;
    c.reduction.orthonormalize = false;
    const Superelement se = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
    EXPECT_EQ(se.stiffness.rows(), 6);
    return Eigen::MatrixXd(se.stiffness.inverse());
  };
  const Eigen::MatrixXd g_elimination = tip_flexibility(DistributingForm::kElimination);
  const Eigen::MatrixXd g = tip_flexibility(DistributingForm::kMultiplier);
  EXPECT_LT(relative_difference(g, g_elimination), 1e-9);
  const double I = h * h * h * h / 12.0, A = h * h, G = E / (2.0 * (1.0 + nu));
  const double kappa = 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu);
  const double delta = L * L * L / (3.0 * E * I) + L / (kappa * G * A);  // per newton
  std::printf("[ RBE3 tip ] flexibility vs elimination %.1e; y %.4e m/N, z %.4e, beam %.4e\n",
              relative_difference(g, g_elimination), g(1, 1), g(2, 2), delta);
  EXPECT_NEAR(g(1, 1) / delta, 1.0, 0.02) << "tip flexibility y " << g(1, 1) << " m/N, beam " << delta;
  EXPECT_NEAR(g(2, 2) / delta, 1.0, 0.02) << "tip flexibility z " << g(2, 2) << " m/N, beam " << delta;
  // Axial: L / (E A); torsion of the square: L / (G 0.1406 h^4) (Roark, Table 10.1, case 1).
  EXPECT_NEAR(g(0, 0) / (L / (E * A)), 1.0, 0.02);
  EXPECT_NEAR(g(3, 3) / (L / (G * 0.1406 * h * h * h * h)), 1.0, 0.03);
}

TEST_F(Rbe3Bar, MultiplierFormWhereItDoesNotApplyIsAnError) {
  Component modal = bar(DistributingForm::kMultiplier);
  modal.reduction.method = ReductionMethod::kModal;
  try {
    condense_component(modal, EigenBackend::kBlockLanczos, kQuiet);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("volume.rbe3_form"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("modal"), std::string::npos) << e.what();
  }
  // Only distributing couplings: nothing restrains the interior without them.
  Component free = bar(DistributingForm::kMultiplier);
  free.interfaces.erase(free.interfaces.begin());
  EXPECT_THROW(condense_component(free, EigenBackend::kBlockLanczos, kQuiet), Error);
  // auto falls back to the elimination form there (the same free DOF as asked for explicitly).
  free.volume.rbe3_form = DistributingForm::kAuto;
  const Superelement a = condense_component(free, EigenBackend::kBlockLanczos, kQuiet);
  free.volume.rbe3_form = DistributingForm::kElimination;
  const Superelement b = condense_component(free, EigenBackend::kBlockLanczos, kQuiet);
  EXPECT_EQ(a.free_dof_count, b.free_dof_count);
  // ... and picks the multiplier form where it applies.
  const Superelement m =
      condense_component(bar(DistributingForm::kAuto), EigenBackend::kBlockLanczos, kQuiet);
  const Superelement e =
      condense_component(bar(DistributingForm::kElimination), EigenBackend::kBlockLanczos, kQuiet);
  EXPECT_EQ(m.free_dof_count, e.free_dof_count + 12);
}

}  // namespace
}  // namespace nvh::condense
