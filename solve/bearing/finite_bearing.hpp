#pragma once
// The finite journal bearing: the Reynolds equation on a grid over angle and width, by finite volumes,
// with mass-conserving (JFO / Elrod) or Swift-Stieber cavitation as a complementarity problem solved by a
// semismooth Newton method.
//
// The discretisation and the complementarity Newton solve are film_solver.hpp's (shared with the 1D slider,
// slider.hpp); this class maps a journal onto it: cells around (periodic) x across, H = h / c from the
// eccentricity, P = 0 at both edges, feed holes and grooves as supply cells, and adds the journal's
// post-processing (force, torques, flows), parameter Jacobian and warm start.
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
// If Newton does not converge from it: from the cold start, then by continuation in de/dt from the
// cold start at de/dt = 0 (solve_film); a failure keeps the last solution for the next call.
// Symmetry: a bearing symmetric about its mid-plane (an even number of cells across, holes and grooves that
// mirror onto themselves; the film has no tilt) has a symmetric discrete solution, so only the half z < 0 is
// solved, with no flux through the mid-plane (FilmProblem::mirror_north): half the unknowns, and a Newton
// matrix whose sparse LU costs a third to a quarter. Forces, torques and flows count that half twice; the
// fields (pressure(), fill_ratio()) are mirrored back. FiniteSolverOptions::mirror_symmetry = false solves
// the whole grid (the test of the symmetric half against it).
// The object is a plain value type (copying it copies the last solution; the factorization is rebuilt on
// demand).
#include <Eigen/Core>
#include <vector>

#include "solve/bearing/bearing.hpp"
#include "solve/bearing/film_solver.hpp"

namespace nvh::bearing {

class FiniteBearing {
 public:
  /// Validates the spec (nvh::Error naming the field) and builds the grid, feed cells and sparsity pattern.
  explicit FiniteBearing(BearingSpec spec, FiniteSolverOptions options = {});

  /// Solve the film for this motion, warm-started from the previous solution (if any).
  /// Throws nvh::Error if |e| >= c or if Newton does not converge.
  /// Detail::kForces leaves out the flows (side_flow, feed_flow: one assembly fewer).
  FilmResult evaluate(const Kinematics& k, Detail detail = Detail::kFull);
  /// As evaluate, with the Jacobian (`jacobian`, `full_jacobian`) exact at the solution also when the
  /// options reuse factorizations (then the last step may have used an older one): it factorizes at the
  /// solution if needed. Without reuse_factorization the same as evaluate.
  FilmResult evaluate_with_jacobian(const Kinematics& k, Detail detail = Detail::kFull);
  /// Forget the previous solution: the next evaluation starts cold (full-film linear solve, clipped; if that
  /// does not converge, by continuation in de/dt).
  void reset() { has_solution_ = false; }

  /// Pressure (Pa) of the last solution, cells_around x cells_across; cell (i, j) is centred at
  /// theta_i = (i + 1/2) 2 pi / cells_around, z_j = -L/2 + (j + 1/2) L / cells_across.
  Eigen::MatrixXd pressure() const;
  /// Fill ratio (1 in the full film) of the last solution, same layout. 1 everywhere unless JFO.
  Eigen::MatrixXd fill_ratio() const;
  /// True for cells held at the supply pressure (holes, grooves), same layout.
  Eigen::MatrixXi supply_cells() const;
  const BearingSpec& spec() const { return spec_; }
  const FiniteSolverOptions& options() const { return options_; }

 private:
  /// Supply cells (holes, grooves) of the whole grid, cells_around x cells_across.
  std::vector<char> supply_cells_of_whole_grid() const;
  /// The film cell that holds the values of grid cell (i, k), k over the whole width.
  int cell(int i, int k) const;
  void set_motion(const Kinematics& k);
  /// Solve the film at k into (P_, r_) (its motion set); the iterations, negative if it did not converge.
  int solve_film(const Kinematics& k);
  /// Forces, torques, film extremes and power loss from (P, r); the flows from the assembly `a` if given.
  FilmResult post_process(const Kinematics& k, const FilmAssembly* a) const;
  void parameter_jacobian(const FilmAssembly& a, FilmResult& result);
  void torque_jacobian(FilmResult& result) const;
  void predict(const Kinematics& k);

  BearingSpec spec_;
  FiniteSolverOptions options_;
  int nt_ = 0, nz_ = 0;                                // cells around, across (the whole width)
  int rows_ = 0, n_ = 0;                               // rows and cells solved: half of them if symmetric
  double weight_ = 1;                                  // 2 when the half grid stands for both halves
  double dtheta_ = 0, dz_ = 0;                         // nondimensional: theta in rad, Z = z / R
  std::vector<double> cos_c_, sin_c_, cos_f_, sin_f_;  // cell centres and faces i + 1/2
  FilmSolver film_;                                    // grid, coefficients and the Newton solve

  // Motion-dependent (set_motion)
  double omega_ref_ = 1, p_ref_ = 1;

  // State
  bool has_solution_ = false;
  double p_ref_of_solution_ = 1;
  Kinematics kinematics_of_solution_;
  Eigen::VectorXd P_, r_;
  Eigen::VectorXd P_good_, r_good_;  // the last solution while a new one is sought (solve_film)
  FilmAssembly final_state_;  // the fluxes at the last solution (for the flows), kept to reuse its storage
  // d(P, r)/d(ex, ey, ex_dot, ey_dot) of the last solution (nondimensional P per SI unit): the predictor.
  bool has_sensitivity_ = false;
  Eigen::MatrixXd dP_dq_, dr_dq_;
};

}  // namespace nvh::bearing
