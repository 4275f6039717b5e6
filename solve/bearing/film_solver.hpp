#pragma once
// The finite-volume Reynolds equation with mass-conserving (JFO / Elrod) or Swift-Stieber cavitation on a
// structured grid, and its complementarity Newton solve: the common core of the finite journal bearing
// (finite_bearing.hpp: periodic around, p = 0 at both edges) and the 1D slider (slider.hpp: given pressures
// at both ends, no side flow).
//
// Nondimensional, cells (i, k) with i along the sliding direction x (nx cells of width dx) and k across
// (nz cells of width dz); cell m = i + nx k. Unknowns per cell: the pressure P >= 0 and the void fraction
// r = 1 - fill ratio >= 0, with P r = 0 (Giacopini, Fowell, Dini and Strozzi, J. Tribol. 132 (2010)
// 041702). Mass balance of each cell (net outflow = 0), with the Couette flux upwinded and carrying the
// fill ratio (Elrod 1981; Vijayaraghavan and Keith 1989):
//   sum over faces [ -G / mu_r dP/dn + C H_f (1 - r)_upwind n_x ] + (1 - r) dH/dtau A = 0
// G: the Poiseuille conductance of the face (H^3 for a smooth film), H_f: the film that carries the Couette
// flux, C: the mean surface speed (sign = direction), mu_r = exp(alpha P) (Barus, 1 below ambient). With
// closing_film_full (the piston skirt) a cell whose film closes takes dH/dtau A instead of (1 - r) dH/dtau A.
// Boundaries: along x either periodic (journal) or a given pressure half a cell beyond the end cells, with
// a film of a given fill ratio (1: fully flooded; JFO) entering from outside; across, optionally P = 0 half a
// cell beyond both edges, or periodic (a full circle across, the piston skirt: skirt_film.hpp).
// Coefficients: per column (the journal and the slider: the film varies along x only), or per cell (the
// piston skirt: the film varies in both directions); each per-cell vector, when given, replaces its
// per-column one, and the per-column ones are then not read.
// Swift-Stieber: the fill ratio stays 1 and r is a local mass source >= 0 complementary to P. kNone: P
// unconstrained, r = 0 (linear). Supply cells are held at the supply pressure with r = 0.
//
// The complementarity P >= 0, r >= 0, P r = 0 is solved with the mass balance by a semismooth Newton method:
// first as min(P, r) = 0, a primal-dual active-set method (Hintermueller, Ito and Kunisch, SIAM J. Optim.
// 13 (2003) 865): for a given set of cavitated cells the isoviscous equations are linear, so once the set is
// right one full step is exact; after `active_set_iterations` (12) steps as Fischer-Burmeister P + r -
// sqrt(P^2 + r^2) = 0 with Armijo backtracking (Fischer 1992; Woloszynski et al., Tribol. Lett. 58 (2015)
// 18). Each Newton step eliminates one unknown per cell with the local complementarity equation (the one with
// the larger derivative), so the linear system has one unknown per cell and the five-point pattern; it is
// factorized by KLU with the ordering computed once per grid and numeric refactorizations that keep the pivot
// sequence while it stays well conditioned.
#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "solve/bearing/bearing.hpp"

namespace nvh::bearing {

struct FiniteSolverOptions {
  double tolerance = 1e-9;  ///< Newton stops when the step is below tolerance * (1 + max p) (nondimensional)
  int max_iterations = 60;
  /// Newton steps in the active-set form min(p, r) = 0 before Fischer-Burmeister takes over.
  int active_set_iterations = 12;
  bool jacobian = true;  ///< finite bearing: compute d(force)/d(e, de/dt)
  /// Finite bearing: solve one half of the width when the bearing is symmetric about its mid-plane (an even
  /// number of cells across and feed holes and grooves that mirror onto themselves). The discrete solution
  /// is the same (it is symmetric); the Newton system has half the unknowns. Off: the whole grid, always.
  bool mirror_symmetry = true;
  /// Simplified Newton across calls: while the cells keep their primary unknowns (the same active set) and
  /// the steps contract by at least `chord_contraction`, a step reuses the factorization of an earlier state
  /// instead of refactorizing (the residual is always the current one, so the solution is the same to the
  /// tolerance). A time integration calls with states close together, where the refactorization is most of
  /// the cost. Sensitivities (the Jacobian) then need `FiniteBearing::refresh_jacobian`.
  bool reuse_factorization = false;
  double chord_contraction = 0.25;
};

/// The grid and coefficients of one film problem (nondimensional). The grid part (sizes, periodic_x,
/// z_edges, periodic_z, supply) must not change after the first solve; the coefficients may change between
/// solves. Cell m = i + nx k.
struct FilmProblem {
  int nx = 0, nz = 1;
  double dx = 0, dz = 1;
  bool periodic_x = true;    ///< journal: column nx - 1 joins column 0; else boundary faces at both ends
  bool z_edges = true;       ///< P = 0 half a cell beyond rows 0 and nz - 1 (side leakage)
  /// With z_edges: the north edge of row nz - 1 is a plane of symmetry instead (no flux through it), so the
  /// grid is one half of a film symmetric about its mid-plane and only row 0 leaks (finite_bearing.hpp).
  bool mirror_north = false;
  bool periodic_z = false;   ///< row nz - 1 joins row 0 (needs nz >= 3 and no z_edges)
  std::vector<char> supply;  ///< per cell: held at supply_p with r = 0
  Cavitation cavitation = Cavitation::kJfo;

  double couette = 0;             ///< C: mean surface speed along x
  double barus = 0;               ///< alpha p_ref
  double supply_p = 0;            ///< P at supply cells
  std::vector<double> g_east;     ///< nx: conductance G of the east face of column i (x = x_i + dx/2)
  std::vector<double> h_east;     ///< nx: Couette film H_f of the east face of column i
  std::vector<double> h_centre;   ///< nx: film at the column centres (faces across the width and edges)
  std::vector<double> hdot;       ///< nx: dH/dtau per column (squeeze)
  double g_west = 0, h_west = 0;  ///< not periodic: the west face of column 0 (x = 0)
  double p_west = 0, p_east = 0;  ///< not periodic: P half a cell beyond columns 0 and nx - 1
  /// Not periodic, JFO: the fill ratio of the film that the Couette flux carries in from outside through the
  /// west end (couette >= 0) or the east end (couette < 0); < 1 is a starved (partly flooded) inlet. The
  /// other models keep a full film (fill 1).
  double fill_west = 1, fill_east = 1;
  /// JFO: a cell whose film closes (dH/dtau < 0) takes the squeeze term dH/dtau whatever its fill ratio (the
  /// closing gap taken as full, a cavitated cell then has to be fed or pressurize), instead of (1 - r)
  /// dH/dtau. Opening cells keep (1 - r) dH/dtau. Off: the journal bearing's closure. See docs/bearing.md
  /// section 14.
  bool closing_film_full = false;

  // Per-cell coefficients (optional): each one, when not empty, replaces its per-column vector above.
  std::vector<double> g_east_cells;  ///< nx nz: conductance of the east face of cell m (x = x_i + dx/2)
  std::vector<double> h_east_cells;  ///< nx nz: Couette film of the east face of cell m
  /// nx nz: conductance of the north face of cell m (z = z_k + dz/2; row nz - 1: the face to row 0 when
  /// periodic_z, else not read). Empty: H^3 of the cell's centre film, as with per-column coefficients.
  std::vector<double> g_north_cells;
  std::vector<double> h_centre_cells;  ///< nx nz: film at the cell centres (the edge faces' conductance H^3)
  std::vector<double> hdot_cells;      ///< nx nz: dH/dtau per cell (squeeze)
  std::vector<double> g_west_rows;     ///< nz: not periodic, the conductance of the west face of each row
  std::vector<double> h_west_rows;     ///< nz: not periodic, the Couette film of the west face of each row
};

/// Residuals and their derivatives at one state. Rows and stencil slots per cell.
struct FilmAssembly {
  Eigen::VectorXd M;                      ///< mass balance: net outflow of each cell (nondimensional)
  Eigen::VectorXd Phi;                    ///< complementarity residual
  Eigen::VectorXd ap, ar;                 ///< dPhi/dP, dPhi/dr
  std::vector<std::array<double, 5>> JP;  ///< dM/dP of the stencil cells (self, east, west, north, south)
  std::vector<std::array<double, 5>> JR;  ///< dM/dr of the stencil cells
  std::vector<char> primary_is_p;         ///< which unknown the reduced system keeps per cell
  double side_flow = 0;                   ///< out through both edges across (z_edges)
  double west_flow = 0;                   ///< along +x through the west end (not periodic)
  double east_flow = 0;                   ///< along +x through the east end (not periodic)
  double squeeze_flow = 0;                ///< the squeeze terms' sum: the rate of the film's stored volume
};

class FilmSolver {
 public:
  static constexpr int kSelf = 0, kEast = 1, kWest = 2, kNorth = 3, kSouth = 4;

  FilmSolver();
  /// Copies the problem; the factorization is rebuilt on demand.
  FilmSolver(const FilmSolver& other);
  FilmSolver& operator=(const FilmSolver& other);
  FilmSolver(FilmSolver&&) noexcept;
  FilmSolver& operator=(FilmSolver&&) noexcept;
  ~FilmSolver();

  FilmProblem problem;

  /// Newton solve from (P, r); on return (P, r) is the last iterate. Returns the iterations taken, or
  /// -iterations if it did not converge.
  int solve(Eigen::VectorXd& P, Eigen::VectorXd& r, const FiniteSolverOptions& options);
  /// The full-film (linear, isoviscous) solution, negative pressures clipped to zero and the cells they
  /// leave marked as partly filled (JFO).
  void cold_start(Eigen::VectorXd& P, Eigen::VectorXd& r);
  /// Residuals (and derivatives) at (P, r); `linear`: full film, isoviscous.
  void assemble(const Eigen::VectorXd& P, const Eigen::VectorXd& r, bool jacobian, FilmAssembly& a,
                bool linear = false) const;
  /// The assembly of the last Newton step (its factorization is the one solve_last() uses).
  const FilmAssembly& last_step() const { return last_; }
  /// True when the factorization solve_last() uses was made at the last step's state (a Newton step, not a
  /// simplified one with an older factorization).
  bool last_step_was_factorized() const { return last_factorized_; }
  /// Numeric factorizations made by the last solve() (fewer than its iterations with reuse_factorization).
  int factorizations() const { return factorizations_; }
  /// When the last solve() needed the Barus continuation: alpha times the peak of its isoviscous solution
  /// (nondimensional), else 0. In 1D the Barus pressure is -ln(1 - alpha q) / alpha of the isoviscous q,
  /// which has no bound once alpha q >= 1: a failure with this >= 1 is the piezoviscous runaway, not the
  /// solver.
  double barus_isoviscous_product() const { return barus_isoviscous_; }
  /// Assembles and factorizes at (P, r) (min form of the complementarity), so that last_step() and
  /// solve_last() belong to this state. False if the matrix is singular.
  bool factorize_at(const Eigen::VectorXd& P, const Eigen::VectorXd& r);
  /// b <- A^-1 b with the reduced matrix of the last Newton step (for sensitivities).
  void solve_last(Eigen::VectorXd& b);
  /// Stencil of cell m: self, east, west, north, south (-1: none).
  const std::array<int, 5>& neighbours(int m) const { return neighbour_[m]; }
  int cells() const { return problem.nx * problem.nz; }

 private:
  struct Linear;
  /// Throws nvh::Error if the problem's sizes do not fit together (a programming error of the caller).
  void check_problem() const;
  /// The semismooth Newton solve of solve() at the current coefficients (solve() adds the Barus
  /// continuation).
  int solve_newton(Eigen::VectorXd& P, Eigen::VectorXd& r, const FiniteSolverOptions& options);
  void build_pattern();
  double merit(const FilmAssembly& a) const;
  /// The reduced Newton system at `a`: the right-hand side, and the matrix's values when `matrix`.
  void reduce(FilmAssembly& a, Eigen::VectorXd& rhs, bool matrix);
  /// Factorizes the reduced matrix (of `a`'s unknowns); false if singular.
  bool factorize_reduced(const FilmAssembly& a);

  std::vector<std::array<int, 5>> neighbour_;
  bool min_complementarity_ = false;  // this Newton iteration: min(P, r) = 0 instead of Fischer-Burmeister
  bool last_factorized_ = false;      // see last_step_was_factorized()
  int factorizations_ = 0;            // see factorizations()
  double barus_isoviscous_ = 0;       // see barus_isoviscous_product()
  double chord_rate_ = 1;             // contraction of the last two simplified steps (1: none measured yet)
  FilmAssembly last_;
  Eigen::VectorXd P_start_, r_start_;  // solve_newton's start, for its fall-back (kept: no allocation per solve)
  std::unique_ptr<Linear> linear_;
};

}  // namespace nvh::bearing
