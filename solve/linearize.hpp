#pragma once
// The modes of a model linearised at a state: the eigenvalues of the linearised equations on the constraint
// manifold, with the bodies and elements that take part in each (for `solve --advise`, advise.hpp).
//
// The residual F(t, y, y') = 0 (model.hpp) linearised at (t, y0, y0'): B dy' + A dy = 0 with A = dF/dy and
// B = dF/dy' from the model's analytic Jacobian (A = J(cj = 0), B = J(1) - J(0)). The pencil (A, B) of the
// stabilized index-2 form has infinite eigenvalues (multipliers, constrained directions) whose perturbation
// by round-off is of order sqrt(eps) for index-2 Jordan blocks, so they are removed first, not filtered:
//   1. the algebraic rows (B's row is zero: constraints, normalizations, algebraic element states) restrict
//      dy to their null space N: dy = N s;
//   2. the directions of s that move no differential variable (N_d Z1 = 0: multipliers) are eliminated from
//      the differential rows by a left null space L of (A N Z1);
//   3. the remaining square pencil  L^T B N Z2 u' + L^T A N Z2 u = 0  is an ODE on the manifold:
//      lambda = eigenvalues of -(L^T B N Z2)^-1 (L^T A N Z2).
// A mode is lambda = omega (-zeta +- i sqrt(1 - zeta^2)): omega = |lambda| (rad/s, the undamped natural
// frequency of a linear oscillator), zeta = -Re(lambda) / |lambda|. Zero eigenvalues (rigid motion, the
// clock, the energy integrals) are dropped; real ones are relaxation rates (a Maxwell damper, a
// normalization). Participation: a mode's kinetic energy per body, Re(w^H M w) of its velocity part, and its
// elastic energy per force element and flexible body: d^T K_e d of each element's stiffness along the mode's
// displacement d, by central differences of the element's wrenches (work -(dF . dp + dT . dtheta) at its
// markers), and eta^H K eta of a flexible body's modal stiffness. Inertial stiffness (gravity, centrifugal)
// is not counted; shares are of the counted total.
#include <string>
#include <utility>
#include <vector>

#include "common/log.hpp"
#include "solve/model.hpp"

namespace nvh::solve {

struct LinearMode {
  double omega = 0;          // rad/s: |lambda|
  double damping_ratio = 0;  // -Re(lambda) / |lambda|; < 0: the linearisation grows
  double frequency_hz() const;
  std::vector<std::pair<std::string, double>> kinetic;  // body name, share of the kinetic energy (sum 1)
  std::vector<std::pair<std::string, double>> elastic;  // element or flexible body, share of elastic energy
};

struct Linearization {
  std::vector<LinearMode> modes;         // oscillatory (Im lambda > 0), by omega ascending
  std::vector<double> relaxation_rates;  // 1/s: -lambda of real negative eigenvalues, ascending
  std::vector<double> growth_rates;      // 1/s: real positive eigenvalues (statically unstable), ascending
  int size = 0;                          // the order of the ODE on the manifold (reduced pencil)
};

/// Linearise `model` at (t, y, y') (a consistent state, e.g. from Model::consistent_initial_state) and find
/// its modes. Throws nvh::Error if the reduced pencil is singular (a mass-less direction, an index above 2).
Linearization linearize(const Model& model, double t, const Eigen::VectorXd& y, const Eigen::VectorXd& yp);

}  // namespace nvh::solve
