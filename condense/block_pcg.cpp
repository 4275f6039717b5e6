#include "condense/block_pcg.hpp"

#include <cmath>
#include <string>

#include "common/error.hpp"

namespace nvh::condense {
BlockPcgResult block_pcg(const SparseMatrix& a, const PMultigrid& preconditioner, const Block& b,
                         double tolerance, int max_iterations) {
  const Eigen::Index n = b.rows(), k = b.cols();
  BlockPcgResult result;
  result.x = Block::Zero(n, k);
  const Eigen::ArrayXd b_norm = column_dots(b, b).sqrt();
  Block r = b, z, p, ap, s1, s2, s3;
  preconditioner.apply(r, z, {s1, s2, s3});
  p = z;
  Eigen::ArrayXd rz = column_dots(r, z);
  for (int it = 0;; ++it) {
    const Eigen::ArrayXd r_norm = column_dots(r, r).sqrt();
    Eigen::ArrayXd relative = r_norm / b_norm.max(1e-300);
    for (Eigen::Index j = 0; j < k; ++j)
      if (b_norm[j] == 0) relative[j] = 0;
    Eigen::Index worst_column = 0;
    result.largest_residual = k ? relative.maxCoeff(&worst_column) : 0.0;
    result.iterations = it;
    if (result.largest_residual <= tolerance) break;
    if (it == max_iterations)
      throw Error("the preconditioned conjugate gradients did not converge in " +
                  std::to_string(max_iterations) + " iterations: right-hand side " +
                  std::to_string(worst_column + 1) + " of " + std::to_string(k) + " at relative residual " +
                  scientific(result.largest_residual) + " > " + scientific(tolerance));
    symmetric_block_product(a, p, ap);
    const Eigen::ArrayXd curvature = column_dots(p, ap);
    // A converged column keeps iterating with the others (its step is tiny); a zero one is left at x = 0.
    Eigen::ArrayXd alpha = Eigen::ArrayXd::Zero(k);
    for (Eigen::Index j = 0; j < k; ++j) {
      if (b_norm[j] == 0 || rz[j] == 0) continue;
      if (!(curvature[j] > 0))
        throw Error("the preconditioned conjugate gradients met p^T A p = " + scientific(curvature[j]) +
                    " <= 0 in right-hand side " + std::to_string(j + 1) +
                    ": the matrix is not positive definite (an unrestrained part?)");
      alpha[j] = rz[j] / curvature[j];
    }
    for (Eigen::Index i = 0; i < n; ++i) {
      result.x.row(i).array() += alpha.transpose() * p.row(i).array();
      r.row(i).array() -= alpha.transpose() * ap.row(i).array();
    }
    preconditioner.apply(r, z, {s1, s2, s3});
    const Eigen::ArrayXd rz_next = column_dots(r, z);
    Eigen::ArrayXd beta = Eigen::ArrayXd::Zero(k);
    for (Eigen::Index j = 0; j < k; ++j)
      if (rz[j] != 0) beta[j] = rz_next[j] / rz[j];
    for (Eigen::Index i = 0; i < n; ++i)
      p.row(i).array() = z.row(i).array() + beta.transpose() * p.row(i).array();
    rz = rz_next;
  }
  return result;
}

}  // namespace nvh::condense
