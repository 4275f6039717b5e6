#pragma once
// A Cholesky factor of A restricted to C u = r: the solves with a symmetric positive definite sparse A
// (K_ii, K - sigma M) under a few dense linear constraints C u = r (m rows, m << n: the distributing
// couplings in multiplier form, fe_model.hpp), by the range-space method of the saddle-point system
//
//     [A  C^T] [u     ]   [b]
//     [C  0  ] [lambda] = [r]
//
// (Nocedal & Wright, Numerical Optimization, 2nd ed. 2006, sec. 16.2, eq. 16.16-16.18; Benzi, Golub &
// Liesen, Acta Numerica 14, 2005, sec. 5). With A = P^T L L^T P (SparseCholesky) and
// Y = L^-1 P C^T = U R (thin QR, U n x m orthonormal), the Schur complement is S = C A^-1 C^T = Y^T Y =
// R^T R, and the constrained inverse A^-1 - A^-1 C^T S^-1 C A^-1 = P^T L^-T Q L^-1 P with
// Q = I - U U^T, an orthogonal projector. So a solve is
//
//     y = Q L^-1 P b + U R^-T r,   u = P^T L^-T y        (then C u = R^T U^T y = r)
//
// one forward and one backward substitution like an unconstrained solve, plus two products with the
// n x m matrix U. The shift-invert eigen-solve works on the symmetric operator
// Q L^-1 P M P^T L^-T Q (eigensolver.cpp): forward() and backward() below include the projection.
// Without constraints (m = 0) every call is the plain factor's.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>

#include "condense/sparse_cholesky.hpp"

namespace nvh::condense {

class ConstrainedFactor {
 public:
  explicit ConstrainedFactor(Ordering ordering = Ordering::kAuto);

  /// The constraint matrix C (m x n, rows of C u = r; empty: none). Set before factorize(); a later
  /// factorize() keeps it. nvh::Error (from factorize) if its rows are linearly dependent.
  void set_constraints(const SparseMatrix& c);
  /// Factor A (its lower triangle is read; the pattern is analysed on the first call only) and form
  /// U and R from C. false if A is not positive definite (see failed_dof()).
  bool factorize(const SparseMatrix& a);

  Eigen::Index rows() const { return n_; }
  Eigen::Index constraint_count() const { return constraints_.rows(); }
  bool constrained() const { return constraints_.rows() > 0; }
  const SparseMatrix& constraints() const { return constraints_; }

  /// u with A u + C^T lambda = b and C u = 0, for one right-hand side (raw arrays of rows() values) ...
  void solve(const double* b, double* u) const;
  /// ... for many ...
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b) const;
  /// ... and with C u = r (r: m x columns of b).
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b, const Eigen::MatrixXd& r) const;
  /// The two halves of a solve with r = 0: forward(b) = Q L^-1 P b, backward(y) = P^T L^-T Q y, so that
  /// backward(forward(b)) = solve(b) and the eigen-solve's operator forward(M backward(y)) is symmetric.
  Eigen::MatrixXd forward(const Eigen::MatrixXd& b) const;
  Eigen::MatrixXd backward(const Eigen::MatrixXd& y) const;

  Eigen::Index failed_dof() const { return factor_.failed_dof(); }
  const FactorStats& stats() const { return factor_.stats(); }

 private:
  /// y <- Q y = y - U (U^T y).
  void project(Eigen::Ref<Eigen::MatrixXd> y) const;

  SparseCholesky factor_;
  SparseMatrix constraints_;  ///< C, m x n
  Eigen::MatrixXd u_;         ///< n x m, orthonormal basis of L^-1 P C^T
  Eigen::MatrixXd r_;         ///< m x m, upper triangular: L^-1 P C^T = U R
  Eigen::Index n_ = 0;
};

}  // namespace nvh::condense
