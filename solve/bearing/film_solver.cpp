#include "solve/bearing/film_solver.hpp"

#include <klu.h>

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.hpp"

namespace nvh::bearing {

namespace {

// Sparse LU of the reduced Newton matrix by KLU (Davis and Palamadai Natarajan, ACM TOMS 37 (2010) 36): the
// fill-reducing ordering (AMD) is computed once per grid; each Newton step refactorizes numerically with the
// pivot sequence of the last full factorization (klu_refactor) and falls back to a full factorization with
// partial pivoting when the reciprocal pivot growth or condition estimate says the old pivots went bad.
class KluLu {
 public:
  KluLu() { klu_defaults(&common_); }
  KluLu(const KluLu&) = delete;
  KluLu& operator=(const KluLu&) = delete;
  ~KluLu() {
    if (numeric_) klu_free_numeric(&numeric_, &common_);
    if (symbolic_) klu_free_symbolic(&symbolic_, &common_);
  }
  void analyze(Eigen::SparseMatrix<double>& a) {
    symbolic_ = klu_analyze(static_cast<int>(a.rows()), a.outerIndexPtr(), a.innerIndexPtr(), &common_);
    if (!symbolic_)
      throw Error("finite film: KLU could not analyze the Reynolds matrix (status " +
                  std::to_string(common_.status) + ")");
  }
  /// Numeric factorization of `a` (same pattern as analyzed). False if the matrix is singular.
  bool factorize(Eigen::SparseMatrix<double>& a) {
    int* ap = a.outerIndexPtr();
    int* ai = a.innerIndexPtr();
    double* ax = a.valuePtr();
    // The old pivots are kept while the cheap condition estimate (min/max |U_ii|) stays above 1e-12. The
    // reciprocal pivot growth (klu_rgrowth) was checked as well; it cost 2 % of the crankshaft run
    // (testdata/scenes/bearing_crankshaft.toml), where neither test failed once in 40,000 refactorizations.
    if (numeric_ && klu_refactor(ap, ai, ax, symbolic_, numeric_, &common_) &&
        klu_rcond(symbolic_, numeric_, &common_) && common_.rcond > 1e-12)
      return true;
    if (numeric_) klu_free_numeric(&numeric_, &common_);
    numeric_ = klu_factor(ap, ai, ax, symbolic_, &common_);
    return numeric_ != nullptr && common_.status == KLU_OK;
  }
  /// Solves in place: b <- A^-1 b.
  void solve(Eigen::VectorXd& b) {
    klu_solve(symbolic_, numeric_, static_cast<int>(b.size()), 1, b.data(), &common_);
  }

 private:
  klu_common common_;
  klu_symbolic* symbolic_ = nullptr;
  klu_numeric* numeric_ = nullptr;
};

}  // namespace

struct FilmSolver::Linear {
  Eigen::SparseMatrix<double> A;
  std::vector<int> value_index;  // cell * 5 + slot -> index into A.valuePtr() (-1: absent)
  KluLu lu;
  bool factored = false;
  std::vector<char> factor_primary;  // primary_is_p of the factorized matrix (the unknowns it is for)
};

FilmSolver::FilmSolver() = default;
FilmSolver::FilmSolver(const FilmSolver& o)
    : problem(o.problem),
      neighbour_(o.neighbour_),
      min_complementarity_(o.min_complementarity_),
      last_(o.last_) {}
FilmSolver& FilmSolver::operator=(const FilmSolver& o) {
  if (this != &o) *this = FilmSolver(o);
  return *this;
}
FilmSolver::FilmSolver(FilmSolver&&) noexcept = default;
FilmSolver& FilmSolver::operator=(FilmSolver&&) noexcept = default;
FilmSolver::~FilmSolver() = default;

void FilmSolver::check_problem() const {
  const FilmProblem& f = problem;
  const std::size_t nx = f.nx > 0 ? f.nx : 0, n = f.nx > 0 && f.nz > 0 ? std::size_t(f.nx) * f.nz : 0;
  auto bad = [](const std::string& what) { throw Error("film solver: " + what); };
  if (f.nx < 1 || f.nz < 1 || !(f.dx > 0) || !(f.dz > 0)) bad("the grid needs nx, nz >= 1 and dx, dz > 0");
  if (f.periodic_x && f.nx < 3) bad("periodic_x needs nx >= 3");
  if (f.periodic_z && (f.z_edges || f.nz < 3)) bad("periodic_z needs nz >= 3 and no z_edges");
  if (f.mirror_north && (!f.z_edges || f.periodic_z)) bad("mirror_north needs z_edges and no periodic_z");
  if (f.supply.size() != n) bad("'supply' needs nx nz entries");
  auto sized = [&](const std::vector<double>& cells, const std::vector<double>& columns, const char* name) {
    if (cells.empty() ? columns.size() != nx : cells.size() != n)
      bad(std::string("'") + name + "' needs nx entries per column or nx nz per cell");
  };
  sized(f.g_east_cells, f.g_east, "g_east");
  sized(f.h_east_cells, f.h_east, "h_east");
  sized(f.h_centre_cells, f.h_centre, "h_centre");
  sized(f.hdot_cells, f.hdot, "hdot");
  if (!f.g_north_cells.empty() && f.g_north_cells.size() != n) bad("'g_north_cells' needs nx nz entries");
  for (const auto* rows : {&f.g_west_rows, &f.h_west_rows})
    if (!rows->empty() && rows->size() != std::size_t(f.nz))
      bad("'g_west_rows', 'h_west_rows' need nz entries");
  if (!(f.fill_west >= 0 && f.fill_west <= 1 && f.fill_east >= 0 && f.fill_east <= 1))
    bad("the inlet fill ratios must lie in [0, 1]");
}

void FilmSolver::build_pattern() {
  check_problem();
  const int nx = problem.nx, nz = problem.nz, n = cells();
  neighbour_.resize(n);
  for (int k = 0; k < nz; ++k) {
    const int north = k + 1 < nz ? k + 1 : (problem.periodic_z ? 0 : -1);
    const int south = k > 0 ? k - 1 : (problem.periodic_z ? nz - 1 : -1);
    for (int i = 0; i < nx; ++i) {
      int east = i + 1 < nx ? i + 1 : (problem.periodic_x ? 0 : -1);
      int west = i > 0 ? i - 1 : (problem.periodic_x ? nx - 1 : -1);
      neighbour_[i + nx * k] = {i + nx * k, east >= 0 ? east + nx * k : -1, west >= 0 ? west + nx * k : -1,
                                north >= 0 ? i + nx * north : -1, south >= 0 ? i + nx * south : -1};
    }
  }
  linear_ = std::make_unique<Linear>();
  std::vector<Eigen::Triplet<double>> t;
  for (int m = 0; m < n; ++m)
    for (int s = 0; s < 5; ++s)
      if (neighbour_[m][s] >= 0) t.emplace_back(m, neighbour_[m][s], m * 5 + s + 1.0);  // tag: slot id + 1
  linear_->A.resize(n, n);
  linear_->A.setFromTriplets(t.begin(), t.end());
  linear_->A.makeCompressed();
  linear_->value_index.assign(5 * n, -1);
  for (int v = 0; v < linear_->A.nonZeros(); ++v) {
    linear_->value_index[static_cast<int>(linear_->A.valuePtr()[v]) - 1] = v;
  }
  linear_->lu.analyze(linear_->A);
}

void FilmSolver::assemble(const Eigen::VectorXd& P, const Eigen::VectorXd& r, bool jacobian, FilmAssembly& a,
                          bool linear) const {
  const FilmProblem& f = problem;
  const int nx = f.nx, nz = f.nz, n = cells();
  const Cavitation cavitation = linear ? Cavitation::kNone : f.cavitation;
  const bool jfo = cavitation == Cavitation::kJfo;
  const bool ss = cavitation == Cavitation::kSwiftStieber;
  const double barus = linear ? 0.0 : f.barus;
  const double dx = f.dx, dz = f.dz, C = f.couette;
  a.M.setZero(n);
  a.side_flow = a.west_flow = a.east_flow = a.squeeze_flow = 0;
  if (jacobian) {
    a.JP.assign(n, {0, 0, 0, 0, 0});
    a.JR.assign(n, {0, 0, 0, 0, 0});
  }
  // Fluidity mu0 / mu = exp(-alpha p) (Barus), taken as 1 below ambient; and its derivative.
  auto fluidity = [&](double p) { return barus > 0 && p > 0 ? std::exp(-barus * p) : 1.0; };
  auto dfluidity = [&](double p) { return barus > 0 && p > 0 ? -barus * std::exp(-barus * p) : 0.0; };
  const double area = dx * dz;

  for (int k = 0; k < nz; ++k) {
    const int row = nx * k;
    // This row's coefficients: per cell when given, else the per-column ones (the same for every row).
    const double* g_east = f.g_east_cells.empty() ? f.g_east.data() : f.g_east_cells.data() + row;
    const double* h_east = f.h_east_cells.empty() ? f.h_east.data() : f.h_east_cells.data() + row;
    const double* h_centre = f.h_centre_cells.empty() ? f.h_centre.data() : f.h_centre_cells.data() + row;
    const double* hdot = f.hdot_cells.empty() ? f.hdot.data() : f.hdot_cells.data() + row;
    const double* g_north = f.g_north_cells.empty() ? nullptr : f.g_north_cells.data() + row;
    // Faces between columns i and i + 1 along x (periodic, or the east end for the last column).
    for (int i = 0; i < nx; ++i) {
      const int w = row + i;
      const double G = g_east[i], H = h_east[i];
      if (i + 1 == nx && !f.periodic_x) {  // east end: P = p_east half a cell away, film from outside
        const double g = G * fluidity(P[w]);
        const double dP = f.p_east - P[w];
        const double fill = jfo ? (C >= 0 ? 1 - r[w] : f.fill_east) : 1.0;
        const double F = (-g * dP / (0.5 * dx) + C * H * fill) * dz;
        a.M[w] += F;
        a.east_flow += F;
        if (!jacobian) continue;
        a.JP[w][kSelf] += (g - G * dfluidity(P[w]) * dP) / (0.5 * dx) * dz;
        if (jfo && C >= 0) a.JR[w][kSelf] -= C * H * dz;
        continue;
      }
      const int e = row + (i + 1) % nx;
      const double fw = fluidity(P[w]), fe = fluidity(P[e]);
      const double g = G * 0.5 * (fw + fe);
      const int up = C >= 0 ? w : e;
      const double fill = jfo ? 1 - r[up] : 1.0;
      const double dP = P[e] - P[w];
      const double F = (-g * dP / dx + C * H * fill) * dz;
      a.M[w] += F;
      a.M[e] -= F;
      if (!jacobian) continue;
      const double dFw = (g / dx - G * 0.5 * dfluidity(P[w]) * dP / dx) * dz;
      const double dFe = (-g / dx - G * 0.5 * dfluidity(P[e]) * dP / dx) * dz;
      a.JP[w][kSelf] += dFw, a.JP[w][kEast] += dFe;
      a.JP[e][kWest] -= dFw, a.JP[e][kSelf] -= dFe;
      if (jfo) {
        const double dFr = -C * H * dz;
        if (up == w) {
          a.JR[w][kSelf] += dFr, a.JR[e][kWest] -= dFr;
        } else {
          a.JR[w][kEast] += dFr, a.JR[e][kSelf] -= dFr;
        }
      }
    }
    // West end (not periodic): P = p_west half a cell before column 0, a film of fill_west from outside.
    if (!f.periodic_x) {
      const int s = row;
      const double G = f.g_west_rows.empty() ? f.g_west : f.g_west_rows[k];
      const double H = f.h_west_rows.empty() ? f.h_west : f.h_west_rows[k];
      const double g = G * fluidity(P[s]);
      const double dP = P[s] - f.p_west;
      const double fill = jfo ? (C < 0 ? 1 - r[s] : f.fill_west) : 1.0;
      const double F = (-g * dP / (0.5 * dx) + C * H * fill) * dz;  // along +x, into the cell
      a.M[s] -= F;
      a.west_flow += F;
      if (jacobian) {
        a.JP[s][kSelf] += (g + G * dfluidity(P[s]) * dP) / (0.5 * dx) * dz;
        if (jfo && C < 0) a.JR[s][kSelf] += C * H * dz;
      }
    }
    // Faces across the width (the last row's to row 0 if periodic), and the two edges (P = 0 half a cell
    // away).
    const bool north = k + 1 < nz || f.periodic_z;
    for (int i = 0; i < nx; ++i) {
      const int s = row + i;
      const double H3 = h_centre[i] * h_centre[i] * h_centre[i];
      if (north) {
        const int nn = k + 1 < nz ? s + nx : i;
        const double Gn = g_north ? g_north[i] : H3;
        const double g = Gn * 0.5 * (fluidity(P[s]) + fluidity(P[nn]));
        const double dP = P[nn] - P[s];
        const double F = -g * dP / dz * dx;
        a.M[s] += F;
        a.M[nn] -= F;
        if (jacobian) {
          const double dFs = (g - Gn * 0.5 * dfluidity(P[s]) * dP) / dz * dx;
          const double dFn = (-g - Gn * 0.5 * dfluidity(P[nn]) * dP) / dz * dx;
          a.JP[s][kSelf] += dFs, a.JP[s][kNorth] += dFn;
          a.JP[nn][kSouth] -= dFs, a.JP[nn][kSelf] -= dFn;
        }
      }
      if (f.z_edges && (k == 0 || (k == nz - 1 && !f.mirror_north))) {
        const int edges = nz == 1 && !f.mirror_north ? 2 : 1;
        const double g = H3 * fluidity(P[s]);
        const double F = edges * g * P[s] / (0.5 * dz) * dx;
        a.M[s] += F;
        a.side_flow += F;
        if (jacobian) a.JP[s][kSelf] += edges * (g + H3 * dfluidity(P[s]) * P[s]) / (0.5 * dz) * dx;
      }
    }
    // Squeeze (quasi-steady: (1 - r) dH/dtau; with closing_film_full, dH/dtau where the film closes) and the
    // Swift-Stieber mass source.
    for (int i = 0; i < nx; ++i) {
      const int m = row + i;
      const bool fill_weighted = jfo && !(f.closing_film_full && hdot[i] < 0);
      const double squeeze = (fill_weighted ? 1 - r[m] : 1.0) * hdot[i] * area;
      a.M[m] += squeeze;
      a.squeeze_flow += squeeze;
      if (ss) a.M[m] -= r[m] * area;
      if (!jacobian) continue;
      if (fill_weighted) a.JR[m][kSelf] -= hdot[i] * area;
      if (ss) a.JR[m][kSelf] -= area;
    }
  }
  // Complementarity P >= 0, r >= 0, P r = 0 as min(P, r) = 0 (the primal-dual active-set form) or as
  // Fischer-Burmeister; kNone keeps r = 0 (Phi = r).
  a.Phi.resize(n), a.ap.resize(n), a.ar.resize(n);
  for (int m = 0; m < n; ++m) {
    if (cavitation == Cavitation::kNone || f.supply[m]) {
      a.Phi[m] = r[m], a.ap[m] = 0, a.ar[m] = 1;
      continue;
    }
    if (min_complementarity_) {
      const bool pressurized = P[m] > r[m];
      a.Phi[m] = pressurized ? r[m] : P[m];
      a.ap[m] = pressurized ? 0 : 1;
      a.ar[m] = pressurized ? 1 : 0;
      continue;
    }
    const double norm = std::hypot(P[m], r[m]);
    a.Phi[m] = P[m] + r[m] - norm;
    if (norm > 1e-300) {
      a.ap[m] = 1 - P[m] / norm, a.ar[m] = 1 - r[m] / norm;
    } else {
      a.ap[m] = a.ar[m] = 1 - std::sqrt(0.5);  // an element of the generalized Jacobian at (0, 0)
    }
  }
}

double FilmSolver::merit(const FilmAssembly& a) const {
  const double area = problem.dx * problem.dz;
  double f = 0;
  for (int m = 0; m < cells(); ++m) {
    if (problem.supply[m]) continue;
    const double mm = a.M[m] / area;
    f += mm * mm + a.Phi[m] * a.Phi[m];
  }
  return 0.5 * f;
}

// One Newton step: J_MP dP + J_MR dr = -M and ap dP + ar dr = -Phi per cell. Each cell keeps the unknown
// whose complementarity coefficient is smaller and eliminates the other (the larger coefficient is
// >= 1 - 1/sqrt(2)).
void FilmSolver::reduce(FilmAssembly& a, Eigen::VectorXd& rhs, bool matrix) {
  const int n = cells();
  const std::vector<char>& supply = problem.supply;
  a.primary_is_p.resize(n);
  for (int m = 0; m < n; ++m) a.primary_is_p[m] = a.ar[m] >= a.ap[m];
  double* values = linear_->A.valuePtr();
  rhs.resize(n);
  for (int m = 0; m < n; ++m) {
    if (supply[m]) {  // P = supply, r = 0 held: identity row
      for (int s = 0; s < 5 && matrix; ++s)
        if (linear_->value_index[m * 5 + s] >= 0)
          values[linear_->value_index[m * 5 + s]] = s == kSelf ? 1 : 0;
      rhs[m] = 0;
      continue;
    }
    double b = -a.M[m];
    for (int s = 0; s < 5; ++s) {
      const int j = neighbour_[m][s];
      if (j < 0 || supply[j]) {
        if (j >= 0 && matrix) values[linear_->value_index[m * 5 + s]] = 0;
        continue;
      }
      if (a.primary_is_p[j]) {
        b += a.JR[m][s] * a.Phi[j] / a.ar[j];
        if (matrix) values[linear_->value_index[m * 5 + s]] = a.JP[m][s] - a.JR[m][s] * a.ap[j] / a.ar[j];
      } else {
        b += a.JP[m][s] * a.Phi[j] / a.ap[j];
        if (matrix) values[linear_->value_index[m * 5 + s]] = a.JR[m][s] - a.JP[m][s] * a.ar[j] / a.ap[j];
      }
    }
    rhs[m] = b;
  }
}

bool FilmSolver::factorize_reduced(const FilmAssembly& a) {
  linear_->factored = false;
  ++factorizations_;
  if (!linear_->lu.factorize(linear_->A)) return false;
  linear_->factored = true;
  linear_->factor_primary = a.primary_is_p;
  return true;
}

void FilmSolver::cold_start(Eigen::VectorXd& P, Eigen::VectorXd& r) {
  if (!linear_) build_pattern();
  check_problem();
  const int n = cells();
  P.setZero(n);
  r.setZero(n);
  for (int m = 0; m < n; ++m)
    if (problem.supply[m]) P[m] = problem.supply_p;
  if (problem.cavitation == Cavitation::kNone) return;
  FilmAssembly a;
  assemble(P, r, true, a, /*linear=*/true);
  Eigen::VectorXd rhs;
  reduce(a, rhs, true);
  linear_->factored = false;  // the full-film matrix: not one for simplified steps
  if (!linear_->lu.factorize(linear_->A)) return;  // keep the zero start
  Eigen::VectorXd d = rhs;
  linear_->lu.solve(d);
  for (int m = 0; m < n; ++m) {
    if (problem.supply[m]) continue;
    const double p = P[m] + d[m];
    P[m] = std::max(p, 0.0);
    r[m] = p < 0 ? (problem.cavitation == Cavitation::kJfo ? 0.1 : 0.0) : 0.0;
  }
}

// With Barus viscosity the discrete equations also have spurious solutions: at high pressure the fluidity
// exp(-alpha p) vanishes, the fluxes with it, and the mass balance holds at any pressure. Newton, and
// Fischer-Burmeister's line search too (its merit keeps decreasing on the way), can run there: at eps 0.8 of
// the example in docs/bearing.md section 6 it "converged" to P ~ 1e32 (alpha p ~ 1e32), from which the next
// solves failed. Such a result, or a failed solve, is solved again by continuation in alpha: from the cold
// start (isoviscous full film), alpha raised in kBarusSteps steps, each solve warm-started from the last,
// which follows the physical branch from the isoviscous solution.
int FilmSolver::solve(Eigen::VectorXd& P, Eigen::VectorXd& r, const FiniteSolverOptions& options) {
  check_problem();
  // mu / mu0 = exp(alpha p) beyond e^30 (1e13): no longer a lubricant, and beyond Barus's law by far.
  constexpr double kRunaway = 30;
  constexpr int kBarusSteps = 8;
  const double barus = problem.barus;
  auto runaway = [&] { return barus > 0 && barus * P.maxCoeff() > kRunaway; };
  barus_isoviscous_ = 0;
  const int direct = solve_newton(P, r, options);
  if (barus <= 0 || (direct > 0 && !runaway())) return direct;
  int iterations = std::abs(direct), factorizations = factorizations_;
  cold_start(P, r);
  bool ok = true;
  for (int k = 0; k <= kBarusSteps && ok; ++k) {
    problem.barus = barus * k / kBarusSteps;
    const int it = solve_newton(P, r, options);
    iterations += std::abs(it);
    factorizations += factorizations_;
    ok = it > 0 && !runaway();
    if (k == 0) barus_isoviscous_ = barus * P.maxCoeff();
  }
  problem.barus = barus;
  factorizations_ = factorizations;
  return ok ? iterations : -iterations;
}

int FilmSolver::solve_newton(Eigen::VectorXd& P, Eigen::VectorXd& r, const FiniteSolverOptions& options) {
  if (!linear_) build_pattern();
  const int n = cells();
  FilmAssembly& a = last_;
  Eigen::VectorXd rhs, dP(n), dr(n);
  int iteration = 0;
  bool converged = false;
  double last_step = 0;
  // Active-set (min) Newton first: exact in one step once the cavitated cells are right, because the
  // discrete equations are linear in (P, r) for a given set (isoviscous). If it has not converged after
  // options.active_set_iterations, Fischer-Burmeister with line search (globally convergent) takes over.
  min_complementarity_ = true;
  // Simplified steps (an older factorization) while allowed; a step that contracts too little ends them.
  bool chord_allowed = options.reuse_factorization;
  double last_chord_step = 0;
  factorizations_ = 0;
  Eigen::VectorXd y(n), Pt(n), rt(n);
  FilmAssembly trial;
  // The fall-back from the active-set form (whole steps, no line search) to Fischer-Burmeister with its line
  // search, before active_set_iterations when the active-set matrix is singular (its 0/1 complementarity rows
  // can leave cells without a pressure equation). It starts again from this solve's start.
  P_start_ = P, r_start_ = r;  // sized at the first solve, reused after
  bool tried_cold_start = false;
  auto fall_back = [&] {
    min_complementarity_ = false;
    P = P_start_, r = r_start_;
    last_step = 0;
    chord_allowed = false;
  };
  for (; iteration < options.max_iterations && !converged; ++iteration) {
    if (iteration == options.active_set_iterations) min_complementarity_ = false;
    assemble(P, r, true, a);
    // A simplified step needs only the right-hand side: the reduced matrix is the factorized one's.
    bool chord = chord_allowed && min_complementarity_ && linear_->factored;
    reduce(a, rhs, !chord);
    if (chord && a.primary_is_p != linear_->factor_primary) {
      chord = false;
      reduce(a, rhs, true);  // another active set: the factorized matrix is for other unknowns
    }
    if (!chord && !factorize_reduced(a)) {
      // A singular matrix: the fall-back below (breaking out here ended the solve without trying it, at eps
      // 0.9 in the example of docs/bearing.md section 6); in the Fischer-Burmeister form, once from the cold
      // start.
      if (min_complementarity_) {
        fall_back();
        continue;
      }
      if (tried_cold_start) break;
      tried_cold_start = true;
      cold_start(P, r);
      last_step = 0;
      continue;
    }
    last_factorized_ = !chord;
    y = rhs;
    linear_->lu.solve(y);
    for (int m = 0; m < n; ++m) {
      if (problem.supply[m]) {
        dP[m] = dr[m] = 0;
      } else if (a.primary_is_p[m]) {
        dP[m] = y[m], dr[m] = (-a.Phi[m] - a.ap[m] * y[m]) / a.ar[m];
      } else {
        dr[m] = y[m], dP[m] = (-a.Phi[m] - a.ar[m] * y[m]) / a.ap[m];
      }
    }
    const double step = std::max(dP.lpNorm<Eigen::Infinity>() / (1 + P.lpNorm<Eigen::Infinity>()),
                                 dr.lpNorm<Eigen::Infinity>());
    // Backtracking (Armijo) on the merit 1/2 |residual|^2; the full step is taken near the solution.
    // A step below the tolerance is the last: the state is at the solution up to round-off.
    const double f0 = merit(a);
    double t = 1;
    double f1 = f0;
    for (int ls = 0; ls < 30 && step >= options.tolerance; ++ls) {
      Pt = P + t * dP, rt = r + t * dr;
      assemble(Pt, rt, false, trial);
      f1 = merit(trial);
      // Active-set steps are taken whole (their merit need not decrease while the set is being found).
      if (min_complementarity_ || f1 <= (1 - 1e-4 * t) * f0 || f0 < 1e-28) break;
      t *= 0.5;
    }
    P += t * dP;
    r += t * dr;
    // Converged when the step is below the tolerance; or when the residual at the new state is at round-off
    // level (the active-set step was exact); or, in the active-set phase (Newton, quadratic once the set is
    // right), when a full step shows a contraction step_k <= C step_{k-1}^2 that puts the next step,
    // C step_k^2, below the tolerance. (Not in the Fischer-Burmeister phase: its convergence near
    // degenerate cells can be linear.)
    // A simplified step converges linearly, at a rate rho = step / previous step (the last simplified solve's
    // rate for its first step): it has converged when the error left after it, rho / (1 - rho) step, is below
    // the tolerance (the test of simplified Newton in implicit integrators: Hairer and Wanner, Solving ODEs
    // II, section IV.8, eq. 8.10). A step that has not contracted by chord_contraction sends the next step to
    // a factorization.
    const double contraction = last_step > 0 ? step / (last_step * last_step) : 1e300;
    if (chord && last_chord_step > 0) chord_rate_ = step / last_chord_step;
    const bool chord_converged =
        chord && t == 1 && chord_rate_ < options.chord_contraction && chord_rate_ / (1 - chord_rate_) * step < options.tolerance;
    converged = step < options.tolerance || (t == 1 && std::sqrt(2 * f1) < options.tolerance * 1e-3) ||
                chord_converged ||
                (!chord && min_complementarity_ && t == 1 && step < 1e-3 && step < 0.1 * last_step &&
                 contraction * step * step < options.tolerance);
    if (chord && last_chord_step > 0 && step > options.chord_contraction * last_chord_step) chord_allowed = false;
    last_chord_step = chord ? step : 0.0;
    last_step = t == 1 && !chord ? step : 0.0;
  }
  return converged ? iteration : -iteration;
}

bool FilmSolver::factorize_at(const Eigen::VectorXd& P, const Eigen::VectorXd& r) {
  if (!linear_) build_pattern();
  check_problem();
  min_complementarity_ = true;
  assemble(P, r, true, last_);
  Eigen::VectorXd rhs;
  reduce(last_, rhs, true);
  if (!factorize_reduced(last_)) return false;
  last_factorized_ = true;
  return true;
}

void FilmSolver::solve_last(Eigen::VectorXd& b) {
  linear_->lu.solve(b);
}

}  // namespace nvh::bearing
