#include "condense/static_solve.hpp"

#include <Eigen/QR>

#include "common/error.hpp"

namespace nvh::condense {

SparseMatrix submatrix(const SparseMatrix& a, const std::vector<int>& rows, const std::vector<int>& cols) {
  std::vector<int> row_map(a.rows(), -1), col_map(a.cols(), -1);
  for (std::size_t i = 0; i < rows.size(); ++i) row_map[rows[i]] = static_cast<int>(i);
  for (std::size_t j = 0; j < cols.size(); ++j) col_map[cols[j]] = static_cast<int>(j);
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < a.outerSize(); ++k) {
    if (col_map[k] < 0) continue;
    for (SparseMatrix::InnerIterator it(a, k); it; ++it)
      if (row_map[it.row()] >= 0) t.emplace_back(row_map[it.row()], col_map[k], it.value());
  }
  SparseMatrix s(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols.size()));
  s.setFromTriplets(t.begin(), t.end());
  return s;
}

Eigen::MatrixXd symmetric_times(const SparseMatrix& a, bool lower, const Eigen::MatrixXd& x) {
  if (lower) return a.selfadjointView<Eigen::Lower>() * x;
  return a * x;
}

Eigen::MatrixXd inertia_relief_solve(const SparseMatrix& K, const SparseMatrix& M, bool lower,
                                     const Eigen::MatrixXd& F, const Eigen::MatrixXd& phi_r,
                                     Ordering ordering, FactorStats* stats) {
  const int n = static_cast<int>(K.rows());
  const int rigid = static_cast<int>(phi_r.cols());
  // P F = F - M Phi_r (Phi_r^T F).
  const Eigen::MatrixXd m_phi_r = rigid > 0 ? symmetric_times(M, lower, phi_r) : Eigen::MatrixXd(n, 0);
  const Eigen::MatrixXd pf = rigid > 0 ? Eigen::MatrixXd(F - m_phi_r * (phi_r.transpose() * F)) : F;

  // A statically determinate set of `rigid` DOF: the pivots of a column-pivoted QR of Phi_r^T, on which
  // Phi_r is nonsingular; held, they leave K_c positive definite (its kernel is rigid motion).
  std::vector<bool> held(n, false);
  if (rigid > 0) {
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(phi_r.transpose());
    for (int k = 0; k < rigid; ++k) held[qr.colsPermutation().indices()(k)] = true;
  }
  std::vector<int> keep;
  keep.reserve(n);
  for (int d = 0; d < n; ++d)
    if (!held[d]) keep.push_back(d);
  ConstrainedFactor chol(ordering);
  if (!chol.factorize(submatrix(K, keep, keep))) {
    throw Error(
        "static solution: the stiffness with the rigid-body motion held is not positive definite (a "
        "mechanism, or more rigid-body modes than counted)");
  }
  if (stats) stats->add(chol.stats());
  Eigen::MatrixXd rhs(static_cast<Eigen::Index>(keep.size()), F.cols());
  for (std::size_t i = 0; i < keep.size(); ++i) rhs.row(static_cast<Eigen::Index>(i)) = pf.row(keep[i]);
  const Eigen::MatrixXd uc = chol.solve(rhs);
  Eigen::MatrixXd u = Eigen::MatrixXd::Zero(n, F.cols());
  for (std::size_t i = 0; i < keep.size(); ++i) u.row(keep[i]) = uc.row(static_cast<Eigen::Index>(i));
  // P^T u = u - Phi_r (Phi_r^T M u).
  if (rigid > 0) u -= phi_r * (m_phi_r.transpose() * u);
  return u;
}

}  // namespace nvh::condense
