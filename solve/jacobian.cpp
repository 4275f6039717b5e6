#include "solve/jacobian.hpp"

#include <cmath>
#include <limits>

namespace nvh::solve {

ColoredJacobian::ColoredJacobian(const Model& model, bool dense) : model_(model) {
  if (dense) {
    pattern_.n = model.size();
    for (int c = 0; c <= pattern_.n; ++c) pattern_.column_start.push_back(c * pattern_.n);
    for (int c = 0; c < pattern_.n; ++c)
      for (int r = 0; r < pattern_.n; ++r) pattern_.rows.push_back(r);
  } else {
    pattern_ = model.jacobian_pattern();
  }
  const Eigen::VectorXd mask = model.differential_mask();
  algebraic_.resize(mask.size());
  for (Eigen::Index k = 0; k < mask.size(); ++k) algebraic_[k] = mask[k] == 0;
  // Greedy colouring: a column joins the first group none of whose columns shares a row with it.
  const int n = pattern_.n;
  std::vector<std::vector<char>> used;  // per group: rows taken
  for (int c = 0; c < n; ++c) {
    int g = 0;
    for (; g < static_cast<int>(groups_.size()); ++g) {
      bool clash = false;
      for (int k = pattern_.column_start[c]; k < pattern_.column_start[c + 1] && !clash; ++k)
        clash = used[g][pattern_.rows[k]];
      if (!clash) break;
    }
    if (g == static_cast<int>(groups_.size())) {
      groups_.emplace_back();
      used.emplace_back(n, 0);
    }
    groups_[g].push_back(c);
    for (int k = pattern_.column_start[c]; k < pattern_.column_start[c + 1]; ++k) used[g][pattern_.rows[k]] = 1;
  }
}

void ColoredJacobian::evaluate(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& yp,
                               const Eigen::VectorXd& f0, double cj, double h, const Eigen::VectorXd& weights,
                               std::vector<double>& values) const {
  const double srur = std::sqrt(std::numeric_limits<double>::epsilon());
  values.assign(pattern_.rows.size(), 0.0);
  Eigen::VectorXd yy = y, yyp = yp, f(y.size()), inc(y.size());
  for (const auto& group : groups_) {
    for (int c : group) {
      // A floor on the increment: with tight absolute tolerances 1/weight is far below the round-off of the
      // rows a variable feeds (a coordinate at 0 with atol 1e-10 would get 1e-18). Multipliers enter F
      // linearly (any increment is exact): unit floor; coordinates and velocities: 1e-2 (m, rad, m/s).
      const double floor = algebraic_[c] ? 1.0 : 1e-2;
      double d = srur * std::max({std::abs(y[c]), std::abs(h * yp[c]), 1.0 / weights[c], floor});
      if (h * yp[c] < 0) d = -d;
      d = (y[c] + d) - y[c];  // exactly representable
      inc[c] = d;
      yy[c] += d;
      yyp[c] += cj * d;
    }
    model_.residual(t, yy.data(), yyp.data(), f.data());
    ++evaluations_;
    for (int c : group) {
      for (int k = pattern_.column_start[c]; k < pattern_.column_start[c + 1]; ++k) {
        const int r = pattern_.rows[k];
        values[k] = (f[r] - f0[r]) / inc[c];
      }
      yy[c] = y[c];
      yyp[c] = yp[c];
    }
  }
}

}  // namespace nvh::solve
