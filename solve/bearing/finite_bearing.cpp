#include "solve/bearing/finite_bearing.hpp"

#include <klu.h>

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "common/error.hpp"

namespace nvh::bearing {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr int kSelf = 0, kEast = 1, kWest = 2, kNorth = 3, kSouth = 4;

/// Angle wrapped to (-pi, pi].
double wrap(double a) {
  return std::remainder(a, 2 * kPi);
}
}  // namespace

/// Residuals and their derivatives at one state. Rows and stencil slots per cell.
struct FiniteBearing::Assembly {
  Eigen::VectorXd M;                      // mass balance: net outflow of each cell (nondimensional)
  Eigen::VectorXd Phi;                    // Fischer-Burmeister residual
  Eigen::VectorXd ap, ar;                 // dPhi/dP, dPhi/dr
  std::vector<std::array<double, 5>> JP;  // dM/dP of the stencil cells
  std::vector<std::array<double, 5>> JR;  // dM/dr of the stencil cells
  std::vector<char> primary_is_p;         // which unknown the reduced system keeps per cell
  double side_flow = 0;                   // nondimensional
};

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
      throw Error("finite bearing: KLU could not analyze the Reynolds matrix (status " +
                  std::to_string(common_.status) + ")");
  }
  /// Numeric factorization of `a` (same pattern as analyzed). False if the matrix is singular.
  bool factorize(Eigen::SparseMatrix<double>& a) {
    int* ap = a.outerIndexPtr();
    int* ai = a.innerIndexPtr();
    double* ax = a.valuePtr();
    if (numeric_ && klu_refactor(ap, ai, ax, symbolic_, numeric_, &common_) &&
        klu_rgrowth(ap, ai, ax, symbolic_, numeric_, &common_) && common_.rgrowth > 1e-8 &&
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

struct FiniteBearing::Solver {
  Eigen::SparseMatrix<double> A;
  std::vector<int> value_index;  // cell * 5 + slot -> index into A.valuePtr() (-1: absent)
  KluLu lu;
};

FiniteBearing::FiniteBearing(BearingSpec spec, FiniteSolverOptions options)
    : spec_(std::move(spec)), options_(options) {
  validate(spec_);
  nt_ = spec_.cells_around;
  nz_ = spec_.cells_across;
  n_ = nt_ * nz_;
  dtheta_ = 2 * kPi / nt_;
  dz_ = spec_.width / spec_.radius() / nz_;
  cos_c_.resize(nt_), sin_c_.resize(nt_), cos_f_.resize(nt_), sin_f_.resize(nt_);
  for (int i = 0; i < nt_; ++i) {
    cos_c_[i] = std::cos((i + 0.5) * dtheta_), sin_c_[i] = std::sin((i + 0.5) * dtheta_);
    cos_f_[i] = std::cos((i + 1.0) * dtheta_), sin_f_[i] = std::sin((i + 1.0) * dtheta_);
  }
  neighbour_.resize(n_);
  for (int k = 0; k < nz_; ++k) {
    for (int i = 0; i < nt_; ++i) {
      neighbour_[i + nt_ * k] = {i + nt_ * k, (i + 1) % nt_ + nt_ * k, (i + nt_ - 1) % nt_ + nt_ * k,
                                 k + 1 < nz_ ? i + nt_ * (k + 1) : -1, k > 0 ? i + nt_ * (k - 1) : -1};
    }
  }
  mark_supply_cells();
  P_ = Eigen::VectorXd::Zero(n_);
  r_ = Eigen::VectorXd::Zero(n_);
}

FiniteBearing::FiniteBearing(const FiniteBearing& o)
    : spec_(o.spec_),
      options_(o.options_),
      nt_(o.nt_),
      nz_(o.nz_),
      n_(o.n_),
      dtheta_(o.dtheta_),
      dz_(o.dz_),
      supply_(o.supply_),
      cos_c_(o.cos_c_),
      sin_c_(o.sin_c_),
      cos_f_(o.cos_f_),
      sin_f_(o.sin_f_),
      neighbour_(o.neighbour_),
      has_solution_(o.has_solution_),
      p_ref_of_solution_(o.p_ref_of_solution_),
      kinematics_of_solution_(o.kinematics_of_solution_),
      P_(o.P_),
      r_(o.r_),
      has_sensitivity_(o.has_sensitivity_),
      dP_dq_(o.dP_dq_),
      dr_dq_(o.dr_dq_) {}
FiniteBearing& FiniteBearing::operator=(const FiniteBearing& o) {
  if (this != &o) *this = FiniteBearing(o);
  return *this;
}
FiniteBearing::FiniteBearing(FiniteBearing&&) noexcept = default;
FiniteBearing& FiniteBearing::operator=(FiniteBearing&&) noexcept = default;
FiniteBearing::~FiniteBearing() = default;

// A cell is a supply cell if its centre lies in a hole or groove; a feature narrower than a cell takes
// the nearest cells so that it is never lost on a coarse grid.
void FiniteBearing::mark_supply_cells() {
  supply_.assign(n_, 0);
  const double R = spec_.radius(), L = spec_.width;
  auto theta_of = [&](int i) { return (i + 0.5) * dtheta_; };
  auto z_of = [&](int k) { return -0.5 * L + (k + 0.5) * L / nz_; };
  auto nearest_i = [&](double angle) {
    const double a = angle - 2 * kPi * std::floor(angle / (2 * kPi));
    return std::min(nt_ - 1, static_cast<int>(a / dtheta_));
  };
  auto nearest_k = [&](double z) {
    return std::clamp(static_cast<int>((z + 0.5 * L) / (L / nz_)), 0, nz_ - 1);
  };
  for (const FeedHole& h : spec_.holes) {
    bool any = false;
    for (int k = 0; k < nz_; ++k)
      for (int i = 0; i < nt_; ++i) {
        const double s = R * wrap(theta_of(i) - h.angle), dz = z_of(k) - h.axial_position;
        if (s * s + dz * dz <= 0.25 * h.diameter * h.diameter) supply_[i + nt_ * k] = 1, any = true;
      }
    if (!any) supply_[nearest_i(h.angle) + nt_ * nearest_k(h.axial_position)] = 1;
  }
  for (const Groove& g : spec_.grooves) {
    std::vector<int> rows, cols;
    if (g.kind == Groove::Kind::kCircumferential) {
      for (int k = 0; k < nz_; ++k)
        if (std::abs(z_of(k) - g.axial_position) <= 0.5 * g.width) rows.push_back(k);
      if (rows.empty()) rows.push_back(nearest_k(g.axial_position));
      const double span = g.arc_end - g.arc_start;
      for (int i = 0; i < nt_; ++i) {
        const double a = theta_of(i) - g.arc_start;
        if (span >= 2 * kPi - 1e-12 || a - 2 * kPi * std::floor(a / (2 * kPi)) <= span) cols.push_back(i);
      }
      if (cols.empty()) cols.push_back(nearest_i(0.5 * (g.arc_start + g.arc_end)));
    } else {
      for (int i = 0; i < nt_; ++i)
        if (std::abs(wrap(theta_of(i) - g.angle)) <= 0.5 * g.angular_width) cols.push_back(i);
      if (cols.empty()) cols.push_back(nearest_i(g.angle));
      for (int k = 0; k < nz_; ++k)
        if (std::abs(z_of(k) - g.axial_position) <= 0.5 * g.length) rows.push_back(k);
      if (rows.empty()) rows.push_back(nearest_k(g.axial_position));
    }
    for (int k : rows)
      for (int i : cols) supply_[i + nt_ * k] = 1;
  }
}

void FiniteBearing::build_pattern() {
  solver_ = std::make_unique<Solver>();
  std::vector<Eigen::Triplet<double>> t;
  for (int m = 0; m < n_; ++m)
    for (int s = 0; s < 5; ++s)
      if (neighbour_[m][s] >= 0) t.emplace_back(m, neighbour_[m][s], m * 5 + s + 1.0);  // tag: slot id + 1
  solver_->A.resize(n_, n_);
  solver_->A.setFromTriplets(t.begin(), t.end());
  solver_->A.makeCompressed();
  solver_->value_index.assign(5 * n_, -1);
  for (int v = 0; v < solver_->A.nonZeros(); ++v) {
    solver_->value_index[static_cast<int>(solver_->A.valuePtr()[v]) - 1] = v;
  }
  solver_->lu.analyze(solver_->A);
}

// Nondimensional variables: H = h/c, Z = z/R, P = p / p_ref with p_ref = 12 mu0 R^2 omega_ref / c^2, time
// tau = omega_ref t. The Reynolds equation becomes
//   div(H^3 / mu_r grad P) = (omega_m / omega_ref) dH/dtheta + dH/dtau,   mu_r = mu / mu0 = exp(alpha p).
void FiniteBearing::set_motion(const Kinematics& k) {
  const double c = spec_.radial_clearance, R = spec_.radius(), mu = spec_.viscosity;
  const double wm = 0.5 * (k.omega_journal + k.omega_shell);
  const double supply_scale = spec_.supply_pressure * c * c / (12 * mu * R * R);
  omega_ref_ = std::max({std::abs(wm), k.e_dot.norm() / c, supply_scale, 1e-9});
  p_ref_ = 12 * mu * R * R * omega_ref_ / (c * c);
  couette_ = wm / omega_ref_;
  barus_ = spec_.barus * p_ref_;
  supply_p_ = spec_.supply_pressure / p_ref_;
  const double ex = k.e.x() / c, ey = k.e.y() / c;
  h_c_.resize(nt_), h_f_.resize(nt_), hdot_.resize(nt_);
  for (int i = 0; i < nt_; ++i) {
    h_c_[i] = 1 - ex * cos_c_[i] - ey * sin_c_[i];
    h_f_[i] = 1 - ex * cos_f_[i] - ey * sin_f_[i];
    hdot_[i] = -(k.e_dot.x() * cos_c_[i] + k.e_dot.y() * sin_c_[i]) / (c * omega_ref_);
  }
}

void FiniteBearing::assemble(const Eigen::VectorXd& P, const Eigen::VectorXd& r, bool jacobian, Assembly& a,
                             bool linear) const {
  const Cavitation cavitation = linear ? Cavitation::kNone : spec_.cavitation;
  const bool jfo = cavitation == Cavitation::kJfo;
  const bool ss = cavitation == Cavitation::kSwiftStieber;
  const double barus = linear ? 0.0 : barus_;
  a.M.setZero(n_);
  a.side_flow = 0;
  if (jacobian) {
    a.JP.assign(n_, {0, 0, 0, 0, 0});
    a.JR.assign(n_, {0, 0, 0, 0, 0});
  }
  // Fluidity mu0 / mu = exp(-alpha p) (Barus), taken as 1 below ambient; and its derivative.
  auto fluidity = [&](double p) { return barus > 0 && p > 0 ? std::exp(-barus * p) : 1.0; };
  auto dfluidity = [&](double p) { return barus > 0 && p > 0 ? -barus * std::exp(-barus * p) : 0.0; };
  const double area = dtheta_ * dz_;

  for (int k = 0; k < nz_; ++k) {
    const int row = nt_ * k;
    // Faces between cells i and i + 1 around the circumference (periodic).
    for (int i = 0; i < nt_; ++i) {
      const int w = row + i, e = row + (i + 1) % nt_;
      const double H = h_f_[i], H3 = H * H * H;
      const double fw = fluidity(P[w]), fe = fluidity(P[e]);
      const double g = H3 * 0.5 * (fw + fe);
      const int up = couette_ >= 0 ? w : e;
      const double fill = jfo ? 1 - r[up] : 1.0;
      const double dP = P[e] - P[w];
      const double F = (-g * dP / dtheta_ + couette_ * H * fill) * dz_;
      a.M[w] += F;
      a.M[e] -= F;
      if (!jacobian) continue;
      const double dFw = (g / dtheta_ - H3 * 0.5 * dfluidity(P[w]) * dP / dtheta_) * dz_;
      const double dFe = (-g / dtheta_ - H3 * 0.5 * dfluidity(P[e]) * dP / dtheta_) * dz_;
      a.JP[w][kSelf] += dFw, a.JP[w][kEast] += dFe;
      a.JP[e][kWest] -= dFw, a.JP[e][kSelf] -= dFe;
      if (jfo) {
        const double dFr = -couette_ * H * dz_;
        if (up == w) {
          a.JR[w][kSelf] += dFr, a.JR[e][kWest] -= dFr;
        } else {
          a.JR[w][kEast] += dFr, a.JR[e][kSelf] -= dFr;
        }
      }
    }
    // Faces across the width, and the two edges (p = 0 half a cell away).
    for (int i = 0; i < nt_; ++i) {
      const int s = row + i;
      const double H3 = h_c_[i] * h_c_[i] * h_c_[i];
      if (k + 1 < nz_) {
        const int n = s + nt_;
        const double g = H3 * 0.5 * (fluidity(P[s]) + fluidity(P[n]));
        const double dP = P[n] - P[s];
        const double F = -g * dP / dz_ * dtheta_;
        a.M[s] += F;
        a.M[n] -= F;
        if (jacobian) {
          const double dFs = (g - H3 * 0.5 * dfluidity(P[s]) * dP) / dz_ * dtheta_;
          const double dFn = (-g - H3 * 0.5 * dfluidity(P[n]) * dP) / dz_ * dtheta_;
          a.JP[s][kSelf] += dFs, a.JP[s][kNorth] += dFn;
          a.JP[n][kSouth] -= dFs, a.JP[n][kSelf] -= dFn;
        }
      }
      if (k == 0 || k == nz_ - 1) {
        const int edges = nz_ == 1 ? 2 : 1;
        const double g = H3 * fluidity(P[s]);
        const double F = edges * g * P[s] / (0.5 * dz_) * dtheta_;
        a.M[s] += F;
        a.side_flow += F;
        if (jacobian) a.JP[s][kSelf] += edges * (g + H3 * dfluidity(P[s]) * P[s]) / (0.5 * dz_) * dtheta_;
      }
    }
    // Squeeze (quasi-steady: (1 - r) dH/dtau) and the Swift-Stieber mass source.
    for (int i = 0; i < nt_; ++i) {
      const int m = row + i;
      a.M[m] += (jfo ? 1 - r[m] : 1.0) * hdot_[i] * area;
      if (ss) a.M[m] -= r[m] * area;
      if (!jacobian) continue;
      if (jfo) a.JR[m][kSelf] -= hdot_[i] * area;
      if (ss) a.JR[m][kSelf] -= area;
    }
  }
  // Complementarity p >= 0, r >= 0, p r = 0 as min(p, r) = 0 (the primal-dual active-set form) or as
  // Fischer-Burmeister; kNone keeps r = 0 (Phi = r).
  a.Phi.resize(n_), a.ap.resize(n_), a.ar.resize(n_);
  for (int m = 0; m < n_; ++m) {
    if (cavitation == Cavitation::kNone || supply_[m]) {
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

double FiniteBearing::merit(const Assembly& a) const {
  const double area = dtheta_ * dz_;
  double f = 0;
  for (int m = 0; m < n_; ++m) {
    if (supply_[m]) continue;
    const double mm = a.M[m] / area;
    f += mm * mm + a.Phi[m] * a.Phi[m];
  }
  return 0.5 * f;
}

// One Newton step: J_MP dP + J_MR dr = -M and ap dP + ar dr = -Phi per cell. Each cell keeps the unknown
// whose FB coefficient is smaller and eliminates the other (the larger coefficient is >= 1 - 1/sqrt(2)).
void FiniteBearing::reduce(Assembly& a, Eigen::VectorXd& rhs) {
  a.primary_is_p.resize(n_);
  for (int m = 0; m < n_; ++m) a.primary_is_p[m] = a.ar[m] >= a.ap[m];
  double* values = solver_->A.valuePtr();
  rhs.resize(n_);
  for (int m = 0; m < n_; ++m) {
    if (supply_[m]) {  // P = supply, r = 0 held: identity row
      for (int s = 0; s < 5; ++s)
        if (solver_->value_index[m * 5 + s] >= 0)
          values[solver_->value_index[m * 5 + s]] = s == kSelf ? 1 : 0;
      rhs[m] = 0;
      continue;
    }
    double b = -a.M[m];
    for (int s = 0; s < 5; ++s) {
      const int j = neighbour_[m][s];
      if (j < 0) continue;
      double v = 0;
      if (!supply_[j]) {
        if (a.primary_is_p[j]) {
          v = a.JP[m][s] - a.JR[m][s] * a.ap[j] / a.ar[j];
          b += a.JR[m][s] * a.Phi[j] / a.ar[j];
        } else {
          v = a.JR[m][s] - a.JP[m][s] * a.ar[j] / a.ap[j];
          b += a.JP[m][s] * a.Phi[j] / a.ap[j];
        }
      }
      values[solver_->value_index[m * 5 + s]] = v;
    }
    rhs[m] = b;
  }
}

// Cold start: the full-film (linear, isoviscous) solution, negative pressures clipped to zero and the
// cells they leave marked as partly filled.
void FiniteBearing::cold_start() {
  P_.setZero(n_);
  r_.setZero(n_);
  for (int m = 0; m < n_; ++m)
    if (supply_[m]) P_[m] = supply_p_;
  if (spec_.cavitation == Cavitation::kNone) return;
  Assembly a;
  assemble(P_, r_, true, a, /*linear=*/true);
  Eigen::VectorXd rhs;
  reduce(a, rhs);
  if (!solver_->lu.factorize(solver_->A)) return;  // keep the zero start
  Eigen::VectorXd d = rhs;
  solver_->lu.solve(d);
  for (int m = 0; m < n_; ++m) {
    if (supply_[m]) continue;
    const double p = P_[m] + d[m];
    P_[m] = std::max(p, 0.0);
    r_[m] = p < 0 ? (spec_.cavitation == Cavitation::kJfo ? 0.1 : 0.0) : 0.0;
  }
}

FilmResult FiniteBearing::evaluate(const Kinematics& k) {
  check_eccentricity(spec_, k);
  if (!solver_) build_pattern();
  set_motion(k);
  if (!has_solution_) {
    cold_start();
  } else {
    if (has_sensitivity_) predict(k);
    P_ *= p_ref_of_solution_ / p_ref_;  // same dimensional pressures under the new scale
    for (int m = 0; m < n_; ++m)
      if (supply_[m]) P_[m] = supply_p_, r_[m] = 0;
  }
  Assembly a;
  Eigen::VectorXd rhs, dP(n_), dr(n_);
  int iteration = 0;
  bool converged = false;
  double last_step = 0;
  // Active-set (min) Newton first: exact in one step once the cavitated cells are right, because the
  // discrete equations are linear in (p, r) for a given set (isoviscous). If it has not converged after
  // kActiveSetIterations, Fischer-Burmeister with line search (globally convergent) takes over.
  constexpr int kActiveSetIterations = 12;
  min_complementarity_ = true;
  for (; iteration < options_.max_iterations && !converged; ++iteration) {
    if (iteration == kActiveSetIterations) min_complementarity_ = false;
    assemble(P_, r_, true, a);
    reduce(a, rhs);
    if (!solver_->lu.factorize(solver_->A)) break;
    Eigen::VectorXd y = rhs;
    solver_->lu.solve(y);
    for (int m = 0; m < n_; ++m) {
      if (supply_[m]) {
        dP[m] = dr[m] = 0;
      } else if (a.primary_is_p[m]) {
        dP[m] = y[m], dr[m] = (-a.Phi[m] - a.ap[m] * y[m]) / a.ar[m];
      } else {
        dr[m] = y[m], dP[m] = (-a.Phi[m] - a.ar[m] * y[m]) / a.ap[m];
      }
    }
    const double step = std::max(dP.lpNorm<Eigen::Infinity>() / (1 + P_.lpNorm<Eigen::Infinity>()),
                                 dr.lpNorm<Eigen::Infinity>());
    // Backtracking (Armijo) on the merit 1/2 |residual|^2; the full step is taken near the solution.
    // A step below the tolerance is the last: the state is at the solution up to round-off.
    const double f0 = merit(a);
    double t = 1;
    Assembly trial;
    double f1 = f0;
    for (int ls = 0; ls < 30 && step >= options_.tolerance; ++ls) {
      assemble(P_ + t * dP, r_ + t * dr, false, trial);
      f1 = merit(trial);
      // Active-set steps are taken whole (their merit need not decrease while the set is being found).
      if (min_complementarity_ || f1 <= (1 - 1e-4 * t) * f0 || f0 < 1e-28) break;
      t *= 0.5;
    }
    P_ += t * dP;
    r_ += t * dr;
    // Converged when the step is below the tolerance; or when the residual at the new state is at round-off
    // level (the active-set step was exact); or, in the active-set phase (Newton, quadratic once the set is
    // right), when a full step shows a contraction step_k <= C step_{k-1}^2 that puts the next step,
    // C step_k^2, below the tolerance. (Not in the Fischer-Burmeister phase: its convergence near
    // degenerate cells can be linear.)
    const double contraction = last_step > 0 ? step / (last_step * last_step) : 1e300;
    converged = step < options_.tolerance || (t == 1 && std::sqrt(2 * f1) < options_.tolerance * 1e-3) ||
                (min_complementarity_ && t == 1 && step < 1e-3 && step < 0.1 * last_step &&
                 contraction * step * step < options_.tolerance);
    last_step = t == 1 ? step : 0.0;
  }
  if (!converged) {
    has_solution_ = false;
    std::ostringstream msg;
    msg << "bearing '" << spec_.name << "': the finite-bearing Newton solve did not converge in " << iteration
        << " iterations at e = (" << k.e.x() << ", " << k.e.y() << ") m, de/dt = (" << k.e_dot.x() << ", "
        << k.e_dot.y() << ") m/s; try a finer grid or check the input";
    throw Error(msg.str());
  }
  has_solution_ = true;
  has_sensitivity_ = false;
  p_ref_of_solution_ = p_ref_;
  kinematics_of_solution_ = k;
  Assembly final_state;
  assemble(P_, r_, false, final_state);
  FilmResult result = post_process(k, final_state);
  result.iterations = iteration;
  // The last factorization belongs to the state one (tiny) step before: within the tolerance of the solution.
  if (options_.jacobian) parameter_jacobian(a, result);
  return result;
}

FilmResult FiniteBearing::post_process(const Kinematics& k, const Assembly& a) const {
  const double R = spec_.radius(), c = spec_.radial_clearance, mu0 = spec_.viscosity;
  const bool jfo = spec_.cavitation == Cavitation::kJfo;
  const double dA = R * R * dtheta_ * dz_;           // m^2 per cell
  const double flow_scale = c * R * R * omega_ref_;  // m^3/s per unit of nondimensional flux
  FilmResult r;
  set_min_film(spec_, k, r);
  const double Uj = R * k.omega_journal, Us = R * k.omega_shell;
  int m_max = 0;
  for (int kz = 0; kz < nz_; ++kz) {
    for (int i = 0; i < nt_; ++i) {
      const int m = i + nt_ * kz;
      const double p = p_ref_ * P_[m];
      r.force -= p * dA * Eigen::Vector2d(cos_c_[i], sin_c_[i]);
      const double h = c * h_c_[i];
      const double mu = spec_.barus > 0 && p > 0 ? mu0 * std::exp(spec_.barus * p) : mu0;
      const double fill = jfo ? 1 - r_[m] : 1.0;
      const int e = neighbour_[m][kEast], w = neighbour_[m][kWest];
      const double dpdx = p_ref_ * (P_[e] - P_[w]) / (2 * R * dtheta_);
      r.torque_journal += R * dA * (mu * (Us - Uj) / h * fill - 0.5 * h * dpdx);
      r.torque_shell += R * dA * (mu * (Uj - Us) / h * fill - 0.5 * h * dpdx);
      if (P_[m] > P_[m_max]) m_max = m;
      if (supply_[m]) r.feed_flow += flow_scale * a.M[m];
    }
  }
  // Peak pressure: parabola through the highest cell and its two circumferential neighbours.
  const double pc = P_[m_max], pe = P_[neighbour_[m_max][kEast]], pw = P_[neighbour_[m_max][kWest]];
  const double curv = pe - 2 * pc + pw;
  double shift = curv < 0 ? 0.5 * (pw - pe) / curv : 0.0;
  shift = std::clamp(shift, -0.5, 0.5);
  r.max_pressure = p_ref_ * (pc - 0.125 * (pe - pw) * (pe - pw) / (curv < 0 ? curv : -1e300));
  r.max_pressure_angle = wrap(((m_max % nt_) + 0.5 + shift) * dtheta_);
  r.side_flow = flow_scale * a.side_flow;
  r.power_loss =
      -(r.torque_journal * k.omega_journal + r.torque_shell * k.omega_shell + r.force.dot(k.e_dot));
  return r;
}

// d(force)/d(q), q = (ex, ey, ex_dot, ey_dot): J du/dq = -dG/dq with G = (M, Phi); Phi does not depend on q,
// so the reduced system takes -dM/dq as its right-hand side. Then dF/dq = -sum p_ref dP/dq n dA.
void FiniteBearing::parameter_jacobian(const Assembly& a, FilmResult& result) {
  dP_dq_.resize(n_, 4);
  dr_dq_.resize(n_, 4);
  const double c = spec_.radial_clearance, R = spec_.radius();
  const bool jfo = spec_.cavitation == Cavitation::kJfo;
  auto fluidity = [&](double p) { return barus_ > 0 && p > 0 ? std::exp(-barus_ * p) : 1.0; };
  const double area = dtheta_ * dz_;
  for (int q = 0; q < 4; ++q) {
    Eigen::VectorXd dM = Eigen::VectorXd::Zero(n_);
    for (int k = 0; k < nz_; ++k) {
      const int row = nt_ * k;
      for (int i = 0; i < nt_; ++i) {
        if (q < 2) {  // position: the film thickness changes, dH/de = -n / c
          const double dHf = -(q == 0 ? cos_f_[i] : sin_f_[i]) / c;
          const double dHc = -(q == 0 ? cos_c_[i] : sin_c_[i]) / c;
          const int w = row + i, e = row + (i + 1) % nt_;
          const double H = h_f_[i];
          const int up = couette_ >= 0 ? w : e;
          const double fill = jfo ? 1 - r_[up] : 1.0;
          const double g = 3 * H * H * dHf * 0.5 * (fluidity(P_[w]) + fluidity(P_[e]));
          const double dF = (-g * (P_[e] - P_[w]) / dtheta_ + couette_ * dHf * fill) * dz_;
          dM[w] += dF;
          dM[e] -= dF;
          const int s = row + i;
          const double Hc = h_c_[i];
          if (k + 1 < nz_) {
            const int n = s + nt_;
            const double gz = 3 * Hc * Hc * dHc * 0.5 * (fluidity(P_[s]) + fluidity(P_[n]));
            const double F = -gz * (P_[n] - P_[s]) / dz_ * dtheta_;
            dM[s] += F;
            dM[n] -= F;
          }
          if (k == 0 || k == nz_ - 1) {
            const int edges = nz_ == 1 ? 2 : 1;
            dM[s] += edges * 3 * Hc * Hc * dHc * fluidity(P_[s]) * P_[s] / (0.5 * dz_) * dtheta_;
          }
        } else {  // velocity: the squeeze term, dHdot/de_dot = -n / (c omega_ref)
          const double dHdot = -(q == 2 ? cos_c_[i] : sin_c_[i]) / (c * omega_ref_);
          const int m = row + i;
          dM[m] += (jfo ? 1 - r_[m] : 1.0) * dHdot * area;
        }
      }
    }
    Eigen::VectorXd rhs(n_);
    for (int m = 0; m < n_; ++m) rhs[m] = supply_[m] ? 0.0 : -dM[m];
    Eigen::VectorXd y = rhs;
    solver_->lu.solve(y);
    Eigen::Vector2d dF = Eigen::Vector2d::Zero();
    for (int m = 0; m < n_; ++m) {
      if (supply_[m]) {
        dP_dq_(m, q) = dr_dq_(m, q) = 0;
        continue;
      }
      // Phi does not depend on q: ap dP + ar dr = 0 in every cell.
      const double dP = a.primary_is_p[m] ? y[m] : -a.ar[m] / a.ap[m] * y[m];
      dP_dq_(m, q) = dP;
      dr_dq_(m, q) = a.primary_is_p[m] ? -a.ap[m] / a.ar[m] * y[m] : y[m];
      const int i = m % nt_;
      dF -= p_ref_ * dP * R * R * area * Eigen::Vector2d(cos_c_[i], sin_c_[i]);
    }
    result.jacobian.col(q) = dF;
  }
  has_sensitivity_ = true;
}

// Tangent predictor: the last solution moved along its sensitivities to the new (e, de/dt), projected onto
// p >= 0, r >= 0. Exact to first order while the cavitation boundary stays in its cells.
void FiniteBearing::predict(const Kinematics& k) {
  Eigen::Vector4d dq;
  dq << k.e - kinematics_of_solution_.e, k.e_dot - kinematics_of_solution_.e_dot;
  P_ = (P_ + dP_dq_ * dq).cwiseMax(0.0);
  r_ = (r_ + dr_dq_ * dq).cwiseMax(0.0);
}

Eigen::MatrixXd FiniteBearing::pressure() const {
  Eigen::MatrixXd p(nt_, nz_);
  for (int k = 0; k < nz_; ++k)
    for (int i = 0; i < nt_; ++i) p(i, k) = has_solution_ ? p_ref_of_solution_ * P_[i + nt_ * k] : 0.0;
  return p;
}

Eigen::MatrixXd FiniteBearing::fill_ratio() const {
  Eigen::MatrixXd f = Eigen::MatrixXd::Ones(nt_, nz_);
  if (spec_.cavitation == Cavitation::kJfo && has_solution_)
    for (int k = 0; k < nz_; ++k)
      for (int i = 0; i < nt_; ++i) f(i, k) = 1 - r_[i + nt_ * k];
  return f;
}

Eigen::MatrixXi FiniteBearing::supply_cells() const {
  Eigen::MatrixXi s(nt_, nz_);
  for (int k = 0; k < nz_; ++k)
    for (int i = 0; i < nt_; ++i) s(i, k) = supply_[i + nt_ * k];
  return s;
}

}  // namespace nvh::bearing
