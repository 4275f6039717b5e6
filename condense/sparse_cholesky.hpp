#pragma once
// Sparse Cholesky factorization A = P^T L L^T P of a symmetric positive definite matrix (CHOLMOD,
// supernodal), with a fill-reducing ordering P and a record of what it cost: the ordering chosen, the
// fill nnz(L) and the time of the ordering (symbolic analysis) and of the numeric factorization. The
// shift-invert eigen-solve and the Craig-Bampton constraint modes both use it.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <string>

namespace nvh::condense {

using SparseMatrix = Eigen::SparseMatrix<double>;  // column-major

/// Fill-reducing ordering. kAuto: CHOLMOD's default - AMD, and METIS as well when AMD's factor is dense
/// (flops / nnz(L) >= 500 and nnz(L) / nnz(A) >= 5), the better of the two kept.
enum class Ordering { kAuto, kAmd, kMetis, kNesdis };

/// Parse "auto" | "amd" | "metis" | "nesdis"; nvh::Error listing the choices otherwise.
Ordering parse_ordering(const std::string& name);
std::string to_string(Ordering ordering);

/// What the factorizations of a run cost (summed over several with add()).
struct FactorStats {
  std::string ordering;        ///< the ordering CHOLMOD used: "AMD", "METIS", "NESDIS", "natural", ...
  double matrix_nonzeros = 0;  ///< nnz of the lower triangle of A
  double factor_nonzeros = 0;  ///< nnz(L) (without the explicit zeros of supernodal amalgamation)
  double flops = 0;            ///< floating-point operations of the numeric factorization
  double order_seconds = 0;    ///< ordering and symbolic analysis
  double factor_seconds = 0;   ///< numeric factorization
  int factorizations = 0;

  /// Fill ratio nnz(L) / nnz(tril(A)).
  double fill() const { return matrix_nonzeros > 0 ? factor_nonzeros / matrix_nonzeros : 0.0; }
  /// Sum of the times and counts; the sizes and the ordering are those of the largest factor.
  void add(const FactorStats& other);
};

class SparseCholesky {
 public:
  explicit SparseCholesky(Ordering ordering = Ordering::kAuto);
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  /// Analyse the pattern (only on the first call: later calls must have the same pattern) and factor
  /// `a` (its lower triangle is read). false if `a` is not positive definite; see failed_dof().
  bool factorize(const SparseMatrix& a);
  /// x = A^-1 b for one right-hand side (raw arrays of rows() values: no copies in the Lanczos loop) ...
  void solve(const double* b, double* x) const;
  /// ... and for many.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b) const;
  /// The two halves of a solve, A^-1 = (P^T L^-T) (L^-1 P): forward(b) = L^-1 P b and
  /// backward(b) = P^T L^-T b. The shift-invert eigen-solve works on L^-1 P M P^T L^-T, symmetric in
  /// the ordinary inner product (eigensolver.cpp).
  Eigen::MatrixXd forward(const Eigen::MatrixXd& b) const;
  Eigen::MatrixXd backward(const Eigen::MatrixXd& b) const;
  /// The DOF (original numbering) where the last factorization broke down, -1 if unknown.
  Eigen::Index failed_dof() const;
  /// Costs so far (one analysis, every factorization).
  const FactorStats& stats() const { return stats_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  FactorStats stats_;
};

}  // namespace nvh::condense
