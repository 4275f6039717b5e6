#pragma once
// The test oracle of the model's analytic Jacobian (test_jacobian.cpp, test_jacobian_flexible.cpp): J = dF/dy
// + cj dF/dy' at a random state near the consistent one, against central differences of the residual alone.
//
// J_fd(:, c) = [F(y + h e_c, y' + cj h e_c) - F(y - h e_c, y' - cj h e_c)] / (2 h), h = 1e-6 relative. The
// error of an entry is |J - J_fd| / (largest |J_fd| of its row + 1e-3); `outside` is the largest |J_fd|
// outside the sparsity pattern. Excluded by design (model.hpp): the energy integrals' rows, and mu = 0 in the
// states. `spread` scales the random moves of positions and rotations, `modal` the flexible bodies' modal
// coordinates.
#include <Eigen/Core>

#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "common/log.hpp"
#include "solve/scene.hpp"

namespace nvh::solve::testing {

struct Comparison {
  double worst = 0;    // largest |J - J_fd| / (row scale)
  std::string where;   // the row and column of it
  double outside = 0;  // largest |J_fd| outside the pattern
};

inline Comparison compare(Scene& scene, unsigned seed, double spread = 1.0, double modal = 1e-4) {
  Model& m = scene.model;
  std::ostringstream sink;
  const Logger log(sink, "test", Verbosity::kQuiet);
  Eigen::VectorXd y, yp;
  m.consistent_initial_state(0.0, y, yp, log);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // A random state near the consistent one: positions moved, rotations turned (unit Euler parameters),
  // velocities, rates, element states and lambda random; mu = 0.
  for (std::size_t b = 0; b < m.bodies.size(); ++b) {
    const Body& body = *m.bodies[b];
    const int o = m.body_offset(static_cast<int>(b)), nq = body.position_count(), nw = body.velocity_count();
    for (int k = 0; k < std::min(nq, 3); ++k) y[o + k] += 0.01 * spread * u(rng);
    if (nq >= 7) {
      for (int k = 3; k < 7; ++k) y[o + k] += 0.1 * spread * u(rng);
      y.segment(o + 3, 4).normalize();
      for (int k = 7; k < nq; ++k) y[o + k] += modal * spread * u(rng);
    }
    for (int k = 0; k < nw; ++k) y[o + nq + k] += 2.0 * u(rng);
    for (int k = 0; k < nq + nw; ++k) yp[o + k] = 10.0 * u(rng);
  }
  if (m.clock_index() >= 0) y[m.clock_index()] += u(rng);
  for (const auto& f : m.forces)
    for (int s = 0; s < f.state_count; ++s)
      y[f.state_offset + s] += 0.1 * u(rng), yp[f.state_offset + s] = u(rng);
  for (int e = 0; e < m.constraint_equations(); ++e) {
    y[m.lambda_offset() + e] = 100.0 * u(rng);
    y[m.mu_offset() + e] = 0.0;
  }
  const double cj = 1234.5;
  std::vector<double> values;
  m.jacobian(0.1, y.data(), yp.data(), cj, values);
  const SparsityPattern p = m.jacobian_pattern();
  const int n = m.size();
  Eigen::MatrixXd ja = Eigen::MatrixXd::Zero(n, n);
  Eigen::MatrixXd inside = Eigen::MatrixXd::Zero(n, n);
  for (int c = 0; c < n; ++c)
    for (int k = p.column_start[c]; k < p.column_start[c + 1]; ++k)
      ja(p.rows[k], c) = values[k], inside(p.rows[k], c) = 1;

  Eigen::MatrixXd jf(n, n);
  Eigen::VectorXd fp(n), fm(n);
  for (int c = 0; c < n; ++c) {
    const double h = 1e-6 * std::max(1.0, std::abs(y[c]));
    Eigen::VectorXd y1 = y, yp1 = yp;
    y1[c] += h, yp1[c] += cj * h;
    m.residual(0.1, y1.data(), yp1.data(), fp.data());
    y1[c] = y[c] - h, yp1[c] = yp[c] - cj * h;
    m.residual(0.1, y1.data(), yp1.data(), fm.data());
    jf.col(c) = (fp - fm) / (2 * h);
  }
  Comparison out;
  for (int r = 0; r < n; ++r) {
    if (r == m.energy_offset() || r == m.energy_offset() + 1) continue;
    const double scale = jf.row(r).cwiseAbs().maxCoeff();
    for (int c = 0; c < n; ++c) {
      if (inside(r, c) == 0)
        out.outside = std::max(out.outside, std::abs(jf(r, c)) / std::max(scale, 1e-300));
      const double err = std::abs(ja(r, c) - jf(r, c)) / (scale + 1e-3);
      if (err > out.worst) {
        out.worst = err;
        out.where = "row " + m.describe_state(r) + ", column " + m.describe_state(c) + ": analytic " +
                    std::to_string(ja(r, c)) + ", differences " + std::to_string(jf(r, c));
      }
    }
  }
  return out;
}

}  // namespace nvh::solve::testing
