#pragma once
// The iteration matrix J = dF/dy + cj dF/dy' by finite differences grouped by the sparsity pattern: columns
// that share no row are perturbed together (Curtis, Powell and Reid, IMA J. Appl. Math. 13, 1974), each group
// costs one residual evaluation. y and y' are perturbed together (y_j + h, y'_j + cj h), so one difference
// gives dF/dy_j + cj dF/dy'_j, as in IDA's own difference quotient.
#include <vector>

#include <Eigen/Dense>

#include "solve/model.hpp"

namespace nvh::solve {

class ColoredJacobian {
 public:
  explicit ColoredJacobian(const Model& model, bool dense = false);
  const SparsityPattern& pattern() const { return pattern_; }
  int colors() const { return static_cast<int>(groups_.size()); }

  /// Values in the pattern's CSC order. `f0` is F(t, y, y'); `weights` scales the increments (IDA's error
  /// weights: increment sqrt(eps) max(|y_j|, 1/w_j, |h y'_j|), at least sqrt(eps) for multipliers).
  void evaluate(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& yp, const Eigen::VectorXd& f0,
                double cj, double h, const Eigen::VectorXd& weights, std::vector<double>& values) const;
  /// Number of residual evaluations made so far.
  long residual_evaluations() const { return evaluations_; }

 private:
  const Model& model_;
  SparsityPattern pattern_;
  std::vector<std::vector<int>> groups_;  // columns per color
  std::vector<char> algebraic_;           // per unknown: a multiplier (nu, lambda, mu)
  mutable long evaluations_ = 0;
};

}  // namespace nvh::solve
