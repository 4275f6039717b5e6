// The dense LU of IDA's Newton matrix (solve/newton_matrix_solver.hpp) against known solutions and Eigen's
// full-pivoting LU, its failure on a singular matrix, and the automatic choice between it and KLU.
//
// References: the known x of b = A x, and Eigen's FullPivLU (complete pivoting, independent of LAPACK). The
// matrices are built as IDA's are: CSC, rows scaled over 16 orders of magnitude (constraint rows against
// dynamic rows scaled by cj = alpha / h).
#include <gtest/gtest.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <random>
#include <vector>

#include "solve/newton_matrix_solver.hpp"

namespace nvh::solve {
namespace {

/// RAII for the SUNDIALS objects of one solve.
struct Sundials {
  SUNContext ctx = nullptr;
  SUNMatrix a = nullptr;
  N_Vector x = nullptr, b = nullptr;
  SUNLinearSolver solver = nullptr;
  explicit Sundials(const Eigen::SparseMatrix<double>& m) {
    SUNContext_Create(nullptr, &ctx);
    const auto n = static_cast<sunindextype>(m.rows());
    a = SUNSparseMatrix(n, n, m.nonZeros(), CSC_MAT, ctx);
    for (sunindextype c = 0; c <= n; ++c) SUNSparseMatrix_IndexPointers(a)[c] = m.outerIndexPtr()[c];
    for (Eigen::Index k = 0; k < m.nonZeros(); ++k) {
      SUNSparseMatrix_IndexValues(a)[k] = m.innerIndexPtr()[k];
      SUNSparseMatrix_Data(a)[k] = m.valuePtr()[k];
    }
    x = N_VNew_Serial(n, ctx);
    b = N_VNew_Serial(n, ctx);
  }
  ~Sundials() {
    if (solver) SUNLinSolFree(solver);
    N_VDestroy(x);
    N_VDestroy(b);
    SUNMatDestroy(a);
    SUNContext_Free(&ctx);
  }
  Sundials(const Sundials&) = delete;
  Sundials& operator=(const Sundials&) = delete;
};

/// A sparse n x n matrix like IDA's: dense blocks of `block` on the diagonal (a body's coupled coordinates),
/// a band joining neighbouring blocks, a fraction `coupling` of the other entries set (the flexible bodies'
/// coordinates coupled through their markers to the bodies they touch: the engine's matrix stores 44 % of its
/// entries), rows scaled by 10^(-8..8), and a diagonal that keeps it well conditioned before the scaling.
Eigen::SparseMatrix<double> newton_like(int n, int block, unsigned seed, double coupling = 0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), exponent(-8, 8), pick(0, 1);
  std::vector<double> row_scale(n);
  for (double& s : row_scale) s = std::pow(10.0, exponent(rng));
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    const int b0 = (i / block) * block, b1 = std::min(n, b0 + block);
    for (int j = 0; j < n; ++j) {
      const bool set = (j >= b0 && j < b1) || j == i - block || j == i + block || pick(rng) < coupling;
      if (set) t.emplace_back(i, j, row_scale[i] * (u(rng) + (i == j ? 4.0 * block : 0.0)));
    }
  }
  Eigen::SparseMatrix<double> m(n, n);
  m.setFromTriplets(t.begin(), t.end());
  m.makeCompressed();
  return m;
}

// b = A x for a known x: the solver must return x to the condition of the row-equilibrated matrix (its rows
// scaled to a largest entry of 1: ~1e1 here) times the rounding unit. Unequilibrated partial pivoting would
// lose the small rows' digits; FullPivLU on the row-equilibrated matrix is the independent check of the rest.
TEST(NewtonMatrixSolver, DenseLuSolvesBadlyScaledRowsToTheirCondition) {
  for (const auto& [n, block] : {std::pair{150, 30}, std::pair{358, 51}}) {
    const Eigen::SparseMatrix<double> m = newton_like(n, block, 7);
    Sundials s(m);
    s.solver = make_dense_lu_solver(n, s.ctx);
    ASSERT_EQ(SUNLinSolGetType(s.solver), SUNLINEARSOLVER_DIRECT);
    ASSERT_EQ(SUNLinSolInitialize(s.solver), SUNLS_SUCCESS);
    ASSERT_EQ(SUNLinSolSetup(s.solver, s.a), SUNLS_SUCCESS);
    Eigen::MatrixXd scaled(m);
    for (Eigen::Index i = 0; i < n; ++i) scaled.row(i) /= scaled.row(i).cwiseAbs().maxCoeff();
    const Eigen::FullPivLU<Eigen::MatrixXd> reference(scaled);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    double worst = 0, worst_reference = 0;
    for (int rhs = 0; rhs < 3; ++rhs) {  // the factorization is reused, as by IDA's Newton iterations
      Eigen::VectorXd x_true(n);
      for (int i = 0; i < n; ++i) x_true[i] = u(rng);
      const Eigen::VectorXd b = m * x_true;
      Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(s.b), n) = b;
      ASSERT_EQ(SUNLinSolSolve(s.solver, s.a, s.x, s.b, 0.0), SUNLS_SUCCESS);
      const Eigen::VectorXd x = Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(s.x), n);
      worst = std::max(worst, (x - x_true).norm() / x_true.norm());
      Eigen::VectorXd bs = b;
      for (Eigen::Index i = 0; i < n; ++i) bs[i] /= Eigen::MatrixXd(m).row(i).cwiseAbs().maxCoeff();
      worst_reference = std::max(worst_reference, (reference.solve(bs) - x_true).norm() / x_true.norm());
    }
    std::printf(
        "measured: dense LU (n = %d, rows scaled over 16 orders): %.2e from the known solution "
        "(Eigen's FullPivLU of the equilibrated rows: %.2e)\n",
        n, worst, worst_reference);
    EXPECT_LT(worst, 1e-13);
    EXPECT_LT(worst, 10 * worst_reference + 1e-15);
  }
}

// The KLU solver (make_sparse_lu_solver) on the same matrices: the known solution to the condition of the
// equilibrated rows (KLU scales rows by their largest entry), with SUNDIALS' own SUNLinSol_KLU beside it
// (the solver it replaced); then the values changed on the same pattern (IDA's next setup: a refactorization
// with the first pivots) and after an initialize (IDA's restart: a fresh factorization).
TEST(NewtonMatrixSolver, SparseLuSolvesBadlyScaledRowsRefactorizesAndRestarts) {
  auto solve = [](Sundials& s, const Eigen::SparseMatrix<double>& m, unsigned seed) {
    const Eigen::Index n = m.rows();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    Eigen::VectorXd x_true(n);
    for (Eigen::Index i = 0; i < n; ++i) x_true[i] = u(rng);
    Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(s.b), n) = m * x_true;
    EXPECT_EQ(SUNLinSolSolve(s.solver, s.a, s.x, s.b, 0.0), SUNLS_SUCCESS);
    return (Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(s.x), n) - x_true).norm() / x_true.norm();
  };
  auto set_values = [](Sundials& s, const Eigen::SparseMatrix<double>& m) {
    for (Eigen::Index k = 0; k < m.nonZeros(); ++k) SUNSparseMatrix_Data(s.a)[k] = m.valuePtr()[k];
  };
  for (const auto& [n, block] : {std::pair{150, 30}, std::pair{358, 51}}) {
    const Eigen::SparseMatrix<double> m = newton_like(n, block, 7);
    Sundials ours(m), theirs(m);
    ours.solver = make_sparse_lu_solver(n, ours.ctx);
    theirs.solver = SUNLinSol_KLU(theirs.x, theirs.a, theirs.ctx);
    ASSERT_EQ(SUNLinSolGetType(ours.solver), SUNLINEARSOLVER_DIRECT);
    for (Sundials* s : {&ours, &theirs}) {
      ASSERT_EQ(SUNLinSolInitialize(s->solver), SUNLS_SUCCESS);
      ASSERT_EQ(SUNLinSolSetup(s->solver, s->a), SUNLS_SUCCESS);
    }
    const double first = solve(ours, m, 11), sundials = solve(theirs, m, 11);
    // the same pattern, other values (a neighbouring Newton matrix): refactorized with the first pivots
    Eigen::SparseMatrix<double> m2 = m;
    for (Eigen::Index k = 0; k < m2.nonZeros(); ++k) m2.valuePtr()[k] *= 1.0 + 0.3 * std::sin(double(k));
    set_values(ours, m2);
    ASSERT_EQ(SUNLinSolSetup(ours.solver, ours.a), SUNLS_SUCCESS);
    const double refactored = solve(ours, m2, 12);
    // after an initialize (IDAReInit): factorized afresh
    ASSERT_EQ(SUNLinSolInitialize(ours.solver), SUNLS_SUCCESS);
    ASSERT_EQ(SUNLinSolSetup(ours.solver, ours.a), SUNLS_SUCCESS);
    const double restarted = solve(ours, m2, 13);
    std::printf(
        "measured: KLU (n = %d): %.2e from the known solution (SUNDIALS' SUNLinSol_KLU %.2e); "
        "refactorized %.2e, after a restart %.2e\n",
        n, first, sundials, refactored, restarted);
    for (double e : {first, refactored, restarted}) EXPECT_LT(e, 1e-12);
    EXPECT_LT(first, 10 * sundials + 1e-15);
  }
  // A singular matrix is a recoverable setup failure (IDA retries with a shorter step).
  Eigen::SparseMatrix<double> singular = newton_like(120, 20, 3);
  for (Eigen::SparseMatrix<double>::InnerIterator it(singular, 17); it; ++it) it.valueRef() = 0;
  Sundials s(singular);
  s.solver = make_sparse_lu_solver(120, s.ctx);
  SUNLinSolInitialize(s.solver);
  EXPECT_EQ(SUNLinSolSetup(s.solver, s.a), SUNLS_LUFACT_FAIL);
}

TEST(NewtonMatrixSolver, SingularMatrixIsARecoverableSetupFailure) {
  Eigen::SparseMatrix<double> m = newton_like(120, 20, 3);
  for (Eigen::SparseMatrix<double>::InnerIterator it(m, 17); it; ++it) it.valueRef() = 0;  // column 17 empty
  Sundials s(m);
  s.solver = make_dense_lu_solver(120, s.ctx);
  SUNLinSolInitialize(s.solver);
  const int flag = SUNLinSolSetup(s.solver, s.a);
  EXPECT_EQ(flag, SUNLS_LUFACT_FAIL);  // > 0: IDA retries with a shorter step, as with KLU
  EXPECT_GT(flag, 0);
}

TEST(NewtonMatrixSolver, AutoChoosesDenseOnlyWhereItsFillMakesItCheaper) {
  auto choose = [](const Eigen::SparseMatrix<double>& m, const std::string& setting = "auto") {
    const std::vector<int> start(m.outerIndexPtr(), m.outerIndexPtr() + m.cols() + 1),
        rows(m.innerIndexPtr(), m.innerIndexPtr() + m.nonZeros());
    return choose_newton_solver(setting, static_cast<int>(m.cols()), start, rows);
  };
  // Dense blocks coupled across 30 % of the rest (as the engine's Newton matrix: 358 unknowns): dense.
  const NewtonSolverChoice engine = choose(newton_like(358, 51, 1, 0.3));
  EXPECT_EQ(engine.kind, NewtonSolver::kDense);
  EXPECT_LT(engine.dense_cost_s, 0.7 * engine.klu_cost_s);
  // A chain (tridiagonal blocks of 3, as a valvetrain's masses): KLU.
  const NewtonSolverChoice chain = choose(newton_like(600, 3, 2));
  EXPECT_EQ(chain.kind, NewtonSolver::kKlu);
  EXPECT_GT(chain.dense_cost_s, chain.klu_cost_s);
  // Small models stay with KLU (microseconds either way); explicit settings are obeyed.
  EXPECT_EQ(choose(newton_like(60, 60, 3)).kind, NewtonSolver::kKlu);
  EXPECT_EQ(choose(newton_like(60, 60, 3), "dense").kind, NewtonSolver::kDense);
  EXPECT_EQ(choose(newton_like(358, 51, 1), "klu").kind, NewtonSolver::kKlu);
}

}  // namespace
}  // namespace nvh::solve
