#include "condense/constrained_factor.hpp"

#include <Eigen/QR>
#include <cmath>
#include <string>

#include "common/error.hpp"

namespace nvh::condense {

ConstrainedFactor::ConstrainedFactor(Ordering ordering) : factor_(ordering) {}

void ConstrainedFactor::set_constraints(const SparseMatrix& c) {
  constraints_ = c;
  constraints_.makeCompressed();
}

bool ConstrainedFactor::factorize(const SparseMatrix& a) {
  if (constrained() && constraints_.cols() != a.rows()) {
    throw Error("internal: " + std::to_string(constraints_.cols()) + " constraint columns for a matrix of " +
                std::to_string(a.rows()) + " rows");
  }
  n_ = a.rows();
  if (!factor_.factorize(a)) return false;
  if (!constrained()) return true;
  // Y = L^-1 P C^T = U R (Householder QR in place, thin): S = C A^-1 C^T = Y^T Y = R^T R. Y (n x m) and U
  // are the only dense n x m arrays alive at once.
  const Eigen::Index m = constraints_.rows();
  Eigen::MatrixXd y = factor_.forward(Eigen::MatrixXd(constraints_.transpose()));
  const Eigen::VectorXd column_norms = y.colwise().norm().transpose();
  const Eigen::HouseholderQR<Eigen::Ref<Eigen::MatrixXd>> qr(y);
  r_ = qr.matrixQR().topRows(m).triangularView<Eigen::Upper>();
  u_ = qr.householderQ() * Eigen::MatrixXd::Identity(n_, m);
  // A row of C that is (nearly) a combination of the others leaves S singular: |R_jj| is the part of
  // column j of Y outside the span of the columns before it.
  for (Eigen::Index j = 0; j < m; ++j) {
    if (!(std::abs(r_(j, j)) > 1e-10 * column_norms(j))) {
      throw Error("the linear constraints (distributing couplings) are linearly dependent: constraint row " +
                  std::to_string(j + 1) + " of " + std::to_string(m) +
                  " repeats the others (two couplings on the same surface, or a surface held by supports?)");
    }
  }
  return true;
}

void ConstrainedFactor::project(Eigen::Ref<Eigen::MatrixXd> y) const {
  if (constrained()) y -= u_ * (u_.transpose() * y);
}

void ConstrainedFactor::solve(const double* b, double* u) const {
  if (!constrained()) {
    factor_.solve(b, u);
    return;
  }
  Eigen::Map<Eigen::VectorXd>(u, n_) = solve(Eigen::MatrixXd(Eigen::Map<const Eigen::VectorXd>(b, n_)));
}

Eigen::MatrixXd ConstrainedFactor::solve(const Eigen::MatrixXd& b) const {
  if (!constrained()) return factor_.solve(b);
  return backward(forward(b));
}

Eigen::MatrixXd ConstrainedFactor::solve(const Eigen::MatrixXd& b, const Eigen::MatrixXd& r) const {
  if (!constrained()) return factor_.solve(b);
  if (r.rows() != constraint_count() || r.cols() != b.cols())
    throw Error("internal: the constraint right-hand side does not match the constraints");
  Eigen::MatrixXd y = forward(b);
  // The particular part Y S^-1 r = U R^-T r, which Q leaves alone (it lies in the span of U).
  y += u_ * r_.transpose().triangularView<Eigen::Lower>().solve(r);
  return factor_.backward(y);
}

Eigen::MatrixXd ConstrainedFactor::forward(const Eigen::MatrixXd& b) const {
  Eigen::MatrixXd y = factor_.forward(b);
  project(y);
  return y;
}

Eigen::MatrixXd ConstrainedFactor::backward(const Eigen::MatrixXd& y) const {
  if (!constrained()) return factor_.backward(y);
  Eigen::MatrixXd z = y;
  project(z);
  return factor_.backward(z);
}

}  // namespace nvh::condense
