#include "solve/bearing/finite_bearing.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "common/error.hpp"

namespace nvh::bearing {

namespace {
constexpr double kPi = std::numbers::pi;

/// Angle wrapped to (-pi, pi].
double wrap(double a) {
  return std::remainder(a, 2 * kPi);
}
}  // namespace

FiniteBearing::FiniteBearing(BearingSpec spec, FiniteSolverOptions options)
    : spec_(std::move(spec)), options_(options) {
  validate(spec_);
  nt_ = spec_.cells_around;
  nz_ = spec_.cells_across;
  dtheta_ = 2 * kPi / nt_;
  dz_ = spec_.width / spec_.radius() / nz_;
  cos_c_.resize(nt_), sin_c_.resize(nt_), cos_f_.resize(nt_), sin_f_.resize(nt_);
  for (int i = 0; i < nt_; ++i) {
    cos_c_[i] = std::cos((i + 0.5) * dtheta_), sin_c_[i] = std::sin((i + 0.5) * dtheta_);
    cos_f_[i] = std::cos((i + 1.0) * dtheta_), sin_f_[i] = std::sin((i + 1.0) * dtheta_);
  }
  FilmProblem& f = film_.problem;
  f.periodic_x = true;
  f.z_edges = true;
  f.cavitation = spec_.cavitation;
  // The grid of the whole width; then, if it mirrors onto itself about the mid-plane, its half z < 0 with
  // a symmetry edge at the mid-plane: rows_ = nz_ / 2, and every sum over the cells counts twice.
  const std::vector<char> whole = supply_cells_of_whole_grid();
  bool symmetric = options_.mirror_symmetry && nz_ % 2 == 0;
  for (int k = 0; k < nz_ / 2 && symmetric; ++k)
    for (int i = 0; i < nt_ && symmetric; ++i)
      symmetric = whole[i + nt_ * k] == whole[i + nt_ * (nz_ - 1 - k)];
  rows_ = symmetric ? nz_ / 2 : nz_;
  weight_ = symmetric ? 2.0 : 1.0;
  n_ = nt_ * rows_;
  f.nx = nt_, f.nz = rows_, f.dx = dtheta_, f.dz = dz_;
  f.mirror_north = symmetric;
  f.supply.assign(whole.begin(), whole.begin() + n_);
  P_ = Eigen::VectorXd::Zero(n_);
  r_ = Eigen::VectorXd::Zero(n_);
}

// A cell is a supply cell if its centre lies in a hole or groove; a feature narrower than a cell takes
// the nearest cells so that it is never lost on a coarse grid.
std::vector<char> FiniteBearing::supply_cells_of_whole_grid() const {
  std::vector<char> supply(static_cast<std::size_t>(nt_) * nz_, 0);
  const double R = spec_.radius(), L = spec_.width;
  auto theta_of = [&](int i) { return (i + 0.5) * dtheta_; };
  auto z_of = [&](int k) { return -0.5 * L + (k + 0.5) * L / nz_; };
  // A cell index from a position in cells: clamped to [0, n - 1] before the conversion to int, which is
  // undefined for NaN and for values beyond int (a non-finite hole angle once wrote outside `supply`).
  auto cell = [](double x, int n) {
    return x >= 0 ? static_cast<int>(std::min(x, static_cast<double>(n - 1))) : 0;
  };
  auto nearest_i = [&](double angle) {
    const double a = angle - 2 * kPi * std::floor(angle / (2 * kPi));
    return cell(a / dtheta_, nt_);
  };
  auto nearest_k = [&](double z) { return cell((z + 0.5 * L) / (L / nz_), nz_); };
  for (const FeedHole& h : spec_.holes) {
    bool any = false;
    for (int k = 0; k < nz_; ++k)
      for (int i = 0; i < nt_; ++i) {
        const double s = R * wrap(theta_of(i) - h.angle), dz = z_of(k) - h.axial_position;
        if (s * s + dz * dz <= 0.25 * h.diameter * h.diameter) supply[i + nt_ * k] = 1, any = true;
      }
    if (!any) supply[nearest_i(h.angle) + nt_ * nearest_k(h.axial_position)] = 1;
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
      for (int i : cols) supply[i + nt_ * k] = 1;
  }
  return supply;
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
  FilmProblem& f = film_.problem;
  f.couette = wm / omega_ref_;
  f.barus = spec_.barus * p_ref_;
  f.supply_p = spec_.supply_pressure / p_ref_;
  const double ex = k.e.x() / c, ey = k.e.y() / c;
  f.g_east.resize(nt_), f.h_east.resize(nt_), f.h_centre.resize(nt_), f.hdot.resize(nt_);
  for (int i = 0; i < nt_; ++i) {
    f.h_centre[i] = 1 - ex * cos_c_[i] - ey * sin_c_[i];
    f.h_east[i] = 1 - ex * cos_f_[i] - ey * sin_f_[i];  // the exact film at the face
    f.g_east[i] = f.h_east[i] * f.h_east[i] * f.h_east[i];
    f.hdot[i] = -(k.e_dot.x() * cos_c_[i] + k.e_dot.y() * sin_c_[i]) / (c * omega_ref_);
  }
}

// The film at k. Newton from the tangent prediction of the last solution; if that does not converge (or there
// is none), from the cold start (the full film, clipped); then by continuation in the squeeze velocity: the
// cold start at de/dt = 0 (the wedge film alone) and de/dt raised to its value in kSqueezeSteps steps, each
// warm-started from the one before. Each start fails somewhere in squeeze-dominated states: in the engine
// with finite main bearings (docs/engine.md), at |e|/c 0.2-0.4 with |de/dt| / c 500-1000 1/s against a mean
// speed of 100 rad/s, the cold start did not converge in 60 iterations at 1 in 10 of the states within 2 % of
// each other (test SqueezeDominatedEngineStateConvergesFromTheColdStart), and the warm start from a
// neighbouring solution failed where the cold start converged in 6. The discrete solution does not depend on
// the path (it is the solution of the discrete equations at k to the tolerance); only the start changes. On
// failure the last solution is kept as the start of the next call.
int FiniteBearing::solve_film(const Kinematics& k) {
  constexpr int kSqueezeSteps = 4;
  const std::vector<char>& supply = film_.problem.supply;
  auto hold_supply = [&] {
    for (int m = 0; m < n_; ++m)
      if (supply[m]) P_[m] = film_.problem.supply_p, r_[m] = 0;
  };
  int total = 0;
  // Simplified steps (an older factorization) only from the warm start: after it, the factorization and
  // the contraction rate they rely on belong to another state. From the cold start or along the
  // continuation they failed to converge where full Newton converges, and once stopped at a false solution
  // (test FallbackStartsUseFullNewton: an engine state near the half-speed whirl).
  FiniteSolverOptions full_newton = options_;
  full_newton.reuse_factorization = false;
  bool warm = false;
  auto converged = [&] {
    const int it = film_.solve(P_, r_, warm ? options_ : full_newton);
    total += std::abs(it);
    return it > 0;
  };
  set_motion(k);
  if (has_solution_) {
    P_good_ = P_, r_good_ = r_;  // in the scale of the solution, p_ref_of_solution_
    if (has_sensitivity_) predict(k);
    P_ *= p_ref_of_solution_ / p_ref_;  // same dimensional pressures under the new scale
    hold_supply();
    warm = true;
    if (converged()) return total;
    warm = false;
  }
  film_.cold_start(P_, r_);
  if (converged()) return total;
  Kinematics step = k;
  double p_ref_before = 0;
  bool ok = true;
  for (int s = 0; s <= kSqueezeSteps && ok; ++s) {
    step.e_dot = k.e_dot * (static_cast<double>(s) / kSqueezeSteps);  // exactly k.e_dot at the last step
    set_motion(step);
    if (s == 0) {
      film_.cold_start(P_, r_);
    } else {
      P_ *= p_ref_before / p_ref_;
      hold_supply();
    }
    p_ref_before = p_ref_;
    ok = converged();
  }
  if (ok) return total;
  if (has_solution_) P_ = P_good_, r_ = r_good_;
  return -total;
}

FilmResult FiniteBearing::evaluate(const Kinematics& k, Detail detail) {
  check_eccentricity(spec_, k);
  const int iterations = solve_film(k);
  if (iterations < 0) {
    std::ostringstream msg;
    msg << "bearing '" << spec_.name << "': the finite-bearing Newton solve did not converge (" << -iterations
        << " iterations: from the last solution, the cold start and by continuation in de/dt) at e = ("
        << k.e.x() << ", " << k.e.y() << ") m, de/dt = (" << k.e_dot.x() << ", " << k.e_dot.y()
        << ") m/s, omega journal " << k.omega_journal << " rad/s, shell " << k.omega_shell << " rad/s";
    if (film_.barus_isoviscous_product() >= 1)
      msg << "; with Barus viscosity, alpha x the isoviscous peak pressure is "
          << film_.barus_isoviscous_product()
          << " >= 1: the piezoviscous pressure has no bound in this model (a lower eccentricity, barus or "
             "speed; "
             "docs/bearing.md section 11)";
    else
      msg << "; try a finer grid or check the input";
    throw Error(msg.str());
  }
  has_solution_ = true;
  p_ref_of_solution_ = p_ref_;
  kinematics_of_solution_ = k;
  // The flows need the fluxes at the solution (one more assembly); forces and torques need only (P, r).
  const bool flows = detail == Detail::kFull;
  if (flows) film_.assemble(P_, r_, false, final_state_);
  FilmResult result = post_process(k, flows ? &final_state_ : nullptr);
  result.iterations = iterations;
  result.factorizations = film_.factorizations();
  // The last factorization belongs to the state one (tiny) step before: within the tolerance of the solution.
  // After a simplified step it belongs to an older state: then the sensitivities of the last factorized
  // solution stay for the predictor, and the result carries no Jacobian (evaluate_with_jacobian gives one).
  if (options_.jacobian && film_.last_step_was_factorized()) parameter_jacobian(film_.last_step(), result);
  return result;
}

FilmResult FiniteBearing::evaluate_with_jacobian(const Kinematics& k, Detail detail) {
  FilmResult result = evaluate(k, detail);
  if (!options_.jacobian || result.has_full_jacobian) return result;
  if (!film_.factorize_at(P_, r_))
    throw Error("bearing '" + spec_.name + "': the film's Newton matrix is singular at the solution");
  ++result.factorizations;
  parameter_jacobian(film_.last_step(), result);
  return result;
}

FilmResult FiniteBearing::post_process(const Kinematics& k, const FilmAssembly* a) const {
  const double R = spec_.radius(), c = spec_.radial_clearance, mu0 = spec_.viscosity;
  const bool jfo = spec_.cavitation == Cavitation::kJfo;
  const FilmProblem& f = film_.problem;
  const double dA = R * R * dtheta_ * dz_;           // m^2 per cell
  const double flow_scale = c * R * R * omega_ref_;  // m^3/s per unit of nondimensional flux
  FilmResult r;
  set_min_film(spec_, k, r);
  const double Uj = R * k.omega_journal, Us = R * k.omega_shell;
  int m_max = 0;
  for (int kz = 0; kz < rows_; ++kz) {
    for (int i = 0; i < nt_; ++i) {
      const int m = i + nt_ * kz;
      const double p = p_ref_ * P_[m];
      r.force -= p * dA * Eigen::Vector2d(cos_c_[i], sin_c_[i]);
      const double h = c * f.h_centre[i];
      const double mu = spec_.barus > 0 && p > 0 ? mu0 * std::exp(spec_.barus * p) : mu0;
      const double fill = jfo ? 1 - r_[m] : 1.0;
      const int e = film_.neighbours(m)[FilmSolver::kEast], w = film_.neighbours(m)[FilmSolver::kWest];
      const double dpdx = p_ref_ * (P_[e] - P_[w]) / (2 * R * dtheta_);
      r.torque_journal += R * dA * (mu * (Us - Uj) / h * fill - 0.5 * h * dpdx);
      r.torque_shell += R * dA * (mu * (Uj - Us) / h * fill - 0.5 * h * dpdx);
      if (P_[m] > P_[m_max]) m_max = m;
      if (a && f.supply[m]) r.feed_flow += flow_scale * a->M[m];
    }
  }
  // The half grid of a symmetric bearing: the other half's equal share.
  r.force *= weight_, r.torque_journal *= weight_, r.torque_shell *= weight_, r.feed_flow *= weight_;
  // Peak pressure: parabola through the highest cell and its two circumferential neighbours.
  const double pc = P_[m_max], pe = P_[film_.neighbours(m_max)[FilmSolver::kEast]],
               pw = P_[film_.neighbours(m_max)[FilmSolver::kWest]];
  const double curv = pe - 2 * pc + pw;
  double shift = curv < 0 ? 0.5 * (pw - pe) / curv : 0.0;
  shift = std::clamp(shift, -0.5, 0.5);
  r.max_pressure = p_ref_ * (pc - 0.125 * (pe - pw) * (pe - pw) / (curv < 0 ? curv : -1e300));
  r.max_pressure_angle = wrap(((m_max % nt_) + 0.5 + shift) * dtheta_);
  r.side_flow = a ? weight_ * flow_scale * a->side_flow : 0.0;
  r.power_loss =
      -(r.torque_journal * k.omega_journal + r.torque_shell * k.omega_shell + r.force.dot(k.e_dot));
  return r;
}

// d(force)/d(q), q = (ex, ey, ex_dot, ey_dot, wm) with wm = (omega_journal + omega_shell) / 2: J du/dq = -dG/dq
// with G = (M, Phi); Phi does not depend on q, so the reduced system takes -dM/dq as its right-hand side. Then
// dF/dq = -sum p_ref dP/dq n dA, and the torque's derivative from its sum below (post_process). The scale
// omega_ref is held fixed: the dimensional solution does not depend on it (P p_ref, the supply pressure and
// the Barus coefficient scale together), so d/dwm at fixed omega_ref is the physical derivative.
void FiniteBearing::parameter_jacobian(const FilmAssembly& a, FilmResult& result) {
  constexpr int kParameters = 5;
  dP_dq_.resize(n_, kParameters);
  dr_dq_.resize(n_, kParameters);
  const double c = spec_.radial_clearance, R = spec_.radius();
  const bool jfo = spec_.cavitation == Cavitation::kJfo;
  const FilmProblem& f = film_.problem;
  auto fluidity = [&](double p) { return f.barus > 0 && p > 0 ? std::exp(-f.barus * p) : 1.0; };
  const double area = dtheta_ * dz_;
  for (int q = 0; q < kParameters; ++q) {
    Eigen::VectorXd dM = Eigen::VectorXd::Zero(n_);
    for (int k = 0; k < rows_; ++k) {
      const int row = nt_ * k;
      for (int i = 0; i < nt_; ++i) {
        if (q == 4) {  // mean speed: the wedge (Couette) flux through each east face, d(couette)/d(wm) = 1/omega_ref
          const int w = row + i, e = row + (i + 1) % nt_;
          const int up = f.couette >= 0 ? w : e;
          const double fill = jfo ? 1 - r_[up] : 1.0;
          const double dF = f.h_east[i] * fill * dz_ / omega_ref_;
          dM[w] += dF;
          dM[e] -= dF;
        } else if (q < 2) {  // position: the film thickness changes, dH/de = -n / c
          const double dHf = -(q == 0 ? cos_f_[i] : sin_f_[i]) / c;
          const double dHc = -(q == 0 ? cos_c_[i] : sin_c_[i]) / c;
          const int w = row + i, e = row + (i + 1) % nt_;
          const double H = f.h_east[i];
          const int up = f.couette >= 0 ? w : e;
          const double fill = jfo ? 1 - r_[up] : 1.0;
          const double g = 3 * H * H * dHf * 0.5 * (fluidity(P_[w]) + fluidity(P_[e]));
          const double dF = (-g * (P_[e] - P_[w]) / dtheta_ + f.couette * dHf * fill) * dz_;
          dM[w] += dF;
          dM[e] -= dF;
          const int s = row + i;
          const double Hc = f.h_centre[i];
          if (k + 1 < rows_) {
            const int n = s + nt_;
            const double gz = 3 * Hc * Hc * dHc * 0.5 * (fluidity(P_[s]) + fluidity(P_[n]));
            const double F = -gz * (P_[n] - P_[s]) / dz_ * dtheta_;
            dM[s] += F;
            dM[n] -= F;
          }
          if (k == 0 || (k == rows_ - 1 && !f.mirror_north)) {
            const int edges = rows_ == 1 && !f.mirror_north ? 2 : 1;
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
    for (int m = 0; m < n_; ++m) rhs[m] = f.supply[m] ? 0.0 : -dM[m];
    Eigen::VectorXd y = rhs;
    film_.solve_last(y);
    Eigen::Vector2d dF = Eigen::Vector2d::Zero();
    for (int m = 0; m < n_; ++m) {
      if (f.supply[m]) {
        dP_dq_(m, q) = dr_dq_(m, q) = 0;
        continue;
      }
      // Phi does not depend on q: ap dP + ar dr = 0 in every cell.
      const double dP = a.primary_is_p[m] ? y[m] : -a.ar[m] / a.ap[m] * y[m];
      dP_dq_(m, q) = dP;
      dr_dq_(m, q) = a.primary_is_p[m] ? -a.ap[m] / a.ar[m] * y[m] : y[m];
      const int i = m % nt_;
      dF -= weight_ * p_ref_ * dP * R * R * area * Eigen::Vector2d(cos_c_[i], sin_c_[i]);
    }
    if (q < 4) result.jacobian.col(q) = dF;
    result.full_jacobian.block<2, 1>(0, q < 4 ? q : 4) = dF;
  }
  torque_jacobian(result);
  has_sensitivity_ = true;
}

// d(torque_journal)/d(q) of the sum in post_process, T = sum R dA (mu (Us - Uj) / h fill - h/2 dp/dx), through
// p, r (the sensitivities above), h (position columns: dh/de = -n) and, for the speeds, U = R omega directly.
// Columns of full_jacobian: ex, ey, ex_dot, ey_dot, omega_journal, omega_shell; the film depends on the
// speeds through wm only, so d/domega_journal = d/domega_shell = 1/2 d/dwm plus the direct shear term.
void FiniteBearing::torque_jacobian(FilmResult& result) const {
  const double R = spec_.radius(), c = spec_.radial_clearance, mu0 = spec_.viscosity;
  const bool jfo = spec_.cavitation == Cavitation::kJfo;
  const FilmProblem& f = film_.problem;
  const double dA = weight_ * R * R * dtheta_ * dz_;  // the half grid of a symmetric bearing counts twice
  const double dU = R * (kinematics_of_solution_.omega_shell - kinematics_of_solution_.omega_journal);
  Eigen::Matrix<double, 1, 5> dT = Eigen::Matrix<double, 1, 5>::Zero();
  double shear_by_speed = 0;  // d/d(Us - Uj) of the Couette part, per unit of R
  for (int m = 0; m < n_; ++m) {
    const int i = m % nt_;
    const double p = p_ref_ * P_[m];
    const double h = c * f.h_centre[i];
    const bool piezo = spec_.barus > 0 && p > 0;
    const double mu = piezo ? mu0 * std::exp(spec_.barus * p) : mu0;
    const double fill = jfo ? 1 - r_[m] : 1.0;
    const int e = film_.neighbours(m)[FilmSolver::kEast], w = film_.neighbours(m)[FilmSolver::kWest];
    const double dpdx = p_ref_ * (P_[e] - P_[w]) / (2 * R * dtheta_);
    shear_by_speed += R * dA * mu / h * fill;
    for (int q = 0; q < 5; ++q) {
      const double dp = p_ref_ * dP_dq_(m, q);
      const double dfill = jfo ? -dr_dq_(m, q) : 0.0;
      const double ddpdx = p_ref_ * (dP_dq_(e, q) - dP_dq_(w, q)) / (2 * R * dtheta_);
      const double dh = q < 2 ? -(q == 0 ? cos_c_[i] : sin_c_[i]) : 0.0;
      const double dmu = piezo ? spec_.barus * mu * dp : 0.0;
      dT[q] += R * dA * (dU / h * (dmu * fill + mu * dfill - mu * fill * dh / h) - 0.5 * (dh * dpdx + h * ddpdx));
    }
  }
  result.full_jacobian.block<1, 4>(2, 0) = dT.head<4>();
  result.full_jacobian(2, 4) = 0.5 * dT[4] - R * shear_by_speed;
  result.full_jacobian(2, 5) = 0.5 * dT[4] + R * shear_by_speed;
  result.full_jacobian.block<2, 1>(0, 5) = 0.5 * result.full_jacobian.block<2, 1>(0, 4);
  result.full_jacobian.block<2, 1>(0, 4) = result.full_jacobian.block<2, 1>(0, 5);
  result.has_full_jacobian = true;
}

// Tangent predictor: the last solution moved along its sensitivities to the new (e, de/dt), projected onto
// p >= 0, r >= 0. Exact to first order while the cavitation boundary stays in its cells.
void FiniteBearing::predict(const Kinematics& k) {
  const auto wm = [](const Kinematics& m) { return 0.5 * (m.omega_journal + m.omega_shell); };
  Eigen::Matrix<double, 5, 1> dq;
  dq << k.e - kinematics_of_solution_.e, k.e_dot - kinematics_of_solution_.e_dot, wm(k) - wm(kinematics_of_solution_);
  P_ = (P_ + dP_dq_ * dq).cwiseMax(0.0);
  r_ = (r_ + dr_dq_ * dq).cwiseMax(0.0);
}

int FiniteBearing::cell(int i, int k) const {
  return i + nt_ * (k < rows_ ? k : nz_ - 1 - k);  // the half grid's mirror image for k >= rows_
}

Eigen::MatrixXd FiniteBearing::pressure() const {
  Eigen::MatrixXd p(nt_, nz_);
  for (int k = 0; k < nz_; ++k)
    for (int i = 0; i < nt_; ++i) p(i, k) = has_solution_ ? p_ref_of_solution_ * P_[cell(i, k)] : 0.0;
  return p;
}

Eigen::MatrixXd FiniteBearing::fill_ratio() const {
  Eigen::MatrixXd f = Eigen::MatrixXd::Ones(nt_, nz_);
  if (spec_.cavitation == Cavitation::kJfo && has_solution_)
    for (int k = 0; k < nz_; ++k)
      for (int i = 0; i < nt_; ++i) f(i, k) = 1 - r_[cell(i, k)];
  return f;
}

Eigen::MatrixXi FiniteBearing::supply_cells() const {
  Eigen::MatrixXi s(nt_, nz_);
  for (int k = 0; k < nz_; ++k)
    for (int i = 0; i < nt_; ++i) s(i, k) = film_.problem.supply[cell(i, k)];
  return s;
}

}  // namespace nvh::bearing
