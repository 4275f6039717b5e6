// The generalized symmetric eigenproblem K x = lambda M x (see eigensolver.hpp).
//
// Shift-invert (Ericsson & Ruhe 1980; Grimes, Lewis & Simon 1994): with a shift sigma < 0 the matrix
// K - sigma M is positive definite even for a singular (free-free) K, so it has a Cholesky factorization
// (CHOLMOD, supernodal). The Lanczos iteration in the M inner product then runs on
// OP = (K - sigma M)^-1 M, whose eigenvalues nu = 1 / (lambda - sigma) are largest for the lowest lambda
// and well separated there; lambda = sigma + 1 / nu. Both iterative backends use the same factorization
// K - sigma M = P^T L L^T P:
// - Block Lanczos (default; block_lanczos.hpp) on the symmetric form C below, a block of vectors per
//   solve: the solve with b right-hand sides reads the factor once, so on large factors a vector costs a
//   third to a sixth of a single-vector solve, while the block space needs about twice the vectors.
// - Spectra: its SymEigsSolver on the symmetric form of the same operator,
//   C = L^-1 P M P^T L^-T, whose eigenvalues are the nu and whose eigenvectors y give x = P^T L^-T y
//   (C y = nu y <=> OP x = nu x). The Lanczos iteration then runs in the ordinary inner product: one
//   product with M per step instead of the three of the M inner product (Spectra's SymGEigsShiftSolver
//   did this before; on the 240k-DOF engine block of bench/, 81 solves either way, eigen-solve 19.7 s
//   -> 14.5 s).
// - ARPACK's dsaupd/dseupd in mode 3 (OP in the M inner product), for comparison.
// The dense backend (Eigen's GeneralizedSelfAdjointEigenSolver: Cholesky of M, then a standard symmetric
// eigenproblem) is the reference for small models.
//
// Post-processing common to all backends: eigenpairs sorted ascending, vectors M-orthonormalized
// (normalization plus modified Gram-Schmidt in the M inner product within clusters of equal eigenvalues,
// twice - "twice is enough", Parlett), residual of every mode checked against the request's limit.
#include "condense/eigensolver.hpp"

#include <Spectra/SymEigsSolver.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <arpack.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iomanip>
#include <limits>
#include <memory>
#include <numbers>
#include <numeric>
#include <optional>
#include <sstream>
#include <vector>

#include "common/error.hpp"
#include "condense/block_lanczos.hpp"
#include "condense/lobpcg.hpp"
#include "condense/sparse_cholesky.hpp"

namespace nvh::condense {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
/// Models up to this size always go through the dense solver (cheaper and exact enough).
constexpr Eigen::Index kDenseSize = 300;
/// First guess of the number of modes when only fmax is given; doubled until fmax is passed.
constexpr int kInitialModes = 20;
/// The automatic fallback to the dense solver (fmax above nearly all modes) refuses larger models.
constexpr Eigen::Index kDenseFallbackLimit = 10000;
/// Restarts of the implicitly restarted Lanczos iteration before giving up (per attempt).
constexpr int kMaxRestarts = 1000;

std::string str(double value) {
  std::ostringstream out;
  out << std::setprecision(6) << value;
  return out.str();
}

/// ||A||_1: largest column sum of absolute values (= ||A||_inf for a symmetric A).
double norm1(const SparseMatrix& a) {
  double result = 0.0;
  for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
    double column = 0.0;
    for (SparseMatrix::InnerIterator it(a, j); it; ++it) column += std::abs(it.value());
    result = std::max(result, column);
  }
  return result;
}

/// ||A||_1 of a symmetric matrix stored with both triangles, or with the lower one alone.
double symmetric_norm1(const SparseMatrix& a, bool lower_triangle) {
  if (!lower_triangle) return norm1(a);
  Eigen::VectorXd column = Eigen::VectorXd::Zero(a.cols());
  for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(a, j); it; ++it) {
      column[j] += std::abs(it.value());
      if (it.row() != j) column[it.row()] += std::abs(it.value());
    }
  }
  return column.size() ? column.maxCoeff() : 0.0;
}

bool all_finite(const SparseMatrix& a) {
  for (Eigen::Index j = 0; j < a.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(a, j); it; ++it)
      if (!std::isfinite(it.value())) return false;
  return true;
}

/// Position of entry (row, col) in a compressed column-major matrix, or -1 (binary search).
Eigen::Index find_entry(const SparseMatrix& a, Eigen::Index row, Eigen::Index col) {
  const int* begin = a.innerIndexPtr() + a.outerIndexPtr()[col];
  const int* end = a.innerIndexPtr() + a.outerIndexPtr()[col + 1];
  const int* it = std::lower_bound(begin, end, static_cast<int>(row));
  return it != end && *it == row ? it - a.innerIndexPtr() : -1;
}

/// Make `a` exactly symmetric in place if its asymmetry is round-off (the factorization reads the lower
/// triangle, the products use both: they must see the same matrix); nvh::Error otherwise. No copies for
/// a structurally symmetric pattern (every FE matrix): each entry meets its transpose by binary search.
void symmetrize(SparseMatrix& a, const char* name) {
  a.makeCompressed();
  double* values = a.valuePtr();
  bool structural = true;
  Eigen::VectorXd column_asymmetry = Eigen::VectorXd::Zero(a.cols());
  for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(a, j); it; ++it) {
      if (it.row() == j) continue;
      const Eigen::Index t = find_entry(a, j, it.row());
      structural = structural && t >= 0;
      column_asymmetry[j] += std::abs(it.value() - (t >= 0 ? values[t] : 0.0));
    }
  }
  const double asymmetry = column_asymmetry.size() ? column_asymmetry.maxCoeff() : 0.0;
  if (asymmetry == 0.0) return;
  const double scale = norm1(a);
  if (asymmetry > 1e-10 * scale) {
    throw Error(std::string("the ") + name + " matrix is not symmetric (||A - A^T||_1 = " + str(asymmetry) +
                ", ||A||_1 = " + str(scale) + "); the full symmetric matrix must be stored");
  }
  if (!structural) {  // round-off on one side only of a pattern: the symmetric part, through copies
    a = SparseMatrix(0.5 * (a + SparseMatrix(a.transpose())));
    return;
  }
  for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
    for (Eigen::Index k = a.outerIndexPtr()[j]; k < a.outerIndexPtr()[j + 1]; ++k) {
      const Eigen::Index i = a.innerIndexPtr()[k];
      if (i <= j) continue;
      const Eigen::Index t = find_entry(a, j, i);
      values[k] = values[t] = 0.5 * (values[k] + values[t]);
    }
  }
}

/// y = A x for a symmetric A stored as its lower triangle (compressed, sorted columns) and a block x of
/// columns, reading A once for the whole block: each entry a_ij updates the rows i and j of all columns,
/// held row-major. Eigen's product with a self-adjoint view reads A once per column of x: on the 240k-DOF
/// engine block (bench/README.md) the block Lanczos solve's products with M and the residual checks of
/// 30 modes took 2.1 s that way and 1.5 s this way (a kernel with the width fixed at compile time and
/// AVX-512 clones was no faster: the scattered updates of the rows i bound it).
Eigen::MatrixXd lower_symmetric_times(const SparseMatrix& a, const Eigen::Ref<const Eigen::MatrixXd>& x) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Index b = x.cols();
  if (b == 1 || !a.isCompressed()) return a.selfadjointView<Eigen::Lower>() * x;
  const RowMajor xr = x;
  RowMajor yr = RowMajor::Zero(x.rows(), b);
  const int* outer = a.outerIndexPtr();
  const int* inner = a.innerIndexPtr();
  const double* values = a.valuePtr();
  for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
    const double* xj = xr.data() + j * b;
    double* yj = yr.data() + j * b;
    for (int k = outer[j]; k < outer[j + 1]; ++k) {
      const Eigen::Index i = inner[k];
      const double v = values[k];
      if (i == j) {
        for (Eigen::Index c = 0; c < b; ++c) yj[c] += v * xj[c];
      } else if (i > j) {
        const double* xi = xr.data() + i * b;
        double* yi = yr.data() + i * b;
        for (Eigen::Index c = 0; c < b; ++c) {
          yi[c] += v * xj[c];
          yj[c] += v * xi[c];
        }
      }
    }
  }
  return yr;
}

/// The pencil (K, M) as the eigen-solve keeps it, in lower triangles only, and K not at all but as
/// A = K - sigma_a M: the matrix the first factorization needs, so that the factorization makes no copy
/// of its own and K's storage is given back before it (on large solids the factor sets the peak
/// memory). Products with K are A x + sigma_a M x.
struct Pencil {
  SparseMatrix a;        ///< lower triangle of K - sigma_a M
  double sigma_a = 0.0;  ///< rad^2/s^2
  SparseMatrix m;        ///< lower triangle of M
  double k_norm1 = 0.0;  ///< ||K||_1, kept from before K was dropped
  /// Constrained problems (C x = 0, a given ConstrainedFactor): C (m x n, sparse) and the Cholesky
  /// factor of C C^T, for the projection onto the null space of C; none otherwise.
  const SparseMatrix* constraints = nullptr;
  Eigen::LLT<Eigen::MatrixXd> constraint_gram;

  /// r - C^T (C C^T)^-1 C r: the part of r outside the range of C^T, where K x - lambda M x = -C^T mu
  /// of a constrained eigenpair lies.
  Eigen::VectorXd outside_constraint_range(const Eigen::VectorXd& r) const {
    if (!constraints) return r;
    return r - constraints->transpose() * constraint_gram.solve(*constraints * r);
  }

  Eigen::Index rows() const { return m.rows(); }
  Eigen::MatrixXd mass_times(const Eigen::Ref<const Eigen::MatrixXd>& x) const {
    return lower_symmetric_times(m, x);
  }
  Eigen::MatrixXd stiffness_times(const Eigen::Ref<const Eigen::MatrixXd>& x) const {
    Eigen::MatrixXd y = lower_symmetric_times(a, x);
    if (sigma_a != 0.0) y += sigma_a * mass_times(x);
    return y;
  }
  /// K x from M x already formed (K x = A x + sigma_a M x).
  Eigen::MatrixXd stiffness_times(const Eigen::Ref<const Eigen::MatrixXd>& x,
                                  const Eigen::MatrixXd& mx) const {
    Eigen::MatrixXd y = lower_symmetric_times(a, x);
    if (sigma_a != 0.0) y += sigma_a * mx;
    return y;
  }
  /// Lower triangle of K - sigma M (another shift than sigma_a).
  SparseMatrix shifted(double sigma) const { return SparseMatrix(a + (sigma_a - sigma) * m); }
  /// Full symmetric dense copies (the dense backend).
  Eigen::MatrixXd dense_mass() const {
    return Eigen::MatrixXd(SparseMatrix(m.selfadjointView<Eigen::Lower>()));
  }
  Eigen::MatrixXd dense_stiffness() const {
    return Eigen::MatrixXd(SparseMatrix(a.selfadjointView<Eigen::Lower>())) + sigma_a * dense_mass();
  }
};

/// Build the pencil from symmetric K and M (both triangles, or the lower ones alone), giving back the
/// storage of each once its triangle is taken.
void make_pencil(SparseMatrix& K, SparseMatrix& M, double sigma_a, bool lower_triangles, Pencil& p) {
  const auto release = [](SparseMatrix& a) { SparseMatrix().swap(a); };
  p.k_norm1 = symmetric_norm1(K, lower_triangles);
  p.sigma_a = sigma_a;
  if (lower_triangles && sigma_a == 0.0) {
    p.a.swap(K);
  } else {
    SparseMatrix a = lower_triangles ? SparseMatrix(K - sigma_a * M)
                                     : SparseMatrix((K - sigma_a * M).triangularView<Eigen::Lower>());
    p.a.swap(a);
  }
  release(K);
  if (lower_triangles) {
    p.m.swap(M);
  } else {
    SparseMatrix m = M.triangularView<Eigen::Lower>();
    p.m.swap(m);
  }
  release(M);
}

/// Shift-invert operator of Spectra's OpType concept: y = (K - sigma M)^-1 x on a CHOLMOD supernodal
/// Cholesky factorization, computed once and reused by every solve (and every retry with more modes).
class ShiftInvertOperator {
 public:
  using Scalar = double;

  ShiftInvertOperator(const Pencil& pencil, double sigma, Ordering ordering)
      : pencil_(pencil), factor_(std::make_shared<ConstrainedFactor>(ordering)) {
    factorize(sigma);
  }
  /// On a given factorization of K itself (shift 0; K positive definite).
  ShiftInvertOperator(const Pencil& pencil, std::shared_ptr<const ConstrainedFactor> stiffness_factor)
      : pencil_(pencil), given_(std::move(stiffness_factor)), sigma_(0.0) {}

  Eigen::Index rows() const { return pencil_.rows(); }
  Eigen::Index cols() const { return pencil_.rows(); }
  double shift() const { return sigma_; }
  int solves() const { return solves_; }
  /// The cost of the operator's own factorizations (none on a given factorization).
  FactorStats factor_stats() const { return factor_ ? factor_->stats() : FactorStats{}; }

  /// Called by Spectra with the solver's shift; refactorizes only if it differs from the factored one.
  void set_shift(double sigma) {
    if (sigma != sigma_) factorize(sigma);
  }

  /// y = OP x = (K - sigma M)^-1 x (ARPACK's mode 3 applies M itself).
  void perform_op(const double* x_in, double* y_out) const {
    factor().solve(x_in, y_out);
    count_solve();
  }
  /// y = C x = L^-1 P M P^T L^-T x, the symmetric form of OP (see the top of the file); on a factor
  /// with constraints Q L^-1 P M P^T L^-T Q, Q the projector of constrained_factor.hpp.
  void perform_symmetric_op(const double* x_in, double* y_out) const {
    const Eigen::MatrixXd z = factor().backward(Eigen::Map<const Eigen::VectorXd>(x_in, rows()));
    const Eigen::MatrixXd mz = pencil_.mass_times(z);
    Eigen::Map<Eigen::VectorXd>(y_out, rows()) = factor().forward(mz);
    count_solve();
  }
  /// The same for a block of columns: one solve with as many right-hand sides (block_lanczos.hpp).
  void perform_symmetric_block(const Eigen::MatrixXd& x, Eigen::MatrixXd& y) const {
    y = factor().forward(pencil_.mass_times(factor().backward(x)));
    for (Eigen::Index j = 0; j < x.cols(); ++j) count_solve();
  }
  /// The eigenvectors x = P^T L^-T y of OP from those y of C, in place, a few columns at a time (the
  /// solve's temporaries stay small beside the factor).
  void to_vectors_of_op(Eigen::MatrixXd& y) const {
    constexpr Eigen::Index kColumns = 8;
    for (Eigen::Index j = 0; j < y.cols(); j += kColumns) {
      const Eigen::Index count = std::min(kColumns, y.cols() - j);
      y.middleCols(j, count) = factor().backward(y.middleCols(j, count));
    }
  }

  /// Start of a Lanczos run with a basis of `basis` vectors for `wanted` values; `progress` may be empty.
  /// The run takes the basis (plus the start vector) and then basis - wanted solves per restart: one
  /// restart is expected (as seen on solids: 81 solves for 30 modes with a basis of 50), and each one
  /// beyond adds basis - wanted to the expected count, so that the bar does not sit at 100 %.
  void start_run(int basis, int wanted, const EigenProgress* progress) {
    run_start_ = solves_;
    run_per_restart_ = std::max(1, basis - wanted);
    run_expected_ = basis + 1 + run_per_restart_;
    progress_ = progress && *progress ? *progress : EigenProgress{};
  }
  /// The run takes on a larger request (an fmax band's growing block run): `added` more basis columns and
  /// then `per_restart` solves per restart are expected; the count goes on (one bar for the run).
  void extend_run(int added, int per_restart) {
    run_expected_ = std::max(run_expected_, solves_ - run_start_) + added;
    run_per_restart_ = std::max(1, per_restart);
  }

 private:
  const ConstrainedFactor& factor() const { return given_ ? *given_ : *factor_; }
  void count_solve() const {
    ++solves_;
    const int done = solves_ - run_start_;
    if (done > run_expected_) run_expected_ += run_per_restart_;
    if (progress_ && done % 8 == 0) progress_(done, run_expected_);
  }

  void factorize(double sigma) {
    if (!factor_) throw Error("internal: the shift of an eigen-solve on a given factorization cannot move");
    // At the pencil's own shift its matrix is factored as it is; another shift needs a new one.
    const bool ok =
        sigma == pencil_.sigma_a ? factor_->factorize(pencil_.a) : factor_->factorize(pencil_.shifted(sigma));
    if (!ok) {
      std::string where;
      if (const Eigen::Index dof = factor_->failed_dof(); dof >= 0) {
        where = ", pivot of DOF " + std::to_string(dof) + " of " + std::to_string(rows());
      }
      throw Error(
          "the mass matrix is not positive definite or the stiffness matrix is not positive semi-definite "
          "(factorization of K - sigma M failed at shift sigma = " +
          str(sigma) + " rad^2/s^2" + where + ")");
    }
    sigma_ = sigma;
  }

  const Pencil& pencil_;
  std::shared_ptr<ConstrainedFactor> factor_;       ///< own factorization of K - sigma M, or ...
  std::shared_ptr<const ConstrainedFactor> given_;  ///< ... the caller's of K (constrained or not)
  double sigma_ = std::numeric_limits<double>::quiet_NaN();
  mutable int solves_ = 0;
  int run_start_ = 0;
  mutable int run_expected_ = 0;
  int run_per_restart_ = 1;
  EigenProgress progress_;
};

/// Eigenpairs as a backend returns them (any order, vectors not yet checked).
struct RawModes {
  Eigen::VectorXd values;
  Eigen::MatrixXd vectors;
};

/// Lanczos basis size: ncv = max(1.5 nev + 1, nev + 20), at most n. With full re-orthogonalization the
/// cost grows as n ncv^2; measured on a 60,006-DOF beam for 206 modes (bench/condense_beam.cpp), both
/// converge in one pass without restarts: 2 nev + 1 took 18.9 s, 1.5 nev + 1 took 10.4 s, 1.2 nev
/// 11.3 s, 3 nev 42 s. A run that does not converge is retried with a doubled basis.
int lanczos_size(int nev, int n) {
  return std::min(n, std::max(3 * nev / 2 + 1, nev + 20));
}

/// Block Lanczos: blocks of b = nev / 16 columns, 6 to 12 (a free part's six rigid-body modes share one
/// eigenvalue: a block Krylov space holds up to b copies of a multiple eigenvalue), and a basis of
/// max(1.5 nev, nev + 7 b). Measured (one core; bench/README.md): 30 modes of 47k-DOF solids, b = 5 to
/// 10 and bases of 72 to 120: b = 6 and 96 fastest (2.09 s; 72: 2.36 s; Spectra 3.57 s); of the 240k-DOF
/// engine block, b = 6: bases of 96 / 72 / 60 took 10.3 / 10.6 / 11.8 s at a peak of 1,306 / 1,262 /
/// 1,240 MiB (Spectra: 14.6 s, 1,263 MiB) - 72 keeps Spectra's memory; 206 modes of the 60k-DOF beam, b
/// = 6 to 32 and bases of 309 to 412: b = 12 and 309-340 best (4.1-4.2 s; 4.4-6.3 s otherwise; Spectra
/// 8.0 s).
int block_lanczos_block(int nev) {
  return std::clamp(nev / 16, 6, 12);
}
int block_lanczos_basis(int nev) {
  return std::max(3 * nev / 2, nev + 7 * block_lanczos_block(nev));
}

/// Spectra's OpType concept for the symmetric form C of the shift-invert operator.
/// With `deflate` (orthonormal eigenvectors Y of C found before), C restricted to their orthogonal
/// complement, (1 - Y Y^T) C (1 - Y Y^T): Y's eigenvalues become 0, so the run finds the next ones
/// (Saad, Numerical Methods for Large Eigenvalue Problems, 2nd ed., 2011, sec. 4.2, Wielandt/projection
/// deflation). A pass that grows the count of an fmax request solves only for the new modes.
struct SymmetricShiftInvert {
  using Scalar = double;
  const ShiftInvertOperator& op;
  const Eigen::MatrixXd* deflate = nullptr;
  mutable Eigen::VectorXd projected_{};  // scratch of the deflated product
  Eigen::Index rows() const { return op.rows(); }
  Eigen::Index cols() const { return op.cols(); }
  void perform_op(const double* x_in, double* y_out) const {
    if (!deflate || deflate->cols() == 0) {
      op.perform_symmetric_op(x_in, y_out);
      return;
    }
    const Eigen::Map<const Eigen::VectorXd> x(x_in, rows());
    projected_.noalias() = x - *deflate * (deflate->transpose() * x);  // no allocation after the first
    op.perform_symmetric_op(projected_.data(), y_out);
    Eigen::Map<Eigen::VectorXd> y(y_out, rows());
    y -= *deflate * (deflate->transpose() * y);
  }
};

/// Spectra: SymEigsSolver on C, largest nu = 1 / (lambda - sigma) first; lambda = sigma + 1 / nu and
/// x = P^T L^-T y.
/// `deflate`: see SymmetricShiftInvert. `vectors_of_c`: if given, receives the run's eigenvectors of C (to
/// deflate a later run with).
RawModes solve_spectra(ShiftInvertOperator& op, int nev, double tolerance,
                       const Eigen::MatrixXd* deflate = nullptr, Eigen::MatrixXd* vectors_of_c = nullptr) {
  using Solver = Spectra::SymEigsSolver<SymmetricShiftInvert>;
  const int n = static_cast<int>(op.rows());
  SymmetricShiftInvert c{op, deflate};
  // A non-converged run is retried with a doubled Lanczos basis (up to n).
  RawModes modes;
  for (int ncv = lanczos_size(nev, n);; ncv = std::min(n, 2 * ncv)) {
    Solver solver(c, nev, ncv);
    solver.init();
    const Eigen::Index converged = solver.compute(Spectra::SortRule::LargestMagn, kMaxRestarts, tolerance,
                                                  Spectra::SortRule::LargestAlge);
    if (solver.info() == Spectra::CompInfo::Successful) {
      modes.values = (op.shift() + solver.eigenvalues().array().inverse()).matrix();
      modes.vectors = solver.eigenvectors();
      if (vectors_of_c) *vectors_of_c = modes.vectors;
      break;  // the solver and its Lanczos basis go before the vectors are transformed
    }
    if (ncv == n || solver.info() != Spectra::CompInfo::NotConverging) {
      throw Error(
          "the shift-invert Lanczos iteration (Spectra) did not converge: " + std::to_string(converged) +
          " of " + std::to_string(nev) + " eigenvalues converged with " + std::to_string(ncv) +
          " Lanczos vectors after " + std::to_string(solver.num_iterations()) + " restarts");
    }
  }
  op.to_vectors_of_op(modes.vectors);
  return modes;
}

/// Block Lanczos (block_lanczos.hpp) on C, as solve_spectra: largest nu = 1 / (lambda - sigma) first,
/// lambda = sigma + 1 / nu and x = P^T L^-T y; `deflate` and `vectors_of_c` as there. `all_converged`
/// (fmax passes): every leading converged Ritz pair of the basis, at least nev - the basis holds nev + 7
/// blocks, and the pairs beyond nev that have converged by then come free, so the pass reaches further.
/// `grow` (an fmax request's runs that are not deflated): BlockLanczosOptions::grow, on the values of C.
RawModes solve_block_lanczos(
    ShiftInvertOperator& op, int nev, double tolerance, const Eigen::MatrixXd* deflate = nullptr,
    Eigen::MatrixXd* vectors_of_c = nullptr, bool all_converged = false,
    std::function<BlockLanczosGrowth(const Eigen::VectorXd&, Eigen::Index)> grow = {}) {
  BlockLanczosOptions options;
  options.all_converged = all_converged;
  options.grow = std::move(grow);
  options.tolerance = tolerance;
  options.deflate = deflate;
  options.block_size = block_lanczos_block(nev);
  options.basis_size = block_lanczos_basis(nev);
  // A problem too small for the blocks (nev + 3 b beyond its size less the deflated modes) goes to the
  // single-vector Lanczos solver.
  const Eigen::Index room = op.rows() - (deflate ? deflate->cols() : 0);
  if (nev + 3 * options.block_size > room) return solve_spectra(op, nev, tolerance, deflate, vectors_of_c);
  const auto apply = [&op](const Eigen::MatrixXd& x, Eigen::MatrixXd& y) {
    op.perform_symmetric_block(x, y);
  };
  BlockLanczosResult found = block_lanczos(op.rows(), apply, nev, options);
  RawModes modes;
  modes.values = (op.shift() + found.values.array().inverse()).matrix();
  if (vectors_of_c) *vectors_of_c = found.vectors;
  modes.vectors = std::move(found.vectors);
  op.to_vectors_of_op(modes.vectors);
  return modes;
}

std::string arpack_message(const char* routine, int info) {
  std::string what;
  switch (info) {
    case 1:
      what = "maximum number of restarts reached";
      break;
    case 3:
      what = "no shifts could be applied during a restart (the Lanczos basis NCV is too small)";
      break;
    case -1:
      what = "N must be positive";
      break;
    case -2:
      what = "NEV must be positive";
      break;
    case -3:
      what = "NCV must be greater than NEV and at most N";
      break;
    case -4:
      what = "the maximum number of iterations must be positive";
      break;
    case -5:
      what = "WHICH must be one of LM, SM, LA, SA or BE";
      break;
    case -6:
      what = "BMAT must be I or G";
      break;
    case -7:
      what = "the length of the private work array WORKL is not sufficient";
      break;
    case -8:
      what = "error return from the LAPACK tridiagonal eigenvalue calculation";
      break;
    case -9:
      what = "the starting vector is zero";
      break;
    case -10:
      what = "IPARAM(7) (mode) must be 1 to 5";
      break;
    case -11:
      what = "mode 1 and BMAT = G are incompatible";
      break;
    case -12:
      what = "IPARAM(1) (shift strategy) must be 0 or 1";
      break;
    case -13:
      what = "NEV and WHICH = BE are incompatible";
      break;
    case -14:
      what = "dsaupd did not find any eigenvalues to sufficient accuracy";
      break;
    case -15:
      what = "HOWMNY must be A or S when eigenvectors are requested";
      break;
    case -16:
      what = "HOWMNY = S is not supported by this ARPACK";
      break;
    case -17:
      what = "dseupd found a different number of converged Ritz values than dsaupd";
      break;
    case -9999:
      what = "could not build a Lanczos factorization";
      break;
    default:
      what = "unknown error";
      break;
  }
  return std::string("ARPACK ") + routine + " failed with info = " + std::to_string(info) + ": " + what;
}

/// ARPACK: dsaupd in generalized shift-invert mode 3 (BMAT = G, WHICH = LM, OP = (K - sigma M)^-1 M,
/// B = M), then dseupd for the Ritz vectors and lambda = sigma + 1 / nu.
RawModes solve_arpack(ShiftInvertOperator& op, const Pencil& pencil, int nev, double tolerance) {
  const a_int n = static_cast<a_int>(pencil.rows());
  const auto mass = [&](const double* x, double* y) {
    Eigen::Map<Eigen::VectorXd>(y, n) = pencil.mass_times(Eigen::Map<const Eigen::VectorXd>(x, n));
  };
  for (a_int ncv = lanczos_size(nev, n);; ncv = std::min(n, 2 * ncv)) {
    const a_int lworkl = ncv * (ncv + 8);
    std::vector<double> resid(n), v(static_cast<std::size_t>(n) * ncv),
        workd(3 * static_cast<std::size_t>(n)), workl(lworkl), mx(n);
    // Deterministic starting vector (ARPACK's own random one depends on earlier calls in the process).
    std::uint64_t state = 0x2545F4914F6CDD1DULL;
    for (double& r : resid) {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      r = static_cast<double>(state >> 11) / 9007199254740992.0 - 0.5;
    }
    a_int iparam[11] = {};
    a_int ipntr[11] = {};
    iparam[0] = 1;             // exact shifts
    iparam[2] = kMaxRestarts;  // maximum number of restarts
    iparam[3] = 1;             // block size
    iparam[6] = 3;             // mode 3: shift-invert for K x = lambda M x
    a_int ido = 0;
    a_int info = 1;  // resid holds the starting vector
    for (;;) {
      arpack::saupd(ido, arpack::bmat::generalized, n, arpack::which::largest_magnitude, nev, tolerance,
                    resid.data(), ncv, v.data(), n, iparam, ipntr, workd.data(), workl.data(), lworkl, info);
      double* x = workd.data() + ipntr[0] - 1;
      double* y = workd.data() + ipntr[1] - 1;
      if (ido == -1) {  // y = OP x = (K - sigma M)^-1 M x (initialization: no B x available)
        mass(x, mx.data());
        op.perform_op(mx.data(), y);
      } else if (ido == 1) {  // y = (K - sigma M)^-1 z with z = M x already in workd(ipntr(3))
        op.perform_op(workd.data() + ipntr[2] - 1, y);
      } else if (ido == 2) {  // y = M x
        mass(x, y);
      } else {
        break;  // ido == 99: done (or an error in info)
      }
    }
    if ((info == 1 || info == 3) && ncv < n) continue;  // retry with a larger basis
    if (info != 0) {
      throw Error(arpack_message("dsaupd", info) + " (" + std::to_string(iparam[4]) + " of " +
                  std::to_string(nev) + " eigenvalues converged, NCV = " + std::to_string(ncv) + ")");
    }
    std::vector<a_int> select(ncv);
    RawModes modes{Eigen::VectorXd(nev), Eigen::MatrixXd(n, nev)};
    arpack::seupd(1, arpack::howmny::ritz_vectors, select.data(), modes.values.data(), modes.vectors.data(),
                  n, op.shift(), arpack::bmat::generalized, n, arpack::which::largest_magnitude, nev,
                  tolerance, resid.data(), ncv, v.data(), n, iparam, ipntr, workd.data(), workl.data(),
                  lworkl, info);
    if (info != 0) throw Error(arpack_message("dseupd", info));
    const a_int converged = iparam[4];
    if (converged < nev) {
      throw Error("ARPACK converged only " + std::to_string(converged) + " of " + std::to_string(nev) +
                  " eigenvalues");
    }
    return modes;
  }
}

/// All eigenpairs on dense copies (Cholesky of M, then a standard symmetric eigenproblem). With
/// constraints C x = 0, on the null space of C: x = N z with N the orthonormal complement of the range
/// of C^T (the last n - m columns of the Householder Q of C^T), (N^T K N) z = lambda (N^T M N) z.
RawModes solve_dense(const Pencil& pencil) {
  Eigen::MatrixXd k = pencil.dense_stiffness();
  Eigen::MatrixXd m = pencil.dense_mass();
  Eigen::MatrixXd null_space;
  if (pencil.constraints) {
    const Eigen::Index n = pencil.rows(), c = pencil.constraints->rows();
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr{Eigen::MatrixXd(pencil.constraints->transpose())};
    null_space = (qr.householderQ() * Eigen::MatrixXd::Identity(n, n)).rightCols(n - c);
    k = null_space.transpose() * k * null_space;
    m = null_space.transpose() * m * null_space;
    k = 0.5 * (k + k.transpose()).eval();
    m = 0.5 * (m + m.transpose()).eval();
  }
  if (Eigen::LLT<Eigen::MatrixXd>(m).info() != Eigen::Success) {
    throw Error("the mass matrix is not positive definite (its dense Cholesky factorization failed)");
  }
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(
      k, m, Eigen::ComputeEigenvectors | Eigen::Ax_lBx);
  if (solver.info() != Eigen::Success) throw Error("the dense generalized eigensolver did not converge");
  if (null_space.cols() > 0) return {solver.eigenvalues(), null_space * solver.eigenvectors()};
  return {solver.eigenvalues(), solver.eigenvectors()};
}

/// Automatic shift (see EigenRequest::shift). With fmax: -(2 pi f_s)^2, f_s = max(1 Hz, fmax / 100).
/// With a mode count only: each diagonal ratio K_ii / M_ii is a Rayleigh quotient, so the smallest one
/// bounds lambda_1 from above, and the largest is of the order of lambda_max. sigma = -1e-3 min K_ii /
/// M_ii keeps the shift below the lowest modes - but on solids that bound is poor (a thin plate's
/// through-thickness stiffness: min K_ii / M_ii is 1e5 times lambda_1 on NAFEMS FV12), and a shift far
/// beyond the wanted band crowds their transformed eigenvalues 1 / (lambda - sigma) together: the
/// Lanczos iteration then needs many restarts (FV12: 9 s instead of 0.6 s). So the shift is at most
/// 1e-9 max K_ii / M_ii, within the band for meshes whose spectrum spans up to 9 decades (FV12:
/// sigma = -1.3 lambda_1, the engine block of bench/: -0.01 lambda_1), and at least 1e-10 max K_ii /
/// M_ii away from zero for a well-conditioned factorization (condition of K - sigma M about 1e10). A shift
/// that still lies far beyond the band found is moved after the first pass (shift_fits in
/// solve_eigenproblem).
double automatic_shift(const SparseMatrix& K, const SparseMatrix& M, const EigenRequest& request) {
  if (request.modes <= 0) return -eigenvalue_of_hz(std::max(1.0, request.fmax_hz / 100.0));
  double lowest = std::numeric_limits<double>::infinity();
  double highest = 0.0;
  for (Eigen::Index i = 0; i < K.rows(); ++i) {
    const double ratio = K.coeff(i, i) / M.coeff(i, i);
    if (ratio > 0.0) {
      lowest = std::min(lowest, ratio);
      highest = std::max(highest, ratio);
    }
  }
  if (highest == 0.0) return -1.0;  // K has no stiffness on its diagonal (K = 0): every lambda is 0
  return -std::max(std::min(1e-3 * lowest, 1e-9 * highest), 1e-10 * highest);
}

/// Relative residual of each eigenpair, ||K x - lambda M x|| / (||K x|| + |lambda| ||M x|| +
/// sqrt(eps) ||K||_1 ||x||). The last term is the round-off floor of K x: for rigid modes K x and lambda
/// are both round-off. Products with 8 vectors at a time (one pass over the matrices for all 8).
Eigen::VectorXd relative_residuals(const Pencil& pencil, const RawModes& modes) {
  constexpr Eigen::Index kColumns = 8;
  const double floor = std::sqrt(kEpsilon) * pencil.k_norm1;
  const Eigen::Index count = modes.values.size();
  Eigen::VectorXd residuals(count);
  for (Eigen::Index first = 0; first < count; first += kColumns) {
    const Eigen::Index columns = std::min(kColumns, count - first);
    const auto x = modes.vectors.middleCols(first, columns);
    const Eigen::MatrixXd mx = pencil.mass_times(x);
    const Eigen::MatrixXd kx = pencil.stiffness_times(x, mx);
    for (Eigen::Index j = 0; j < columns; ++j) {
      const double lambda = modes.values[first + j];
      Eigen::VectorXd r = kx.col(j) - lambda * mx.col(j);
      // With constraints the residual's part C^T mu is the constraint force, not an error.
      r = pencil.outside_constraint_range(r);
      residuals[first + j] =
          r.norm() / (kx.col(j).norm() + std::abs(lambda) * mx.col(j).norm() + floor * x.col(j).norm());
    }
  }
  return residuals;
}

double worst_residual(const Pencil& pencil, const RawModes& modes) {
  return modes.values.size() ? relative_residuals(pencil, modes).maxCoeff() : 0.0;
}

void check_input(const SparseMatrix& K, const SparseMatrix& M, const EigenRequest& request) {
  if (K.rows() != K.cols() || M.rows() != M.cols() || K.rows() != M.rows()) {
    throw Error("the stiffness and mass matrices must be square and of equal size (K is " +
                std::to_string(K.rows()) + " x " + std::to_string(K.cols()) + ", M is " +
                std::to_string(M.rows()) + " x " + std::to_string(M.cols()) + ")");
  }
  const Eigen::Index n = K.rows();
  if (n == 0) throw Error("the eigenproblem is empty (the model has no degrees of freedom)");
  if (request.modes < 0)
    throw Error("the number of modes must not be negative (got " + std::to_string(request.modes) + ")");
  if (request.modes == 0 && !(request.fmax_hz > 0.0)) {
    throw Error("the eigenvalue request needs a number of modes or a positive fmax (got modes = 0, fmax = " +
                str(request.fmax_hz) + " Hz)");
  }
  if (request.modes > n) {
    throw Error(std::to_string(request.modes) + " modes requested but the model has only " +
                std::to_string(n) + " degrees of freedom");
  }
  if (!(request.shift <= 0.0)) {
    throw Error("the eigenvalue shift must be negative (or 0 for automatic), got " + str(request.shift));
  }
  if (!(request.tolerance > 0.0))
    throw Error("the eigenvalue tolerance must be positive, got " + str(request.tolerance));
  if (!(request.residual_limit > 0.0)) {
    throw Error("the eigenvalue residual limit must be positive, got " + str(request.residual_limit));
  }
  if (!all_finite(K)) throw Error("the stiffness matrix contains non-finite entries");
  if (!all_finite(M)) throw Error("the mass matrix contains non-finite entries");
  for (Eigen::Index i = 0; i < n; ++i) {
    if (const double m = M.coeff(i, i); !(m > 0.0)) {
      throw Error("the mass matrix is not positive definite (diagonal entry of DOF " + std::to_string(i) +
                  " is " + str(m) + ")");
    }
    if (const double k = K.coeff(i, i); k < 0.0) {
      throw Error("the stiffness matrix is not positive semi-definite (diagonal entry of DOF " +
                  std::to_string(i) + " is " + str(k) + ")");
    }
  }
  // Every 2 x 2 principal submatrix of a positive definite matrix is positive definite: a cheap O(nnz)
  // necessary condition that catches a wrong sign or scale of a coupling mass term.
  const Eigen::VectorXd diagonal = M.diagonal();
  for (Eigen::Index j = 0; j < M.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(M, j); it; ++it) {
      const Eigen::Index i = it.row();
      if (i != j && !(it.value() * it.value() < diagonal[i] * diagonal[j])) {
        throw Error("the mass matrix is not positive definite (M_ij^2 >= M_ii M_jj for the DOFs i = " +
                    std::to_string(i) + ", j = " + std::to_string(j) + ": M_ij = " + str(it.value()) +
                    ", M_ii = " + str(diagonal[i]) + ", M_jj = " + str(diagonal[j]) + ")");
      }
    }
  }
}

/// Sorts the eigenpairs ascending and keeps the first `count`.
RawModes sorted(const RawModes& modes, Eigen::Index count) {
  std::vector<Eigen::Index> order(static_cast<std::size_t>(modes.values.size()));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](Eigen::Index a, Eigen::Index b) { return modes.values[a] < modes.values[b]; });
  count = std::min<Eigen::Index>(count, modes.values.size());
  RawModes result{Eigen::VectorXd(count), Eigen::MatrixXd(modes.vectors.rows(), count)};
  for (Eigen::Index j = 0; j < count; ++j) {
    result.values[j] = modes.values[order[static_cast<std::size_t>(j)]];
    result.vectors.col(j) = modes.vectors.col(order[static_cast<std::size_t>(j)]);
  }
  return result;
}

/// X^T M X = I: each vector normalized in the M norm; within a cluster of equal eigenvalues (relative
/// gap <= 1e-8, or absolute gap <= `absolute_gap` for the rigid modes near zero) modified Gram-Schmidt
/// in the M inner product, applied twice.
void m_orthonormalize(const Eigen::VectorXd& values, Eigen::MatrixXd& vectors, const Pencil& pencil,
                      double absolute_gap) {
  const Eigen::Index count = values.size();
  Eigen::MatrixXd mx(vectors.rows(), count);  // M x of the finished vectors of the current cluster
  const auto normalize = [&](Eigen::Index j, double reference) {
    mx.col(j) = pencil.mass_times(vectors.col(j));
    const double q = vectors.col(j).dot(mx.col(j));
    if (!(q > 0.0) || !std::isfinite(q)) {
      throw Error("the mass matrix is not positive definite (x^T M x = " + str(q) +
                  " for the eigenvector of mode " + std::to_string(j + 1) + ")");
    }
    if (std::sqrt(q) < 1e-6 * reference) {
      throw Error("the eigensolver returned mode " + std::to_string(j + 1) +
                  " twice (its vector is linearly dependent on the other vectors of its cluster)");
    }
    vectors.col(j) /= std::sqrt(q);
    mx.col(j) /= std::sqrt(q);
  };
  for (Eigen::Index first = 0; first < count;) {
    Eigen::Index end = first + 1;
    while (end < count &&
           values[end] - values[end - 1] <=
               1e-8 * std::max(std::abs(values[end]), std::abs(values[end - 1])) + absolute_gap) {
      ++end;
    }
    for (Eigen::Index j = first; j < end; ++j) {
      normalize(j, 0.0);
      for (int pass = 0; pass < 2 && end - first > 1; ++pass) {
        for (Eigen::Index i = first; i < j; ++i)
          vectors.col(j) -= mx.col(i).dot(vectors.col(j)) * vectors.col(i);
        normalize(j, 1.0);
      }
    }
    first = end;
  }
}

/// The kLobpcg backend on the pencil's A = K - sigma M (positive definite: sigma < 0) and M: the pencil
/// renumbered along the coarse space's Z-order curve for the iteration and back afterwards; the
/// eigenvalues lambda = mu + sigma, the vectors in the model's numbering. The modes' tolerance is half
/// the residual limit that solve_eigenproblem checks them against (the same relative residual, up to the
/// round-off term).
RawModes solve_lobpcg(Pencil& pencil, const EigenRequest& request, EigenResult& result) {
  if (!request.coarse_space)
    throw Error(
        "the lobpcg eigensolver needs a volume component meshed with second-order tetrahedra (C3D10)");
  if (request.stiffness_factor) throw Error("internal: the lobpcg eigensolver is not for a given factor");
  const auto start = std::chrono::steady_clock::now();
  const CoarseSpace& space = *request.coarse_space;
  const Eigen::Index n = pencil.rows();
  if (static_cast<Eigen::Index>(space.new_index.size()) != n)
    throw Error("internal: the coarse space does not match the model's free DOF");
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> renumbering(n);
  std::copy(space.new_index.begin(), space.new_index.end(), renumbering.indices().data());
  // For the iteration A and M are renumbered and stored whole (the block product's fast form), and given
  // back to the pencil as lower triangles in the model's numbering afterwards. twistedBy leaves each
  // column's rows unsorted; a transpose sorts them.
  for (SparseMatrix* a : {&pencil.a, &pencil.m}) {
    SparseMatrix whole = renumbered_whole(std::move(*a), space.new_index);
    a->swap(whole);
  }
  LobpcgResult found;
  {
    // 10 guard vectors: measured best on the plain block at 109k DOF (6 guards 19 iterations instead of 16,
    // 16 guards 20 % more time).
    const PMultigrid preconditioner(pencil.a, space.prolongation, PMultigrid::kDegree, request.ordering,
                                    space.coarse_only);
    // The start block: the coarse level's own lowest modes (TET4 on the vertices, P^T A P and P^T M P, by
    // shift-invert Lanczos on their small factor, Lanczos tolerance 1e-4), prolonged. Measured on the plain
    // block at 237k DOF: 13 iterations instead of 16 from random vectors, for a coarse eigen-solve of 3.2 s
    // (95 solves): 34 instead of 36 s in all.
    // A free part: its rigid-body modes (known exactly) are kept out of the iteration, M-orthonormal, and
    // given back with lambda = 0; the iteration seeks the elastic ones.
    LobpcgConstraints rigid;
    const int r = static_cast<int>(space.rigid_modes.cols());
    if (r > 0) {
      rigid.y = space.rigid_modes;
      symmetric_block_product(pencil.m, rigid.y, rigid.my);
      const Eigen::MatrixXd g = rigid.y.transpose() * rigid.my;
      const Eigen::MatrixXd u_inverse =
          Eigen::LLT<Eigen::MatrixXd>(g).matrixU().solve(Eigen::MatrixXd::Identity(r, r));
      rigid.y = rigid.y * u_inverse;
      rigid.my = rigid.my * u_inverse;
    }
    const bool by_count = request.modes > 0;
    const int guard = 10;
    // An fmax request: mu = lambda - sigma up to mu_max. The coarse level's eigenvalues are Rayleigh-Ritz
    // values of the fine pencil (Galerkin), so each lies above its fine one: the coarse modes up to
    // 1.05 fmax give the first run's count, and lobpcg_up_to adds runs until the band is covered. (On the
    // plain block of bench/ the coarse frequencies lie 1-3 % above the fine ones: up to 1.2 fmax the first
    // run sought 40 modes for 30, 54 s instead of 33 s at 237k DOF.)
    constexpr double kCoarseBand = 1.05;
    const double mu_max = by_count ? 0.0 : eigenvalue_of_hz(request.fmax_hz) - pencil.sigma_a;
    int elastic = request.modes - r;
    if (by_count && elastic < 1) throw Error("the lobpcg eigensolver: no elastic mode requested");
    Block start;
    const SparseMatrix& p = space.prolongation;
    if (preconditioner.coarse_rows() > 3 * ((by_count ? elastic + guard : kInitialModes) + r)) {
      SparseMatrix coarse_mass = SparseMatrix(p.transpose()) * (pencil.m * p);
      coarse_mass = coarse_mass.triangularView<Eigen::Lower>();
      EigenRequest coarse;
      if (by_count)
        coarse.modes = elastic + guard + r;  // the coarse space holds the rigid motions too: they come first
      else
        coarse.fmax_hz = frequency_hz(kCoarseBand * kCoarseBand * mu_max);
      coarse.lower_triangles = true;
      coarse.ordering = request.ordering;
      coarse.stiffness_factor = preconditioner.coarse_factor();  // shift 0 on the preconditioner's factor
      coarse.residual_limit = 1e-3;                              // a start, not a result
      coarse.tolerance = 1e-4;
      const EigenResult modes = solve_eigenproblem(preconditioner.coarse_matrix(), coarse_mass, coarse);
      const Eigen::Index available = modes.eigenvalues.size() - r;
      if (!by_count) elastic = static_cast<int>(std::max<Eigen::Index>(available, 1));
      const Eigen::Index columns = std::min<Eigen::Index>({available, elastic + guard, pencil.rows() / 3});
      if (columns > 0) start = p * modes.vectors.middleCols(r, columns);
    } else if (!by_count) {
      elastic = kInitialModes;  // a small model: from random vectors, the count from the first run on
    }
    const double tolerance = 0.5 * request.residual_limit;
    const LobpcgConstraints* constraints = r > 0 ? &rigid : nullptr;
    found = by_count ? lobpcg(pencil.a, pencil.m, preconditioner, elastic, tolerance, guard, 500,
                              &request.progress, std::move(start), constraints)
                     : lobpcg_up_to(pencil.a, pencil.m, preconditioner, mu_max, elastic, tolerance, guard,
                                    500, &request.progress, std::move(start), constraints);
    if (r > 0) {  // the rigid-body modes first, at their Rayleigh quotients (0 to round-off)
      const Eigen::MatrixXd ay = [&] {
        Block out;
        symmetric_block_product(pencil.a, rigid.y, out);
        return Eigen::MatrixXd(rigid.y.transpose() * out);
      }();
      const Eigen::Index total = r + found.values.size();
      Eigen::VectorXd values(total);
      values << ay.diagonal(), found.values;
      Eigen::MatrixXd vectors(pencil.rows(), total);
      vectors << Eigen::MatrixXd(rigid.y), found.vectors;
      found.values = values;
      found.vectors = vectors;
    }
    result.factor = preconditioner.coarse_factor_stats();
  }
  for (SparseMatrix* a : {&pencil.a, &pencil.m}) {
    SparseMatrix lower(a->rows(), a->cols());
    lower.selfadjointView<Eigen::Lower>() =
        a->selfadjointView<Eigen::Lower>().twistedBy(renumbering.inverse());
    SparseMatrix().swap(*a);
    const SparseMatrix upper = lower.transpose();
    SparseMatrix().swap(lower);
    *a = upper.transpose();
  }
  RawModes raw;
  raw.values = (found.values.array() + pencil.sigma_a).matrix();
  raw.vectors = renumbering.inverse() * found.vectors;
  result.shift = pencil.sigma_a;
  result.matrix_operations = found.iterations;
  result.iteration_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() -
                             result.factor.factor_seconds;
  return raw;
}

}  // namespace

EigenBackend parse_eigen_backend(const std::string& name) {
  if (name == "spectra") return EigenBackend::kSpectra;
  if (name == "arpack") return EigenBackend::kArpack;
  if (name == "dense") return EigenBackend::kDense;
  if (name == "lobpcg") return EigenBackend::kLobpcg;
  if (name == "block-lanczos") return EigenBackend::kBlockLanczos;
  throw Error("unknown eigensolver backend '" + name +
              "' (expected one of: spectra, block-lanczos, arpack, dense, lobpcg)");
}

std::string to_string(EigenBackend backend) {
  switch (backend) {
    case EigenBackend::kSpectra:
      return "spectra";
    case EigenBackend::kArpack:
      return "arpack";
    case EigenBackend::kDense:
      return "dense";
    case EigenBackend::kLobpcg:
      return "lobpcg";
    case EigenBackend::kBlockLanczos:
      return "block-lanczos";
  }
  return "unknown";
}

double frequency_hz(double eigenvalue) {
  return eigenvalue > 0.0 ? std::sqrt(eigenvalue) / kTwoPi : 0.0;
}

double eigenvalue_of_hz(double hz) {
  return (kTwoPi * hz) * (kTwoPi * hz);
}

double growth_exponent(const Eigen::VectorXd& values) {
  std::vector<double> sorted(values.data(), values.data() + values.size());
  std::sort(sorted.begin(), sorted.end());
  const std::size_t top = sorted.size() - 1, middle = sorted.size() / 2;
  if (sorted.size() < 6 || !(sorted[middle] > 1e-6 * sorted[top])) return 0.5;
  const double p = std::log((top + 1.0) / (middle + 1.0)) / std::log(sorted[top] / sorted[middle]);
  return std::isfinite(p) ? std::clamp(p, 0.25, 1.5) : 0.5;
}

EigenResult solve_eigenproblem(const SparseMatrix& K, const SparseMatrix& M, const EigenRequest& request) {
  return solve_eigenproblem(SparseMatrix(K), SparseMatrix(M), request);
}

EigenResult solve_eigenproblem(SparseMatrix&& K, SparseMatrix&& M, const EigenRequest& request) {
  check_input(K, M, request);
  if (!request.lower_triangles) {
    symmetrize(K, "stiffness");
    symmetrize(M, "mass");
  }
  const int n = static_cast<int>(K.rows());

  const bool by_count = request.modes > 0;
  const double lambda_max =
      by_count ? std::numeric_limits<double>::infinity() : eigenvalue_of_hz(request.fmax_hz);
  // The iterative solvers need nev < n - 1; small models are cheaper dense anyway.
  bool dense =
      request.backend == EigenBackend::kDense || n <= kDenseSize || (by_count && request.modes >= n - 1);

  EigenResult result;
  RawModes raw;
  // Eigenvalues closer than this count as equal (rigid modes near 0, whose computed eigenvalues are
  // round-off of the order of eps lambda_max; ||K||_1 / max M_ii is of the order of lambda_max).
  const double max_mass = M.diagonal().maxCoeff();
  // K and M go into the pencil (lower triangles, K as K - sigma M): no more copies from here on.
  const double sigma = dense || request.stiffness_factor ? 0.0
                       : request.shift < 0.0             ? request.shift
                                                         : automatic_shift(K, M, request);
  Pencil pencil;
  make_pencil(K, M, sigma, request.lower_triangles, pencil);
  if (request.stiffness_factor && request.stiffness_factor->constrained()) {
    const SparseMatrix& c = request.stiffness_factor->constraints();
    if (c.cols() != n) throw Error("internal: the constraints of the given factor do not match K");
    pencil.constraints = &c;
    pencil.constraint_gram.compute(Eigen::MatrixXd(c * c.transpose()));
    if (pencil.constraint_gram.info() != Eigen::Success)
      throw Error("internal: the constraints of the given factor are linearly dependent");
  }
  double absolute_gap = 1e-10 * pencil.k_norm1 / max_mass;
  if (!dense && request.backend == EigenBackend::kLobpcg) {
    raw = solve_lobpcg(pencil, request, result);
    absolute_gap = std::max(absolute_gap, 1e-8 * std::abs(sigma));
  } else if (!dense) {
    ShiftInvertOperator op = request.stiffness_factor ? ShiftInvertOperator(pencil, request.stiffness_factor)
                                                      : ShiftInvertOperator(pencil, sigma, request.ordering);
    // The Lanczos runs' time, without refactorizations at a moved shift (counted in the factor's stats).
    const auto iteration_start = std::chrono::steady_clock::now();
    const double factor_seconds_before = op.factor_stats().factor_seconds;
    // Spectra's runs keep their eigenvectors of C (last_c) so that a later pass can deflate them.
    const bool deflating =
        request.backend == EigenBackend::kSpectra || request.backend == EigenBackend::kBlockLanczos;
    Eigen::MatrixXd last_c;
    // An automatic shift is a guess. If all wanted eigenvalues turn out to lie far below |sigma|, their
    // transformed values 1 / (lambda - sigma) crowd together and the vectors converge poorly (seen:
    // residual 1e-2 on a 384-DOF cantilever with sigma = -9e7 and 8 modes up to lambda = 2.4e6). Ritz
    // values converge much faster than vectors, so the first pass tells where the band lies: then move
    // the shift to -lambda_1 (first elastic value; refactorize) and solve again. A band that reaches
    // past |sigma| is spread well enough (206 modes of a 60,006-DOF beam: residuals 5e-9 in one pass).
    const double lambda_floor = 1e-12 * pencil.k_norm1 / max_mass;
    // The shift the eigenvalues found call for, if it is not the present one (NaN if that one fits).
    const auto better_shift = [&](const Eigen::VectorXd& found) {
      constexpr double kFits = std::numeric_limits<double>::quiet_NaN();
      // The user's shift is kept, and so is shift 0 on a given factorization.
      if (request.shift < 0.0 || request.stiffness_factor || found.size() == 0) return kFits;
      const double sigma = std::abs(op.shift());
      if (found.maxCoeff() >= 0.1 * sigma) return kFits;
      double first = std::numeric_limits<double>::infinity();
      for (Eigen::Index i = 0; i < found.size(); ++i)
        if (found[i] > 1e-6 * sigma) first = std::min(first, found[i]);
      if (!std::isfinite(first)) return kFits;  // only rigid-body modes found: nothing to place
      return -std::max(first, lambda_floor);
    };
    // The next count when the highest of `found` (eigenvalues) lies below fmax: the count extrapolated
    // to fmax times a margin, at least `at_least` and one more than found, at most 4 times found (an
    // extrapolation from the lowest few modes over decades of frequency misjudges: the beam of
    // bench_condense_beam to 9.9 kHz asked for 1,149 modes after 20, for 206 in the band, and Spectra
    // took 267 s and 2.3 GB on it) and n - 2.
    const auto next_count = [&](double at_least, double margin, const Eigen::VectorXd& found) {
      const double extrapolated =
          margin * found.size() * std::pow(lambda_max / found.maxCoeff(), growth_exponent(found));
      const double next = std::max(at_least, std::ceil(std::min(extrapolated, 4.0 * found.size())));
      return static_cast<int>(std::min(std::max<double>(next, found.size() + 1), n - 2.0));
    };
    // An fmax request's block runs grow their count in the same Krylov space until the band is covered
    // (the growth of a run that starts with `first` wanted modes); a deflated pass (after a growth that
    // did not fit) starts anew. Measured (bench/README.md): the engine block to 5 kHz, 60 modes, 558
    // solves in three passes, 270 in one growing run, as the count of 60 itself.
    const auto band_growth = [&](int first) {
      return [&, first, wanted = first](const Eigen::VectorXd& theta,
                                        Eigen::Index converged) mutable -> BlockLanczosGrowth {
        // The Ritz values as eigenvalues, lambda = sigma + 1 / theta, ascending; each is an upper
        // bound of its eigenvalue (theta <= 0: none in reach).
        const Eigen::VectorXd ritz =
            (theta.array() > 0).select(op.shift() + theta.array().inverse(), lambda_max * 2).matrix();
        const Eigen::VectorXd found = ritz.head(converged);
        // The band is covered once a converged value lies beyond it (the converged ones are the
        // leading ones: none below is missing). A shift to move ends the run too (the loop below
        // solves again).
        if (converged > 0 && found.maxCoeff() > lambda_max) return {.stop = true};
        if (converged >= wanted && !std::isnan(better_shift(found))) return {.stop = true};
        // At least as many modes lie in the band as Ritz values do (bounds from above): grow early
        // to those, with a block to spare; once the wanted ones have converged below fmax,
        // extrapolate from them as the passes do, with less margin (a growth costs no new run).
        const int b = block_lanczos_block(first);
        const Eigen::Index ritz_in_band = (ritz.array() <= lambda_max).count();
        int next = static_cast<int>(std::clamp<Eigen::Index>(ritz_in_band + b, wanted, n - 2));
        if (converged >= wanted)
          next = std::max(next, next_count(static_cast<double>(converged + b), 1.05, found));
        if (next <= wanted) return {};
        op.extend_run(block_lanczos_basis(next) - block_lanczos_basis(wanted),
                      (block_lanczos_basis(next) - next) / 2);
        wanted = next;
        return {.nev = wanted, .basis_size = block_lanczos_basis(wanted)};
      };
    };
    const auto solve = [&](int nev, const Eigen::MatrixXd* deflate = nullptr) {
      op.start_run(
          request.backend == EigenBackend::kBlockLanczos ? block_lanczos_basis(nev) : lanczos_size(nev, n),
          nev, &request.progress);
      if (request.backend == EigenBackend::kArpack) return solve_arpack(op, pencil, nev, request.tolerance);
      if (request.backend == EigenBackend::kBlockLanczos) {
        std::function<BlockLanczosGrowth(const Eigen::VectorXd&, Eigen::Index)> grow;
        if (!by_count && !deflate) grow = band_growth(nev);
        return solve_block_lanczos(op, nev, request.tolerance, deflate, by_count ? nullptr : &last_c,
                                   !by_count, std::move(grow));
      }
      return solve_spectra(op, nev, request.tolerance, deflate, by_count ? nullptr : &last_c);
    };
    const auto shift_fits = [&](const RawModes& found) {
      const double moved = better_shift(found.values);
      if (std::isnan(moved)) return true;
      op.set_shift(moved);
      return false;
    };
    if (by_count) {
      // One mode more than asked for, when the model has it: it tells whether the count ends inside a
      // group of equal eigenvalues (EigenResult::split_first).
      const int guarded = request.modes + 1 < n - 1 ? request.modes + 1 : request.modes;
      raw = solve(guarded);
      if (!shift_fits(raw)) {
        raw = solve(guarded);
      } else if (request.shift == 0.0 && !request.stiffness_factor &&
                 worst_residual(pencil, raw) > request.residual_limit) {
        // The small automatic shift of a count request (see automatic_shift) conditions K - sigma M
        // poorly when it lies far below lambda_1 (condition lambda_max / |sigma|): on free-free models
        // the rigid-body vectors then miss the residual limit (seen: 3e-5 on a small gmsh block). Now
        // that lambda_1 is known, move the shift to -1e-3 lambda_1 (as fmax / 100 does) and solve again.
        double first = std::numeric_limits<double>::infinity();
        for (Eigen::Index i = 0; i < raw.values.size(); ++i)
          if (raw.values[i] > 1e-3 * std::abs(op.shift())) first = std::min(first, raw.values[i]);
        if (std::isfinite(first) && 1e-3 * first > std::abs(op.shift())) {
          op.set_shift(-1e-3 * first);
          raw = solve(guarded);
        }
      }
    } else {
      // Grow the number of modes until the highest one found lies above fmax (same factorization). Each
      // pass starts a new Lanczos run, so the next count is extrapolated from the spectrum found: the
      // mode count grows like lambda^p (Weyl: p = 1/2 for beams, 1 for plates and shells, 3/2 for
      // solids), p fitted between the middle and the top of the modes found, with 15 % to spare; at
      // least 1.5 times the count.
      // With Spectra a later pass solves only for the modes above those found, on the operator deflated
      // of them (SymmetricShiftInvert), instead of all of them again: its Lanczos basis is the new
      // modes' (measured: the piston to 30 kHz 185 -> 167 solves, the engine block to 5 kHz, 97 modes, 247 ->
      // 218).
      Eigen::MatrixXd found_c;  // eigenvectors of C of the modes in raw
      for (int nev = std::min(kInitialModes, n - 2), pass = 0;; ++pass) {
        if (pass > 0 && deflating) {
          const Eigen::Index k0 = raw.values.size();
          const RawModes more = solve(nev - static_cast<int>(k0), &found_c);
          const Eigen::Index k1 = more.values.size();
          raw.values.conservativeResize(k0 + k1);
          raw.values.tail(k1) = more.values;
          raw.vectors.conservativeResize(Eigen::NoChange, k0 + k1);
          raw.vectors.rightCols(k1) = more.vectors;
          found_c.conservativeResize(Eigen::NoChange, k0 + k1);
          found_c.rightCols(k1) = last_c;
        } else {
          raw = solve(nev);
          if (pass == 0 && !shift_fits(raw)) raw = solve(nev);
          if (deflating) found_c.swap(last_c);
        }
        const double highest = raw.values.maxCoeff();
        if (highest > lambda_max) break;
        if (nev == n - 2 || raw.values.size() >= n - 2) {
          dense = true;  // fmax lies above (nearly) all modes of the model
          break;
        }
        // A block run may have returned more modes than it was asked for (solve_block_lanczos): ask beyond.
        nev = next_count(1.5 * nev, 1.15, raw.values);
      }
    }
    result.shift = op.shift();
    result.matrix_operations = op.solves();
    result.factor = op.factor_stats();
    result.iteration_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - iteration_start).count() -
        (result.factor.factor_seconds - factor_seconds_before);
    absolute_gap = std::max(absolute_gap, 1e-8 * std::abs(op.shift()));
  }
  if (dense) {
    if (request.backend != EigenBackend::kDense && n > kDenseFallbackLimit) {
      const std::string what = by_count
                                   ? std::to_string(request.modes) + " modes requested"
                                   : "fmax = " + str(request.fmax_hz) + " Hz lies above nearly all modes";
      throw Error(what + " of a model with " + std::to_string(n) +
                  " degrees of freedom: that needs the dense eigensolver, and the model is too large for it");
    }
    const auto dense_start = std::chrono::steady_clock::now();
    raw = solve_dense(pencil);
    result.iteration_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - dense_start).count();
    result.shift = 0.0;
    absolute_gap = std::max(absolute_gap, 1e-10 * raw.values.cwiseAbs().maxCoeff());
  }

  // The lowest `modes`, or all with lambda <= (2 pi fmax)^2.
  Eigen::Index count = raw.values.size();
  if (by_count) {
    count = request.modes;
    if (raw.values.size() > count) {  // the guard mode (or all, dense): does the count split a group?
      std::vector<double> v(raw.values.data(), raw.values.data() + raw.values.size());
      std::sort(v.begin(), v.end());
      const auto equal = [&](std::size_t i) {  // v[i] and v[i + 1], as m_orthonormalize's clusters
        return v[i + 1] - v[i] <= 1e-8 * std::max(std::abs(v[i]), std::abs(v[i + 1])) + absolute_gap;
      };
      std::size_t first = static_cast<std::size_t>(count) - 1;
      if (equal(first)) {
        while (first > 0 && equal(first - 1)) --first;
        result.split_first = static_cast<int>(first);
      }
    }
  } else {
    count = (raw.values.array() <= lambda_max).count();
    for (Eigen::Index i = 0; i < raw.values.size(); ++i) {
      if (raw.values[i] > lambda_max && !(raw.values[i] >= result.next_eigenvalue))
        result.next_eigenvalue = raw.values[i];
    }
  }
  RawModes modes = sorted(raw, count);
  if (by_count && modes.values.size() < request.modes) {
    throw Error("the eigensolver returned " + std::to_string(modes.values.size()) + " of " +
                std::to_string(request.modes) + " requested modes");
  }
  if (!modes.values.allFinite()) throw Error("the eigensolver returned non-finite eigenvalues");
  m_orthonormalize(modes.values, modes.vectors, pencil, absolute_gap);

  result.residuals = relative_residuals(pencil, modes);
  for (Eigen::Index j = 0; j < modes.values.size(); ++j) {
    const double lambda = modes.values[j];
    const double residual = result.residuals[j];
    if (!(residual <= request.residual_limit)) {
      throw Error("mode " + std::to_string(j + 1) + " (" + str(frequency_hz(lambda)) + " Hz, lambda = " +
                  str(lambda) + " rad^2/s^2) has the relative residual " + str(residual) + " > limit " +
                  str(request.residual_limit) + " (" + to_string(request.backend) + " eigensolver)");
    }
  }
  result.eigenvalues = std::move(modes.values);
  result.vectors = std::move(modes.vectors);
  return result;
}

}  // namespace nvh::condense
