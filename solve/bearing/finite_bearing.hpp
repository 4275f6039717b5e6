#pragma once
// The finite journal bearing: the Reynolds equation on a grid over angle and width, by finite volumes,
// with mass-conserving (JFO / Elrod) or Swift-Stieber cavitation as a complementarity problem solved by a
// Fischer-Burmeister-Newton method.
//
// Unknowns per cell: the pressure p >= 0 and the void fraction r = 1 - fill ratio >= 0, with p r = 0
// (Giacopini, Fowell, Dini and Strozzi, J. Tribol. 132 (2010) 041702). Mass balance of each cell, with the
// Couette flux upwinded and carrying the fill ratio (Elrod 1981; Vijayaraghavan and Keith 1989):
//   sum over faces [ -h^3 / (12 mu) dp/dn + U_m h (1 - r)_upwind n_theta ] + (1 - r) dh/dt A = 0
// The complementarity p >= 0, r >= 0, p r = 0 is written as the Fischer-Burmeister equation
//   p + r - sqrt(p^2 + r^2) = 0            (Fischer 1992; Woloszynski et al., Tribol. Lett. 58 (2015) 18)
// and the whole system is solved by a semismooth Newton method. It starts in the active-set form
// min(p, r) = 0 (a primal-dual active-set method, Hintermueller, Ito and Kunisch, SIAM J. Optim. 13 (2003)
// 865): for a given set of cavitated cells the isoviscous equations are linear, so once the set is right one
// full step is exact. If that has not converged in 12 steps, the Fischer-Burmeister form with a backtracking
// line search takes over (globally convergent). Each Newton step eliminates one unknown per cell with the
// local complementarity equation (the one with the larger derivative), so the linear system has one unknown
// per cell and the five-point pattern; it is factorized by KLU with the ordering computed once per grid and
// numeric refactorizations that keep the pivot sequence while it stays well conditioned.
// Stopping: the Newton step below the tolerance, or a residual at round-off level after a full step, or a
// quadratic contraction that puts the next step below the tolerance.
//
// Swift-Stieber: the fill ratio stays 1 and r becomes a local mass source (the mass the Reynolds
// condition creates in the rupture zone), complementary to p. kNone: p unconstrained, r = 0 (linear).
//
// The squeeze term (1 - r) dh/dt is quasi-steady: the time derivative of the fill ratio in the cavitated
// zone is neglected, so one evaluation depends on (e, de/dt) alone. Mass is conserved exactly in steady
// operation; in fast transients the film history of the cavitated zone is not followed (docs/bearing.md).
//
// Jacobian d(force)/d(e, de/dt): by the implicit function theorem on the converged discrete system,
// reusing the factorization of the last Newton step (4 back-substitutions, no re-solve). It is the
// exact derivative of the discrete solution (up to the Newton tolerance), cheaper and more accurate than
// finite differences of warm-started solves, which would cost 4-8 nonlinear solves per call.
//
// Warm start: the object keeps its last (p, r) and its sensitivities d(p, r)/d(e, de/dt) (from the Jacobian
// solves) and starts the next evaluation from the tangent prediction (p, r) + d(p, r)/dq dq, projected onto
// p, r >= 0. It is a starting guess only: the converged result does not depend on it beyond the tolerance.
// The object is a plain value type (copying it copies the last solution; the factorization is rebuilt on
// demand).
#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "solve/bearing/bearing.hpp"

namespace nvh::bearing {

struct FiniteSolverOptions {
  double tolerance = 1e-9;  ///< Newton stops when the step is below tolerance * (1 + max p) (nondimensional)
  int max_iterations = 60;
  bool jacobian = true;  ///< compute d(force)/d(e, de/dt)
};

class FiniteBearing {
 public:
  /// Validates the spec (nvh::Error naming the field) and builds the grid, feed cells and sparsity pattern.
  explicit FiniteBearing(BearingSpec spec, FiniteSolverOptions options = {});
  FiniteBearing(const FiniteBearing& other);
  FiniteBearing& operator=(const FiniteBearing& other);
  FiniteBearing(FiniteBearing&&) noexcept;
  FiniteBearing& operator=(FiniteBearing&&) noexcept;
  ~FiniteBearing();

  /// Solve the film for this motion, warm-started from the previous solution (if any).
  /// Throws nvh::Error if |e| >= c or if Newton does not converge.
  FilmResult evaluate(const Kinematics& k);
  /// Forget the previous solution: the next evaluation starts cold (full-film linear solve, clipped).
  void reset() { has_solution_ = false; }

  /// Pressure (Pa) of the last solution, cells_around x cells_across; cell (i, j) is centred at
  /// theta_i = (i + 1/2) 2 pi / cells_around, z_j = -L/2 + (j + 1/2) L / cells_across.
  Eigen::MatrixXd pressure() const;
  /// Fill ratio (1 in the full film) of the last solution, same layout. 1 everywhere unless JFO.
  Eigen::MatrixXd fill_ratio() const;
  /// True for cells held at the supply pressure (holes, grooves), same layout.
  Eigen::MatrixXi supply_cells() const;
  const BearingSpec& spec() const { return spec_; }

 private:
  struct Assembly;
  struct Solver;
  void mark_supply_cells();
  void build_pattern();
  void set_motion(const Kinematics& k);
  /// Residuals (and derivatives) at (P, r); `linear`: full film, isoviscous (the cold start).
  void assemble(const Eigen::VectorXd& P, const Eigen::VectorXd& r, bool jacobian, Assembly& a,
                bool linear = false) const;
  double merit(const Assembly& a) const;
  /// Reduced linear system of one Newton step: fills the matrix values and the right-hand side.
  void reduce(Assembly& a, Eigen::VectorXd& rhs);
  void cold_start();
  FilmResult post_process(const Kinematics& k, const Assembly& a) const;
  void parameter_jacobian(const Assembly& a, FilmResult& result);
  void predict(const Kinematics& k);

  BearingSpec spec_;
  FiniteSolverOptions options_;
  int nt_ = 0, nz_ = 0, n_ = 0;                        // cells around, across, total
  double dtheta_ = 0, dz_ = 0;                         // nondimensional: theta in rad, Z = z / R
  std::vector<char> supply_;                           // per cell
  std::vector<double> cos_c_, sin_c_, cos_f_, sin_f_;  // cell centres and faces i + 1/2
  std::vector<std::array<int, 5>> neighbour_;          // self, east, west, north, south (-1: none)

  // Motion-dependent (set_motion)
  double omega_ref_ = 1, p_ref_ = 1, couette_ = 0, barus_ = 0, supply_p_ = 0;
  std::vector<double> h_c_, h_f_, hdot_;  // H = h / c at centres and faces; dH/dtau at centres

  // State
  bool has_solution_ = false;
  bool min_complementarity_ = false;  // this Newton iteration: min(p, r) = 0 instead of Fischer-Burmeister
  double p_ref_of_solution_ = 1;
  Kinematics kinematics_of_solution_;
  Eigen::VectorXd P_, r_;
  // d(P, r)/d(ex, ey, ex_dot, ey_dot) of the last solution (nondimensional P per SI unit): the predictor.
  bool has_sensitivity_ = false;
  Eigen::MatrixXd dP_dq_, dr_dq_;
  std::unique_ptr<Solver> solver_;
};

}  // namespace nvh::bearing
