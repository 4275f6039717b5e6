// The model's state layout, residual, analytic Jacobian and consistent initial conditions (see model.hpp).
#include "solve/model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <set>
#include <sstream>

#include <Eigen/Geometry>

#include "common/error.hpp"
#include "common/interrupt.hpp"

namespace nvh::solve {

namespace {
/// The chain rule through a marker: d(marker motion)/d(q, w) of its body (Model::jacobian).
struct MarkerDerivatives {
  int body = -1, nq = 0, nw = 0, q0 = 0, w0 = 0;  // columns of q and w in y
  Eigen::MatrixXd s;                              // 12 x nq
  Eigen::MatrixXd g;                              // 6 x nw: [Jv; Jw]
};
}  // namespace

// Preallocated per model (finalize): the residual and the Jacobian allocate nothing (tested in
// test_jacobian_flexible.cpp, ModelResidualAndJacobian.DoNotAllocate).
struct Model::Workspace {
  Eigen::VectorXd q_force, ct_lambda, ct_mu, w_eff;
  std::vector<std::vector<MarkerMotion>> motions;  // per force element
  std::vector<std::vector<Wrench>> wrenches;       // per force element
  std::vector<ConstraintEquations> equations;      // per constraint
  std::vector<ConstraintEquations> perturbed;      // per constraint (local differences)
  std::vector<double> lambda_scratch;
  // Jacobian
  Eigen::MatrixXd dense;                                         // n x n
  Eigen::VectorXd f0, f_plus, y_scratch, yp_scratch;  // n
  SparsityPattern pattern;
  std::vector<Eigen::MatrixXd> element_jacobian;                // per force element
  std::vector<Eigen::MatrixXd> element_rows_p, element_rows_m;  // per force element: wrench + state rows
  std::vector<Eigen::MatrixXd> kin_dw;                          // per body: d(kinematic rows)/d(w_eff)
  // largest sizes over the bodies; used through their top-left blocks
  Eigen::MatrixXd scratch_q;                                         // max(nq, nw) x max(nq, nw)
  Eigen::MatrixXd scratch_w;                                         // nw x nw: d(inertial rows)/dw
  Eigen::MatrixXd mass;                                              // nw x nw
  Eigen::MatrixXd gw;                                                // nw x 12
  Eigen::MatrixXd pose;                                              // 6 x nq
  Eigen::VectorXd g_row;                                             // nw
  Eigen::MatrixXd radial;                                            // n x 4
  std::vector<std::vector<MarkerDerivatives>> force_markers;         // per force element, per marker
  std::vector<std::array<MarkerDerivatives, 2>> constraint_markers;  // per constraint: i, j
  std::array<MarkerDerivatives, 2> clock_markers;
  std::vector<MarkerMotion> motion_scratch;
  std::vector<Wrench> wrench_scratch_p, wrench_scratch_m;
  std::vector<double> state_scratch_p, state_scratch_m, z_scratch, zp_scratch;
};

Model::Model() : ws_(std::make_unique<Workspace>()) {}
Model::~Model() = default;
Model::Model(Model&&) noexcept = default;
Model& Model::operator=(Model&&) noexcept = default;

void Model::finalize() {
  body_offset_.clear();
  w_global_offset_.clear();
  int k = 0;
  n_w_ = 0;
  int max_nw = 0;
  for (const auto& b : bodies) {
    if (b->algebraic_count() != 0)
      throw Error("body '" + b->name() +
                  "': bodies with algebraic coordinates are not supported by the model");
    body_offset_.push_back(k);
    k += b->state_count();
    w_global_offset_.push_back(n_w_);
    n_w_ += b->velocity_count();
    max_nw = std::max(max_nw, b->velocity_count());
  }
  clock_index_ = clock ? k++ : -1;
  n_gaps_ = 0;
  for (auto& f : forces) {
    if (static_cast<int>(f.markers.size()) != f.element->marker_count())
      throw Error("force element '" + f.name + "' of type " + f.element->type() + " needs " +
                  std::to_string(f.element->marker_count()) + " markers, got " +
                  std::to_string(f.markers.size()));
    f.state_offset = k;
    f.state_count = static_cast<int>(f.element->states().size());
    k += f.state_count;
    f.gap_offset = n_gaps_;
    n_gaps_ += f.element->gap_count();
  }
  energy_offset_ = k;
  k += 2;
  n_eq_ = 0;
  for (auto& c : constraints) {
    if (c.constraint->size() > 6)
      throw Error("joint '" + c.name + "': more than 6 equations (the Jacobian's buffers hold 6 per joint)");
    c.first_row = n_eq_;
    n_eq_ += c.constraint->size();
    c.active.assign(c.constraint->size(), 1);
  }
  lambda_offset_ = k;
  mu_offset_ = k + n_eq_;
  size_ = k + 2 * n_eq_;

  auto& w = *ws_;
  w.q_force.resize(n_w_);
  w.ct_lambda.resize(n_w_);
  w.ct_mu.resize(n_w_);
  w.w_eff.resize(max_nw);
  w.motions.clear();
  w.wrenches.clear();
  w.element_jacobian.clear();
  w.element_rows_p.clear();
  w.element_rows_m.clear();
  for (const auto& f : forces) {
    const int nm = static_cast<int>(f.markers.size());
    w.motions.emplace_back(nm);
    w.wrenches.emplace_back(nm);
    w.element_jacobian.emplace_back(6 * nm + f.state_count, 12 * nm + f.state_count + 1);
    w.element_rows_p.emplace_back(6 * nm + f.state_count, 1);
    w.element_rows_m.emplace_back(6 * nm + f.state_count, 1);
  }
  w.equations.clear();
  w.perturbed.clear();
  for (const auto& c : constraints) {
    w.equations.emplace_back(c.constraint->size());
    w.perturbed.emplace_back(c.constraint->size());
  }
  w.dense.resize(0, 0);
  w.f0.resize(size_);
  w.f_plus.resize(size_);
  w.y_scratch.resize(size_);
  w.yp_scratch.resize(size_);
  w.pattern = jacobian_pattern();
  // Floating bodies whose Euler parameter columns share no row, greedily grouped.
  radial_groups_.clear();
  std::vector<std::vector<char>> taken;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    if (bodies[b]->kind() != "rigid" && bodies[b]->kind() != "flexible") continue;
    const int col = body_offset_[b] + 3;
    std::size_t g = 0;
    for (; g < radial_groups_.size(); ++g) {
      bool clash = false;
      for (int k = w.pattern.column_start[col]; k < w.pattern.column_start[col + 1] && !clash; ++k)
        clash = taken[g][w.pattern.rows[k]];
      if (!clash) break;
    }
    if (g == radial_groups_.size()) radial_groups_.emplace_back(), taken.emplace_back(size_, 0);
    radial_groups_[g].push_back(static_cast<int>(b));
    for (int k = w.pattern.column_start[col]; k < w.pattern.column_start[col + 1]; ++k)
      taken[g][w.pattern.rows[k]] = 1;
  }
  w.kin_dw.clear();
  int max_nq = 0;
  for (const auto& b : bodies) {
    w.kin_dw.emplace_back(b->position_count(), b->velocity_count());
    max_nq = std::max(max_nq, b->position_count());
  }
  const int max_n = std::max(max_nq, max_nw);
  w.scratch_q.resize(max_n, max_n);
  w.scratch_w.resize(max_nw, max_nw);
  w.mass.resize(max_nw, max_nw);
  w.gw.resize(max_nw, 12);
  w.pose.resize(6, max_nq);
  w.g_row.resize(max_nw);
  w.radial.resize(size_, 4);
  auto sized = [&](const MarkerRef& m) {
    MarkerDerivatives d;
    d.s.resize(12, bodies[m.body]->position_count());
    d.g.resize(6, bodies[m.body]->velocity_count());
    return d;
  };
  w.force_markers.clear();
  for (const auto& f : forces) {
    w.force_markers.emplace_back();
    for (const auto& m : f.markers) w.force_markers.back().push_back(sized(m));
  }
  w.constraint_markers.clear();
  for (const auto& c : constraints) w.constraint_markers.push_back({sized(c.i), sized(c.j)});
  if (clock) w.clock_markers = {sized(clock->i), sized(clock->j)};
}

std::span<const double> Model::positions(int b, const double* y) const {
  return {y + body_offset_[b], static_cast<std::size_t>(bodies[b]->position_count())};
}
std::span<const double> Model::velocities(int b, const double* y) const {
  return {y + velocity_offset(b), static_cast<std::size_t>(bodies[b]->velocity_count())};
}

MarkerMotion Model::marker_motion(const MarkerRef& m, const double* y) const {
  return bodies[m.body]->marker_motion(m.marker, positions(m.body, y), velocities(m.body, y));
}

ElementInput Model::element_input(const ForceEntry& f, double t, const double* y, const double* yp,
                                  std::vector<MarkerMotion>& markers) const {
  markers.resize(f.markers.size());
  for (std::size_t k = 0; k < f.markers.size(); ++k) markers[k] = marker_motion(f.markers[k], y);
  ElementInput in;
  in.time = t;
  in.crank_angle = crank_angle(y);
  in.markers = markers;
  in.z = {y + f.state_offset, static_cast<std::size_t>(f.state_count)};
  in.zp = {yp + f.state_offset, static_cast<std::size_t>(f.state_count)};
  return in;
}

Eigen::VectorXd Model::differential_mask() const {
  Eigen::VectorXd id = Eigen::VectorXd::Zero(size_);
  for (std::size_t b = 0; b < bodies.size(); ++b)
    id.segment(body_offset_[b], bodies[b]->position_count() + bodies[b]->velocity_count()).setOnes();
  if (clock_index_ >= 0) id[clock_index_] = 1;
  for (const auto& f : forces) {
    const auto states = f.element->states();
    for (int s = 0; s < f.state_count; ++s) id[f.state_offset + s] = states[s].differential ? 1 : 0;
  }
  id[energy_offset_] = id[energy_offset_ + 1] = 1;
  return id;
}

Eigen::VectorXd Model::error_test_mask() const {
  Eigen::VectorXd m = differential_mask();
  m[energy_offset_] = m[energy_offset_ + 1] = 0;
  return m;
}

Eigen::VectorXd Model::velocity_mask() const {
  Eigen::VectorXd m = Eigen::VectorXd::Zero(size());
  for (std::size_t b = 0; b < bodies.size(); ++b)
    m.segment(velocity_offset(static_cast<int>(b)), bodies[b]->velocity_count()).setOnes();
  return m;
}

Eigen::VectorXd Model::velocity_tolerance_mask() const {
  Eigen::VectorXd m = velocity_mask();
  for (const auto& f : forces) {
    const auto states = f.element->states();
    for (int s = 0; s < f.state_count; ++s)
      if (states[s].velocity) m[f.state_offset + s] = 1;
  }
  return m;
}

int Model::body_of_state(int k) const {
  for (std::size_t b = 0; b < bodies.size(); ++b)
    if (k >= body_offset_[b] && k < body_offset_[b] + bodies[b]->state_count()) return static_cast<int>(b);
  return -1;
}

std::string Model::describe_state(int k) const {
  if (const int b = body_of_state(k); b >= 0) {
    const int r = k - body_offset_[b], nq = bodies[b]->position_count();
    return "body '" + bodies[b]->name() + "' " +
           (r < nq ? "q[" + std::to_string(r) + "]" : "w[" + std::to_string(r - nq) + "]");
  }
  if (k == clock_index_) return "clock angle";
  for (const auto& f : forces)
    if (k >= f.state_offset && k < f.state_offset + f.state_count)
      return f.element->type() + " '" + f.name + "' state " + f.element->states()[k - f.state_offset].name;
  if (k == energy_offset_) return "energy dissipated";
  if (k == energy_offset_ + 1) return "energy input";
  for (const auto& c : constraints) {
    for (int e = 0; e < c.constraint->size(); ++e) {
      const auto name = c.constraint->equation_names()[e];
      if (k == lambda_offset_ + c.first_row + e)
        return c.constraint->type() + " '" + c.name + "' velocity equation " + name;
      if (k == mu_offset_ + c.first_row + e)
        return c.constraint->type() + " '" + c.name + "' position equation " + name;
    }
  }
  return "state " + std::to_string(k);
}

std::string Model::explain_state(int k) const {
  std::string words = describe_state(k);
  if (const int b = body_of_state(k); b >= 0)
    if (const std::string meaning = bodies[b]->state_meaning(k - body_offset_[b]); !meaning.empty())
      words += " (" + meaning + ")";
  return words;
}

// ---------------------------------------------------------------- residual
void Model::evaluate_element(std::size_t fi, double t, const double* y, const double* yp,
                             double* state_rows) const {
  auto& w = *ws_;
  const ForceEntry& f = forces[fi];
  const ElementInput in = element_input(f, t, y, yp, w.motions[fi]);
  for (auto& wr : w.wrenches[fi]) wr = Wrench{};
  ElementOutput out{w.wrenches[fi], {state_rows, static_cast<std::size_t>(f.state_count)}};
  f.element->evaluate(in, out);
}

void Model::residual(double t, const double* y, const double* yp, double* f) const {
  auto& w = *ws_;
  w.q_force.setZero();
  w.ct_lambda.setZero();
  w.ct_mu.setZero();

  // Constraints: their rows, and their reactions as wrenches D^T lambda at the markers (C^T = J^T D^T).
  for (std::size_t ci = 0; ci < constraints.size(); ++ci) {
    const auto& c = constraints[ci];
    const MarkerMotion mi = marker_motion(c.i, y), mj = marker_motion(c.j, y);
    ConstraintEquations& eq = w.equations[ci];
    eq.phi.setZero(), eq.di.setZero(), eq.dj.setZero(), eq.phi_t.setZero();
    c.constraint->evaluate(t, mi, mj, eq);
    Eigen::Matrix<double, 6, 1> twist_i, twist_j, li = Eigen::Matrix<double, 6, 1>::Zero(),
                                                  lj = Eigen::Matrix<double, 6, 1>::Zero(), ui = li, uj = li;
    // C w = D [Jv w; Jw w] (the form whose time derivative matches the position rows for any |p|)
    Vec3 v, omega;
    bodies[c.i.body]->marker_twist(c.i.marker, positions(c.i.body, y), velocities(c.i.body, y), v, omega);
    twist_i << v, omega;
    bodies[c.j.body]->marker_twist(c.j.marker, positions(c.j.body, y), velocities(c.j.body, y), v, omega);
    twist_j << v, omega;
    for (int e = 0; e < c.constraint->size(); ++e) {
      const int row = c.first_row + e;
      const double lambda = y[lambda_offset_ + row], mu = y[mu_offset_ + row];
      if (!c.active[e]) {
        f[lambda_offset_ + row] = lambda;
        f[mu_offset_ + row] = mu;
        continue;
      }
      f[lambda_offset_ + row] = eq.di.row(e).dot(twist_i) + eq.dj.row(e).dot(twist_j) + eq.phi_t[e];
      f[mu_offset_ + row] = eq.phi[e];
      li += eq.di.row(e).transpose() * lambda, lj += eq.dj.row(e).transpose() * lambda;
      ui += eq.di.row(e).transpose() * mu, uj += eq.dj.row(e).transpose() * mu;
    }
    auto add = [&](const MarkerRef& m, const Eigen::Matrix<double, 6, 1>& wr, Eigen::VectorXd& target) {
      const Body& b = *bodies[m.body];
      if (b.velocity_count() == 0) return;
      b.add_wrench(m.marker, positions(m.body, y), wr.head<3>(), wr.tail<3>(),
                   {target.data() + w_global_offset_[m.body], std::size_t(b.velocity_count())});
    };
    add(c.i, li, w.ct_lambda), add(c.j, lj, w.ct_lambda);
    add(c.i, ui, w.ct_mu), add(c.j, uj, w.ct_mu);
  }

  // Force elements: wrenches at their markers, and their state rows.
  for (std::size_t fi = 0; fi < forces.size(); ++fi) {
    const ForceEntry& fe = forces[fi];
    evaluate_element(fi, t, y, yp, f + fe.state_offset);
    for (std::size_t k = 0; k < fe.markers.size(); ++k) {
      const MarkerRef& m = fe.markers[k];
      const Body& b = *bodies[m.body];
      if (b.velocity_count() == 0) continue;
      const Wrench& wr = w.wrenches[fi][k];
      b.add_wrench(m.marker, positions(m.body, y), wr.force, wr.torque,
                   {w.q_force.data() + w_global_offset_[m.body], std::size_t(b.velocity_count())});
    }
  }

  // Body rows.
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const auto& body = *bodies[b];
    const int o = body_offset_[b], nq = body.position_count(), nw = body.velocity_count();
    if (nq + nw == 0) continue;
    const int wo = w_global_offset_[b];
    auto w_eff = w.w_eff.head(nw);
    w_eff = Eigen::Map<const Eigen::VectorXd>(y + o + nq, nw) - w.ct_mu.segment(wo, nw);
    body.kinematic_residual({y + o, std::size_t(nq)}, {yp + o, std::size_t(nq)},
                            {w_eff.data(), std::size_t(nw)}, {}, {f + o, std::size_t(nq)}, {});
    body.inertia_residual({y + o, std::size_t(nq)}, {y + o + nq, std::size_t(nw)},
                          {yp + o + nq, std::size_t(nw)}, gravity, {f + o + nq, std::size_t(nw)});
    Eigen::Map<Eigen::VectorXd>(f + o + nq, nw) += w.ct_lambda.segment(wo, nw) - w.q_force.segment(wo, nw);
  }

  if (clock_index_ >= 0) {
    const MarkerMotion mi = marker_motion(clock->i, y), mj = marker_motion(clock->j, y);
    f[clock_index_] = yp[clock_index_] - mj.axes.col(2).dot(mi.angular_velocity - mj.angular_velocity);
  }

  double dissipated = 0, input = 0;
  element_powers(t, y, yp, dissipated, input);
  f[energy_offset_] = yp[energy_offset_] - dissipated;
  f[energy_offset_ + 1] = yp[energy_offset_ + 1] - input;
}

std::string Model::non_finite_culprit(double t, const double* y, const double* yp) const {
  auto finite = [](const auto& m) { return m.allFinite(); };
  auto value = [](double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  };
  if (!std::isfinite(t)) return "the time is " + value(t);
  // The differential states first: a non-finite one makes every contribution that reads it non-finite. The
  // rates and the multipliers after the contributions: non-finite accelerations and reactions come from a
  // force (a contact with clearance = -inf at the consistent start), which is the one to name.
  const Eigen::VectorXd differential = differential_mask();
  for (int k = 0; k < size_; ++k)
    if (differential[k] > 0 && !std::isfinite(y[k]))
      return "the state " + describe_state(k) + " is " + value(y[k]);
  auto& w = *ws_;
  for (std::size_t ci = 0; ci < constraints.size(); ++ci) {
    const auto& c = constraints[ci];
    ConstraintEquations& eq = w.perturbed[ci];
    eq.phi.setZero(), eq.di.setZero(), eq.dj.setZero(), eq.phi_t.setZero();
    c.constraint->evaluate(t, marker_motion(c.i, y), marker_motion(c.j, y), eq);
    if (!finite(eq.phi) || !finite(eq.di) || !finite(eq.dj) || !finite(eq.phi_t))
      return c.constraint->type() + " '" + c.name + "' gives non-finite equations";
  }
  std::vector<double> rows;
  for (std::size_t fi = 0; fi < forces.size(); ++fi) {
    const ForceEntry& fe = forces[fi];
    rows.assign(static_cast<std::size_t>(fe.state_count), 0.0);
    evaluate_element(fi, t, y, yp, rows.data());
    const std::string who = "force element '" + fe.name + "' (" + fe.element->type() + ")";
    for (std::size_t k = 0; k < fe.markers.size(); ++k) {
      const Wrench& wr = w.wrenches[fi][k];
      if (!finite(wr.force) || !finite(wr.torque))
        return who + " gives a non-finite " + (finite(wr.force) ? "torque" : "force") + " at its marker " +
               std::to_string(k);
    }
    for (int s = 0; s < fe.state_count; ++s)
      if (!std::isfinite(rows[s]))
        return who + " gives a non-finite row for its state " + fe.element->states()[s].name;
  }
  for (int k = 0; k < size_; ++k) {
    if (!std::isfinite(y[k])) return "the state " + describe_state(k) + " is " + value(y[k]);
    if (!std::isfinite(yp[k])) return "the rate of the state " + describe_state(k) + " is " + value(yp[k]);
  }
  // The rest (bodies' inertia and kinematics, the clock, the energy rows): the first non-finite row.
  Eigen::VectorXd f(size_);
  residual(t, y, yp, f.data());
  for (int k = 0; k < size_; ++k)
    if (!std::isfinite(f[k])) return "the equation of " + describe_state(k) + " is " + value(f[k]);
  return {};
}

// Uses the wrenches left in the workspace by the residual's element loop.
void Model::element_powers(double t, const double* y, const double* yp, double& dissipated,
                           double& input) const {
  auto& w = *ws_;
  dissipated = 0;
  input = driver_power(t, y);
  for (std::size_t b = 0; b < bodies.size(); ++b)
    dissipated +=
        bodies[b]->dissipated_power(positions(static_cast<int>(b), y), velocities(static_cast<int>(b), y));
  for (std::size_t fi = 0; fi < forces.size(); ++fi) {
    const ForceEntry& fe = forces[fi];
    if (fe.element->is_source()) {
      for (std::size_t k = 0; k < fe.markers.size(); ++k) {
        const MarkerMotion& m = w.motions[fi][k];
        input += w.wrenches[fi][k].force.dot(m.velocity) + w.wrenches[fi][k].torque.dot(m.angular_velocity);
      }
    } else {
      ElementInput in;
      in.time = t;
      in.crank_angle = crank_angle(y);
      in.markers = w.motions[fi];
      in.z = {y + fe.state_offset, static_cast<std::size_t>(fe.state_count)};
      in.zp = {yp + fe.state_offset, static_cast<std::size_t>(fe.state_count)};
      dissipated += fe.element->energy(in).dissipated;
    }
  }
}

// Power of the driven joints: the reactions -C^T lambda do the work -lambda^T C w = lambda^T Phi_t.
double Model::driver_power(double t, const double* y) const {
  double p = 0;
  for (std::size_t ci = 0; ci < constraints.size(); ++ci) {
    const auto& c = constraints[ci];
    if (!c.constraint->is_driver()) continue;
    const MarkerMotion mi = marker_motion(c.i, y), mj = marker_motion(c.j, y);
    ConstraintEquations& eq = ws_->perturbed[ci];
    eq.phi_t.setZero();
    c.constraint->evaluate(t, mi, mj, eq);
    for (int e = 0; e < c.constraint->size(); ++e)
      if (c.active[e]) p += y[lambda_offset_ + c.first_row + e] * eq.phi_t[e];
  }
  return p;
}

void Model::gaps(double t, const double* y, const double* yp, double* out) const {
  for (std::size_t fi = 0; fi < forces.size(); ++fi) {
    const ForceEntry& fe = forces[fi];
    const int n = fe.element->gap_count();
    if (n == 0) continue;
    const ElementInput in = element_input(fe, t, y, yp, ws_->motions[fi]);
    fe.element->gaps(in, {out + fe.gap_offset, static_cast<std::size_t>(n)});
  }
}

// ---------------------------------------------------------------- Jacobian
namespace {

/// Apply one of the 12 marker-motion perturbations (force_element.hpp) of size h to a marker.
void perturb(MarkerMotion& m, int column, double h) {
  const int axis = column % 3;
  switch (column / 3) {
    case 0:
      m.position[axis] += h;
      break;
    case 1:
      m.axes = Eigen::AngleAxisd(h, Vec3::Unit(axis)).toRotationMatrix() * m.axes;
      break;
    case 2:
      m.velocity[axis] += h;
      break;
    default:
      m.angular_velocity[axis] += h;
      break;
  }
}
double motion_step(const MarkerMotion& m, int column) {
  const int axis = column % 3;
  switch (column / 3) {
    case 0:
      return 1e-7 * std::max(1.0, std::abs(m.position[axis]));
    case 1:
      return 1e-7;
    case 2:
      return 1e-7 * std::max(1.0, std::abs(m.velocity[axis]));
    default:
      return 1e-7 * std::max(1.0, std::abs(m.angular_velocity[axis]));
  }
}

}  // namespace

void Model::jacobian(double t, const double* y, const double* yp, double cj,
                     std::vector<double>& values) const {
  auto& w = *ws_;
  if (w.dense.rows() != size_) w.dense.resize(size_, size_);
  Eigen::MatrixXd& jm = w.dense;
  jm.setZero();
  residual(t, y, yp, w.f0.data());  // fills the workspace: wrenches, constraint equations, C^T mu

  // Bodies' own blocks.
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const Body& body = *bodies[b];
    const int o = body_offset_[b], nq = body.position_count(), nw = body.velocity_count();
    if (nq + nw == 0) continue;
    const auto q = positions(static_cast<int>(b), y);
    const auto wv = velocities(static_cast<int>(b), y);
    const int wo = w_global_offset_[b];
    auto w_eff = w.w_eff.head(nw);
    w_eff = Eigen::Map<const Eigen::VectorXd>(wv.data(), nw) - w.ct_mu.segment(wo, nw);
    auto kq = w.scratch_q.topLeftCorner(nq, nq);
    body.kinematic_jacobian(q, {w_eff.data(), std::size_t(nw)}, kq, w.kin_dw[b]);
    jm.block(o, o, nq, nq) = kq;
    jm.block(o, o, nq, nq).diagonal().array() += cj;
    jm.block(o, o + nq, nq, nw) = w.kin_dw[b];
    auto iq = w.scratch_q.topLeftCorner(nw, nq);
    auto iw = w.scratch_w.topLeftCorner(nw, nw);
    body.inertia_jacobian(q, wv, {yp + o + nq, std::size_t(nw)}, gravity, iq, iw);
    jm.block(o + nq, o, nw, nq) = iq;
    auto mass = w.mass.topLeftCorner(nw, nw);
    body.mass_matrix(q, mass);
    jm.block(o + nq, o + nq, nw, nw) = iw + cj * mass;
  }

  // The chain rule through a marker (d's matrices are sized by finalize).
  auto derivatives = [&](const MarkerRef& m, MarkerDerivatives& d) {
    const Body& body = *bodies[m.body];
    d.body = m.body;
    d.nq = body.position_count();
    d.nw = body.velocity_count();
    d.q0 = body_offset_[m.body];
    d.w0 = d.q0 + d.nq;
    if (d.nq + d.nw == 0) return;
    body.marker_sensitivity(m.marker, positions(m.body, y), velocities(m.body, y), d.s);
    auto jv = d.g.topRows<3>();
    auto jw = d.g.bottomRows<3>();
    body.marker_jacobian(m.marker, positions(m.body, y), jv, jw);
  };
  // rows += a * (d(motion)/d(y) of marker d), a: r x 12 (columns dp, dtheta, dv, domega).
  auto add_motion = [&](int row0, const Eigen::Ref<const Eigen::MatrixXd>& a, const MarkerDerivatives& d) {
    if (d.nq + d.nw == 0) return;
    jm.block(row0, d.q0, a.rows(), d.nq).noalias() += a * d.s;
    jm.block(row0, d.w0, a.rows(), d.nw).noalias() += a.rightCols<6>() * d.g;
  };
  // dynamics rows of marker k's body += sign * G_k^T * a (a: 6 x cols at columns col0).
  auto add_to_dynamics = [&](const MarkerDerivatives& k, double sign,
                             const Eigen::Ref<const Eigen::MatrixXd>& a, int col0) {
    if (k.nw == 0) return;
    jm.block(k.w0, col0, k.nw, a.cols()).noalias() += sign * k.g.transpose() * a;
  };

  // Force elements.
  for (std::size_t fi = 0; fi < forces.size(); ++fi) {
    const ForceEntry& fe = forces[fi];
    const int nm = static_cast<int>(fe.markers.size()), ns = fe.state_count;
    Eigen::MatrixXd& e = w.element_jacobian[fi];
    e.setZero();
    const ElementInput in = element_input(fe, t, y, yp, w.motions[fi]);
    ElementJacobian ej{cj, e};
    if (!fe.element->jacobian(in, ej)) {
      // Local central differences of this element alone.
      e.setZero();
      std::vector<MarkerMotion>& mot = w.motion_scratch;
      mot.assign(in.markers.begin(), in.markers.end());
      w.wrench_scratch_p.resize(nm), w.wrench_scratch_m.resize(nm);
      w.state_scratch_p.resize(ns), w.state_scratch_m.resize(ns);
      w.z_scratch.assign(in.z.begin(), in.z.end()), w.zp_scratch.assign(in.zp.begin(), in.zp.end());
      ElementInput pin = in;
      pin.markers = mot;
      pin.z = w.z_scratch;
      pin.zp = w.zp_scratch;
      auto eval = [&](std::vector<Wrench>& wr, std::vector<double>& st, Eigen::MatrixXd& rows) {
        for (auto& x : wr) x = Wrench{};
        ElementOutput out{wr, st};
        fe.element->evaluate(pin, out);
        for (int k = 0; k < nm; ++k)
          rows.block<3, 1>(6 * k, 0) = wr[k].force, rows.block<3, 1>(6 * k + 3, 0) = wr[k].torque;
        for (int s = 0; s < ns; ++s) rows(6 * nm + s, 0) = st[s];
      };
      auto difference = [&](int col, double h) {
        e.col(col) = (w.element_rows_p[fi] - w.element_rows_m[fi]) / (2 * h);
      };
      for (int k = 0; k < nm; ++k)
        for (int c = 0; c < 12; ++c) {
          const double h = motion_step(in.markers[k], c);
          perturb(mot[k], c, h);
          eval(w.wrench_scratch_p, w.state_scratch_p, w.element_rows_p[fi]);
          mot[k] = in.markers[k];
          perturb(mot[k], c, -h);
          eval(w.wrench_scratch_m, w.state_scratch_m, w.element_rows_m[fi]);
          mot[k] = in.markers[k];
          difference(12 * k + c, h);
        }
      for (int s = 0; s < ns; ++s) {
        const double h = 1e-7 * std::max(1.0, std::abs(in.z[s]));
        w.z_scratch[s] = in.z[s] + h, w.zp_scratch[s] = in.zp[s] + cj * h;
        eval(w.wrench_scratch_p, w.state_scratch_p, w.element_rows_p[fi]);
        w.z_scratch[s] = in.z[s] - h, w.zp_scratch[s] = in.zp[s] - cj * h;
        eval(w.wrench_scratch_m, w.state_scratch_m, w.element_rows_m[fi]);
        w.z_scratch[s] = in.z[s], w.zp_scratch[s] = in.zp[s];
        difference(12 * nm + s, h);
      }
      if (fe.element->uses_crank_angle() && clock_index_ >= 0) {
        const double h = 1e-7 * std::max(1.0, std::abs(in.crank_angle));
        pin.crank_angle = in.crank_angle + h;
        eval(w.wrench_scratch_p, w.state_scratch_p, w.element_rows_p[fi]);
        pin.crank_angle = in.crank_angle - h;
        eval(w.wrench_scratch_m, w.state_scratch_m, w.element_rows_m[fi]);
        difference(12 * nm + ns, h);
      }
    }
    std::vector<MarkerDerivatives>& md = w.force_markers[fi];
    for (int k = 0; k < nm; ++k) derivatives(fe.markers[k], md[k]);
    const int z0 = fe.state_offset, crank_col = 12 * nm + ns;
    // -(sum over the markers k of one body of G_k^T dW_k/d(motion_l)) d(motion_l)/dy: the markers' wrench
    // derivatives are summed per body before the chain rule through marker l, so an element with many
    // markers on one flexible body (the EHL liner's ~170) costs one product per (body, l), not per (k, l).
    for (int k = 0; k < nm; ++k) {
      if (md[k].nw == 0) continue;
      bool first_of_body = true;
      for (int k2 = 0; k2 < k && first_of_body; ++k2) first_of_body = md[k2].body != md[k].body;
      if (!first_of_body) continue;
      for (int l = 0; l < nm; ++l) {
        if (md[l].nq + md[l].nw == 0) continue;
        auto gw = w.gw.topRows(md[k].nw);
        gw.noalias() = -md[k].g.transpose() * e.block(6 * k, 12 * l, 6, 12);
        for (int k2 = k + 1; k2 < nm; ++k2)
          if (md[k2].body == md[k].body)
            gw.noalias() -= md[k2].g.transpose() * e.block(6 * k2, 12 * l, 6, 12);
        add_motion(md[k].w0, gw, md[l]);
      }
    }
    for (int k = 0; k < nm; ++k) {
      if (md[k].nw == 0) continue;
      if (ns > 0) add_to_dynamics(md[k], -1.0, e.block(6 * k, 12 * nm, 6, ns), z0);
      if (clock_index_ >= 0 && fe.element->uses_crank_angle())
        add_to_dynamics(md[k], -1.0, e.block(6 * k, crank_col, 6, 1), clock_index_);
      // the wrench's own change of direction in body coordinates, at fixed (F, T)
      auto dq = w.scratch_q.topLeftCorner(md[k].nw, md[k].nq);
      dq.setZero();
      const Wrench& wr = w.wrenches[fi][k];
      bodies[md[k].body]->add_wrench_derivative(fe.markers[k].marker, positions(md[k].body, y), wr.force,
                                                wr.torque, dq);
      jm.block(md[k].w0, md[k].q0, md[k].nw, md[k].nq) -= dq;
    }
    for (int s = 0; s < ns; ++s) {
      for (int l = 0; l < nm; ++l) add_motion(z0 + s, e.block(6 * nm + s, 12 * l, 1, 12), md[l]);
      jm.block(z0 + s, z0, 1, ns) += e.block(6 * nm + s, 12 * nm, 1, ns);
      if (clock_index_ >= 0 && fe.element->uses_crank_angle())
        jm(z0 + s, clock_index_) += e(6 * nm + s, crank_col);
    }
  }

  // Constraints.
  // (a joint has at most 6 equations: the fixed-size-at-most matrices below live on the stack)
  using Equations = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;
  for (std::size_t ci = 0; ci < constraints.size(); ++ci) {
    const auto& c = constraints[ci];
    const int m = c.constraint->size();
    auto& [di, dj] = w.constraint_markers[ci];
    const MarkerMotion mi = marker_motion(c.i, y), mj = marker_motion(c.j, y);
    const ConstraintEquations& eq = w.equations[ci];  // evaluated by the residual above
    derivatives(c.i, di);
    derivatives(c.j, dj);
    Equations lambda(m), mu(m);
    for (int e = 0; e < m; ++e) {
      const int row = c.first_row + e;
      lambda[e] = c.active[e] ? y[lambda_offset_ + row] : 0.0;
      mu[e] = c.active[e] ? y[mu_offset_ + row] : 0.0;
      if (!c.active[e]) {
        jm(lambda_offset_ + row, lambda_offset_ + row) = 1;
        jm(mu_offset_ + row, mu_offset_ + row) = 1;
      }
    }
    // The change of D with the markers' poses, by local central differences: d(D twist)/d(pose) (m x 12 per
    // marker) and d(D^T lambda)/d(pose) (6 x 12 per marker and per side).
    Eigen::Matrix<double, 6, 1> ti, tj;
    {
      Vec3 v, omega;
      bodies[c.i.body]->marker_twist(c.i.marker, positions(c.i.body, y), velocities(c.i.body, y), v, omega);
      ti << v, omega;
      bodies[c.j.body]->marker_twist(c.j.marker, positions(c.j.body, y), velocities(c.j.body, y), v, omega);
      tj << v, omega;
    }
    Eigen::Matrix<double, Eigen::Dynamic, 24, 0, 6, 24> dvel = Eigen::MatrixXd::Zero(m, 24);
    Eigen::Matrix<double, 6, 24> dreac_i = Eigen::Matrix<double, 6, 24>::Zero(), dreac_j = dreac_i;
    ConstraintEquations& pe = w.perturbed[ci];
    for (int side = 0; side < 2; ++side)
      for (int col = 0; col < 6; ++col) {
        const double h = col < 3 ? 1e-7 * std::max(1.0, std::abs((side ? mj : mi).position[col])) : 1e-7;
        Equations vel_p(m), vel_m(m);
        Eigen::Matrix<double, 6, 1> ri_p, rj_p, ri_m, rj_m;
        for (double sign : {1.0, -1.0}) {
          MarkerMotion a = mi, b = mj;
          perturb(side ? b : a, col, sign * h);
          pe.phi.setZero(), pe.di.setZero(), pe.dj.setZero(), pe.phi_t.setZero();
          c.constraint->evaluate(t, a, b, pe);
          Equations& vel = sign > 0 ? vel_p : vel_m;  // D twist + Phi_t, term by term (no temporary)
          vel.noalias() = pe.di * ti;
          vel.noalias() += pe.dj * tj;
          vel += pe.phi_t;
          (sign > 0 ? ri_p : ri_m) = pe.di.transpose() * lambda;
          (sign > 0 ? rj_p : rj_m) = pe.dj.transpose() * lambda;
        }
        const int k = 12 * side + col;
        dvel.col(k) = (vel_p - vel_m) / (2 * h);
        dreac_i.col(k) = (ri_p - ri_m) / (2 * h);
        dreac_j.col(k) = (rj_p - rj_m) / (2 * h);
      }
    const int lam0 = lambda_offset_ + c.first_row, mu0 = mu_offset_ + c.first_row;
    // velocity rows: D's own change with the poses of both markers
    for (int other = 0; other < 2; ++other) {
      const MarkerDerivatives& o = other ? dj : di;
      if (o.nq == 0) continue;
      for (int e = 0; e < m; ++e)
        if (c.active[e])
          jm.block(lam0 + e, o.q0, 1, o.nq).noalias() += dvel.block(e, 12 * other, 1, 6) * o.s.topRows(6);
    }
    for (int side = 0; side < 2; ++side) {
      const MarkerDerivatives& d = side ? dj : di;
      const auto& dm = side ? eq.dj : eq.di;
      if (d.nq + d.nw == 0) continue;
      for (int e = 0; e < m; ++e) {
        if (!c.active[e]) continue;
        // velocity rows: D [v; omega] + Phi_t
        jm.block(lam0 + e, d.w0, 1, d.nw).noalias() += dm.row(e) * d.g;
        jm.block(lam0 + e, d.q0, 1, d.nq).noalias() += dm.row(e) * d.s.bottomRows(6);
        // position rows: dPhi/d(pose) = D
        jm.block(mu0 + e, d.q0, 1, d.nq).noalias() += dm.row(e) * d.s.topRows(6);
      }
      if (d.nw == 0) continue;
      // dynamics rows: + G^T D^T lambda
      for (int e = 0; e < m; ++e)
        if (c.active[e])
          jm.block(d.w0, lam0 + e, d.nw, 1).noalias() += d.g.transpose() * dm.row(e).transpose();
      const Eigen::Matrix<double, 6, 24>& dreac = side ? dreac_j : dreac_i;
      for (int other = 0; other < 2; ++other) {
        const MarkerDerivatives& o = other ? dj : di;
        if (o.nq == 0) continue;
        auto pose = w.pose.leftCols(o.nq);  // d(D^T lambda)/d(pose of o) through o's coordinates
        pose.noalias() = dreac.block<6, 6>(0, 12 * other) * o.s.topRows(6);
        jm.block(d.w0, o.q0, d.nw, o.nq).noalias() += d.g.transpose() * pose;
      }
      const Eigen::Matrix<double, 6, 1> wr = dm.transpose() * lambda;
      auto dq = w.scratch_q.topLeftCorner(d.nw, d.nq);
      dq.setZero();
      bodies[d.body]->add_wrench_derivative((side ? c.j : c.i).marker, positions(d.body, y), wr.head<3>(),
                                            wr.tail<3>(), dq);
      jm.block(d.w0, d.q0, d.nw, d.nq) += dq;
      // kinematic rows: w_eff = w - C^T mu, so d/dmu = -(d kin/d w_eff) G^T D^T
      for (int e = 0; e < m; ++e)
        if (c.active[e]) {
          auto g_row = w.g_row.head(d.nw);
          g_row.noalias() = d.g.transpose() * dm.row(e).transpose();
          jm.block(d.q0, mu0 + e, d.nq, 1).noalias() -= w.kin_dw[d.body] * g_row;
        }
    }
  }

  // Clock: phi' - z_j . (omega_i - omega_j).
  if (clock_index_ >= 0) {
    const int r = clock_index_;
    jm(r, r) += cj;
    const MarkerMotion mi = marker_motion(clock->i, y), mj = marker_motion(clock->j, y);
    const Vec3 z = mj.axes.col(2), dw = mi.angular_velocity - mj.angular_velocity;
    auto& [di, dj] = w.clock_markers;
    derivatives(clock->i, di);
    derivatives(clock->j, dj);
    Eigen::Matrix<double, 1, 12> a = Eigen::Matrix<double, 1, 12>::Zero();
    a.segment<3>(9) = -z.transpose();
    add_motion(r, a, di);
    a.setZero();
    a.segment<3>(9) = z.transpose();
    a.segment<3>(3) = -z.cross(dw).transpose();
    add_motion(r, a, dj);
  }

  // Euler parameters: the closed forms above are exact for changes of p tangent to |p| = 1 (rotations); a
  // radial change scales A(p) (rotation.hpp), which no marker rotation expresses. That one direction per
  // floating body is a forward difference of the residual, J_p <- J_p (I - u u^T) + dF/du u^T with u = p /
  // |p| (y and y' moved together: dF/dy + cj dF/dy'); bodies that share no row are moved together (one
  // residual per group, radial_groups_).
  const Eigen::VectorXd& f0 = w.f0;
  for (const auto& group : radial_groups_) {
    Eigen::VectorXd &yy = w.y_scratch, &yyp = w.yp_scratch;
    yy = Eigen::Map<const Eigen::VectorXd>(y, size_);
    yyp = Eigen::Map<const Eigen::VectorXd>(yp, size_);
    const double h = 1e-8;
    for (int b : group) {
      const int o = body_offset_[b] + 3;
      const Eigen::Vector4d u = yy.segment<4>(o).normalized();
      yy.segment<4>(o) += h * u;
      yyp.segment<4>(o) += cj * h * u;
    }
    residual(t, yy.data(), yyp.data(), w.f_plus.data());
    for (int b : group) {
      const int o = body_offset_[b] + 3;
      const Eigen::Vector4d u = Eigen::Map<const Eigen::Vector4d>(y + o).normalized();
      w.radial.noalias() = jm.middleCols<4>(o) * (Eigen::Matrix4d::Identity() - u * u.transpose());
      jm.middleCols<4>(o) = w.radial;
      const SparsityPattern& p = w.pattern;
      for (int k = p.column_start[o]; k < p.column_start[o + 1]; ++k) {
        const int r = p.rows[k];
        jm.row(r).segment<4>(o) += (w.f_plus[r] - f0[r]) / h * u.transpose();
      }
    }
  }
  // (The workspace now holds the last group's perturbed state: nothing reads it before the next residual
  // refills it, and the journal bearings keep their last two film states, so no residual restores it.)

  // Energy integrals: their rates only (they feed nothing back).
  jm(energy_offset_, energy_offset_) += cj;
  jm(energy_offset_ + 1, energy_offset_ + 1) += cj;

  // The pattern's entries.
  const SparsityPattern& p = w.pattern;
  values.resize(p.rows.size());
  for (int col = 0; col < p.n; ++col)
    for (int k = p.column_start[col]; k < p.column_start[col + 1]; ++k) values[k] = jm(p.rows[k], col);
}

// ---------------------------------------------------------------- start
void Model::constraint_matrix(double t, const double* y, Eigen::MatrixXd& cm, Eigen::VectorXd& phi,
                              Eigen::VectorXd& phi_t) const {
  cm = Eigen::MatrixXd::Zero(n_eq_, n_w_);
  phi = Eigen::VectorXd::Zero(n_eq_);
  phi_t = Eigen::VectorXd::Zero(n_eq_);
  for (const auto& c : constraints) {
    const MarkerMotion mi = marker_motion(c.i, y), mj = marker_motion(c.j, y);
    ConstraintEquations eq(c.constraint->size());
    c.constraint->evaluate(t, mi, mj, eq);
    const MarkerJacobian ji = bodies[c.i.body]->marker_jacobian(c.i.marker, positions(c.i.body, y));
    const MarkerJacobian jj = bodies[c.j.body]->marker_jacobian(c.j.marker, positions(c.j.body, y));
    const int m = c.constraint->size();
    cm.block(c.first_row, w_global_offset_[c.i.body], m, ji.jv.cols()) +=
        eq.di.leftCols<3>() * ji.jv + eq.di.rightCols<3>() * ji.jw;
    cm.block(c.first_row, w_global_offset_[c.j.body], m, jj.jv.cols()) +=
        eq.dj.leftCols<3>() * jj.jv + eq.dj.rightCols<3>() * jj.jw;
    phi.segment(c.first_row, m) = eq.phi;
    phi_t.segment(c.first_row, m) = eq.phi_t;
  }
}

void Model::consistent_initial_state(double t0, Eigen::VectorXd& y, Eigen::VectorXd& yp, const Logger& log) {
  y = Eigen::VectorXd::Zero(size_);
  yp = Eigen::VectorXd::Zero(size_);
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    y.segment(body_offset_[b], bodies[b]->position_count()) = bodies[b]->initial_positions();
    y.segment(velocity_offset(b), bodies[b]->velocity_count()) = bodies[b]->initial_velocities();
  }
  for (const auto& f : forces) {
    const auto states = f.element->states();
    for (int s = 0; s < f.state_count; ++s) y[f.state_offset + s] = states[s].initial;
  }
  auto apply_velocity_step = [&](const Eigen::VectorXd& dw) {  // q += H(q) dw, Euler parameters renormalized
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      const int nq = bodies[b]->position_count(), nw = bodies[b]->velocity_count();
      if (nq == 0) continue;
      const Eigen::VectorXd dq = bodies[b]->position_rates(
          positions(b, y.data()), {dw.data() + w_global_offset_[b], std::size_t(nw)});
      y.segment(body_offset_[b], nq) += dq;
      if (bodies[b]->kind() != "point-mass" && nq >= 7) y.segment(body_offset_[b] + 3, 4).normalize();
    }
  };

  Eigen::MatrixXd cm;
  Eigen::VectorXd phi, phi_t;
  // 1. Positions onto Phi = 0 by minimal-norm Gauss-Newton steps.
  if (n_eq_ > 0) {
    double initial_violation = 0;
    for (int it = 0; it < 50; ++it) {
      // Dense decompositions of the whole constraint matrix: seconds on a large model, so a signal is heard
      // (solve polls the flag, the results file does not exist yet: nothing to keep).
      if (interrupt_requested()) throw Interrupted("interrupted while assembling the initial positions");
      constraint_matrix(t0, y.data(), cm, phi, phi_t);
      if (it == 0) initial_violation = phi.lpNorm<Eigen::Infinity>();
      if (phi.lpNorm<Eigen::Infinity>() < 1e-13) break;
      apply_velocity_step(-cm.completeOrthogonalDecomposition().solve(phi));
      if (it == 49) {
        // Name the joint (and equation) violated most: that is where the markers do not fit together.
        std::ostringstream msg;
        msg << "the initial positions cannot be assembled: the joints' position equations are still violated by "
            << phi.lpNorm<Eigen::Infinity>() << " after 50 corrections";
        Eigen::Index worst = 0;
        phi.cwiseAbs().maxCoeff(&worst);
        for (const auto& c : constraints)
          if (worst >= c.first_row && worst < c.first_row + c.constraint->size())
            msg << ", most in " << c.constraint->type() << " '" << c.name << "' ("
                << c.constraint->equation_names()[worst - c.first_row] << ")";
        msg << " (check the markers' positions and axes)";
        throw Error(msg.str());
      }
    }
    if (initial_violation > 1e-9)
      log.info("initial positions assembled: joint violation " + std::to_string(initial_violation) + " -> " +
               std::to_string(phi.lpNorm<Eigen::Infinity>()));

    // 2. Redundant equations: a rank-revealing QR of C^T (columns = equations).
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(cm.transpose());
    qr.setThreshold(1e-9);
    const int rank = static_cast<int>(qr.rank());
    if (rank < n_eq_) {
      std::set<int> independent;
      for (int k = 0; k < rank; ++k) independent.insert(qr.colsPermutation().indices()[k]);
      std::ostringstream msg;
      msg << (n_eq_ - rank) << " of " << n_eq_ << " constraint equations are redundant and removed:";
      for (auto& c : constraints)
        for (int e = 0; e < c.constraint->size(); ++e)
          if (!independent.count(c.first_row + e)) {
            c.active[e] = 0;
            msg << " " << c.constraint->type() << " '" << c.name << "' " << c.constraint->equation_names()[e]
                << ";";
          }
      log.info(msg.str());
    }
  }
  auto active_rows = [&](const Eigen::MatrixXd& full) {
    std::vector<int> keep;
    for (const auto& c : constraints)
      for (int e = 0; e < c.constraint->size(); ++e)
        if (c.active[e]) keep.push_back(c.first_row + e);
    Eigen::MatrixXd out(keep.size(), full.cols());
    for (std::size_t k = 0; k < keep.size(); ++k) out.row(k) = full.row(keep[k]);
    return std::pair{out, keep};
  };

  Eigen::VectorXd w(n_w_);
  for (std::size_t b = 0; b < bodies.size(); ++b)
    w.segment(w_global_offset_[b], bodies[b]->velocity_count()) =
        y.segment(velocity_offset(b), bodies[b]->velocity_count());
  auto store_w = [&] {
    for (std::size_t b = 0; b < bodies.size(); ++b)
      y.segment(velocity_offset(b), bodies[b]->velocity_count()) =
          w.segment(w_global_offset_[b], bodies[b]->velocity_count());
  };

  // 3. Velocities onto C w + Phi_t = 0: the correction of least kinetic energy (the mass-weighted projection
  //    dw = -M^-1 C^T (C M^-1 C^T)^-1 (C w + Phi_t)), so a body whose velocity the user left out takes the
  //    velocity the joints impose with the least change of momentum.
  Eigen::MatrixXd mass = Eigen::MatrixXd::Zero(n_w_, n_w_);
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const int nw = bodies[b]->velocity_count();
    if (nw > 0)
      mass.block(w_global_offset_[b], w_global_offset_[b], nw, nw) =
          bodies[b]->mass_matrix(positions(b, y.data()));
  }
  std::vector<int> keep;
  if (n_eq_ > 0) {
    constraint_matrix(t0, y.data(), cm, phi, phi_t);
    auto [ca, rows] = active_rows(cm);
    keep = rows;
    Eigen::VectorXd g(keep.size());
    for (std::size_t k = 0; k < keep.size(); ++k) g[k] = phi_t[keep[k]];
    const Eigen::VectorXd violation = ca * w + g;
    if (violation.size() > 0) {
      const Eigen::LDLT<Eigen::MatrixXd> m_ldlt(mass);
      const Eigen::MatrixXd minv_ct = m_ldlt.solve(ca.transpose());
      const Eigen::MatrixXd schur = ca * minv_ct;
      w -= minv_ct * schur.completeOrthogonalDecomposition().solve(violation);
    }
    store_w();
  }

  // Position rates.
  for (std::size_t b = 0; b < bodies.size(); ++b)
    yp.segment(body_offset_[b], bodies[b]->position_count()) =
        bodies[b]->position_rates(positions(b, y.data()), velocities(b, y.data()));
  if (clock_index_ >= 0) {
    const MarkerMotion mi = marker_motion(clock->i, y.data()), mj = marker_motion(clock->j, y.data());
    y[clock_index_] = relative_angle(mi, mj) - clock->zero_angle;
    yp[clock_index_] = mj.axes.col(2).dot(mi.angular_velocity - mj.angular_velocity);
  }

  // Element states: the rates of differential states (algebraic states: their values) that zero their rows,
  // by Newton with local differences (a few iterations; the rows are usually linear in them).
  {
    Eigen::VectorXd f0(size_), f1(size_);
    for (const auto& fe : forces)
      for (int s = 0; s < fe.state_count; ++s) {
        const bool differential = fe.element->states()[s].differential;
        const int k = fe.state_offset + s;
        double& v = differential ? yp[k] : y[k];
        for (int it = 0; it < 20; ++it) {
          if (interrupt_requested())
            throw Interrupted("interrupted while finding the initial element states");
          residual(t0, y.data(), yp.data(), f0.data());
          if (std::abs(f0[k]) < 1e-14 * std::max(1.0, std::abs(v))) break;
          const double h = 1e-7 * std::max(1.0, std::abs(v));
          v += h;
          residual(t0, y.data(), yp.data(), f1.data());
          v -= h;
          const double slope = (f1[k] - f0[k]) / h;
          if (slope == 0)
            throw Error(fe.element->type() + " '" + fe.name + "': the row of its state " +
                        fe.element->states()[s].name + " does not depend on it");
          v -= f0[k] / slope;
        }
      }
  }

  // 4. Accelerations and multipliers: [M C^T; C 0] [w'; lambda] = [Q - h; -(dC/dt w + Phi_tt)].
  Eigen::VectorXd f0(size_);
  residual(t0, y.data(), yp.data(), f0.data());  // with w' = 0, lambda = 0: dynamics rows = h - Q
  Eigen::VectorXd rhs_w(n_w_);
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const int nw = bodies[b]->velocity_count();
    if (nw == 0) continue;
    rhs_w.segment(w_global_offset_[b], nw) = -f0.segment(velocity_offset(b), nw);
  }
  const int na = static_cast<int>(keep.size());
  Eigen::MatrixXd aug = Eigen::MatrixXd::Zero(n_w_ + na, n_w_ + na);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n_w_ + na);
  aug.topLeftCorner(n_w_, n_w_) = mass;
  rhs.head(n_w_) = rhs_w;
  if (na > 0) {
    auto [ca, rows] = active_rows(cm);
    aug.topRightCorner(n_w_, na) = ca.transpose();
    aug.bottomLeftCorner(na, n_w_) = ca;
    // d/dt (C w + Phi_t) at w' = 0 by a central difference along the motion.
    const double h = 1e-6;
    Eigen::VectorXd yplus = y + h * yp, yminus = y - h * yp, fp(size_), fm(size_);
    residual(t0 + h, yplus.data(), yp.data(), fp.data());
    residual(t0 - h, yminus.data(), yp.data(), fm.data());
    for (int k = 0; k < na; ++k)
      rhs[n_w_ + k] = -(fp[lambda_offset_ + rows[k]] - fm[lambda_offset_ + rows[k]]) / (2 * h);
  }
  const Eigen::VectorXd sol = aug.fullPivLu().solve(rhs);
  for (std::size_t b = 0; b < bodies.size(); ++b)
    yp.segment(velocity_offset(b), bodies[b]->velocity_count()) =
        sol.segment(w_global_offset_[b], bodies[b]->velocity_count());
  for (int k = 0; k < na; ++k) y[lambda_offset_ + keep[k]] = sol[n_w_ + k];

  // 5. The energy integrals start at zero with the rates of this state.
  y[energy_offset_] = y[energy_offset_ + 1] = 0;
  yp[energy_offset_] = yp[energy_offset_ + 1] = 0;
  residual(t0, y.data(), yp.data(), f0.data());
  yp[energy_offset_] = -f0[energy_offset_];
  yp[energy_offset_ + 1] = -f0[energy_offset_ + 1];
}

// ---------------------------------------------------------------- pattern
SparsityPattern Model::jacobian_pattern() const {
  // Blocks: each body's states, the clock, each element's states, the energy integrals, each constraint's
  // lambda and mu. deps[r] = the column blocks row block r depends on.
  const int nb = static_cast<int>(bodies.size()), nf = static_cast<int>(forces.size());
  const int clock_block = nb, element_block0 = nb + 1, energy_block = nb + 1 + nf,
            constraint_block0 = energy_block + 1;
  const int nblocks = constraint_block0 + static_cast<int>(constraints.size());
  std::vector<std::vector<int>> block_rows(nblocks);
  for (int b = 0; b < nb; ++b)
    for (int r = body_offset_[b]; r < body_offset_[b] + bodies[b]->state_count(); ++r)
      block_rows[b].push_back(r);
  if (clock_index_ >= 0) block_rows[clock_block].push_back(clock_index_);
  for (int f = 0; f < nf; ++f)
    for (int s = 0; s < forces[f].state_count; ++s)
      block_rows[element_block0 + f].push_back(forces[f].state_offset + s);
  block_rows[energy_block] = {energy_offset_, energy_offset_ + 1};
  for (std::size_t c = 0; c < constraints.size(); ++c)
    for (int e = 0; e < constraints[c].constraint->size(); ++e) {
      block_rows[constraint_block0 + c].push_back(lambda_offset_ + constraints[c].first_row + e);
      block_rows[constraint_block0 + c].push_back(mu_offset_ + constraints[c].first_row + e);
    }
  std::vector<std::set<int>> deps(nblocks);
  for (int k = 0; k < nblocks; ++k) deps[k].insert(k);
  for (std::size_t c = 0; c < constraints.size(); ++c) {
    const int cb = constraint_block0 + static_cast<int>(c);
    for (int b : {constraints[c].i.body, constraints[c].j.body}) {
      deps[b].insert(cb);
      deps[cb].insert(constraints[c].i.body);
      deps[cb].insert(constraints[c].j.body);
      deps[b].insert(constraints[c].i.body);
      deps[b].insert(constraints[c].j.body);
    }
  }
  for (int f = 0; f < nf; ++f) {
    const auto& fe = forces[f];
    std::vector<int> bs;
    for (const auto& m : fe.markers) bs.push_back(m.body);
    const int eb = element_block0 + f;
    const bool crank = clock_index_ >= 0 && fe.element->uses_crank_angle();
    for (int a : bs) {
      for (int b : bs) deps[a].insert(b);
      if (fe.state_count > 0) deps[a].insert(eb), deps[eb].insert(a);
      if (crank) deps[a].insert(clock_block);
    }
    if (crank && fe.state_count > 0) deps[eb].insert(clock_block);
  }
  if (clock_index_ >= 0) {
    deps[clock_block].insert(clock->i.body);
    deps[clock_block].insert(clock->j.body);
  }
  std::vector<std::set<int>> col_deps(nblocks);
  for (int r = 0; r < nblocks; ++r)
    for (int c : deps[r]) col_deps[c].insert(r);
  std::vector<std::vector<int>> columns(size_);
  for (int cb = 0; cb < nblocks; ++cb) {
    std::vector<int> rows;
    for (int rb : col_deps[cb]) rows.insert(rows.end(), block_rows[rb].begin(), block_rows[rb].end());
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    for (int c : block_rows[cb]) columns[c] = rows;
  }
  SparsityPattern p;
  p.n = size_;
  p.column_start.push_back(0);
  for (int c = 0; c < size_; ++c) {
    if (columns[c].empty()) columns[c].push_back(c);
    p.rows.insert(p.rows.end(), columns[c].begin(), columns[c].end());
    p.column_start.push_back(static_cast<int>(p.rows.size()));
  }
  return p;
}

// ---------------------------------------------------------------- output
Vec3 Model::marker_acceleration(const MarkerRef& m, const double* y, const double* yp) const {
  const auto& body = *bodies[m.body];
  const int nw = body.velocity_count();
  if (nw == 0) return Vec3::Zero();
  return body.marker_acceleration(m.marker, positions(m.body, y), velocities(m.body, y),
                                  {yp + velocity_offset(m.body), std::size_t(nw)});
}

void Model::reaction(int ci, double t, const double* y, Vec3& force, Vec3& torque) const {
  // The reaction on body i is -C_i^T lambda = -J_i^T D_i^T lambda: the wrench -D_i^T lambda at marker i.
  const auto& c = constraints[ci];
  const MarkerMotion mi = marker_motion(c.i, y), mj = marker_motion(c.j, y);
  ConstraintEquations eq(c.constraint->size());
  c.constraint->evaluate(t, mi, mj, eq);  // at t: a speed driver's D_i turns with theta(t)
  Eigen::VectorXd lambda(c.constraint->size());
  for (int e = 0; e < c.constraint->size(); ++e)
    lambda[e] = c.active[e] ? y[lambda_offset_ + c.first_row + e] : 0.0;
  const Eigen::Matrix<double, 6, 1> ft = -eq.di.transpose() * lambda;
  force = ft.head<3>();
  torque = ft.tail<3>();
}

void Model::applied_wrench(int b, double t, const double* y, const double* yp, const Vec3& point, Vec3& force,
                           Vec3& torque) const {
  force.setZero(), torque.setZero();
  auto add = [&](const Vec3& at, const Vec3& f, const Vec3& tq) {
    force += f;
    torque += tq + (at - point).cross(f);
  };
  std::vector<double> rows;
  for (std::size_t fi = 0; fi < forces.size(); ++fi) {
    const ForceEntry& fe = forces[fi];
    if (std::none_of(fe.markers.begin(), fe.markers.end(), [&](const MarkerRef& m) { return m.body == b; }))
      continue;
    rows.assign(static_cast<std::size_t>(fe.state_count), 0.0);
    evaluate_element(fi, t, y, yp, rows.data());
    for (std::size_t k = 0; k < fe.markers.size(); ++k)
      if (fe.markers[k].body == b)
        add(ws_->motions[fi][k].position, ws_->wrenches[fi][k].force, ws_->wrenches[fi][k].torque);
  }
  // A constraint acts on body i by the wrench -D_i^T lambda at marker i, on body j by -D_j^T lambda at marker j.
  for (const auto& c : constraints) {
    if (c.i.body != b && c.j.body != b) continue;
    const MarkerMotion mi = marker_motion(c.i, y), mj = marker_motion(c.j, y);
    ConstraintEquations eq(c.constraint->size());
    c.constraint->evaluate(t, mi, mj, eq);
    Eigen::VectorXd lambda(c.constraint->size());
    for (int e = 0; e < c.constraint->size(); ++e)
      lambda[e] = c.active[e] ? y[lambda_offset_ + c.first_row + e] : 0.0;
    if (c.i.body == b) {
      const Eigen::Matrix<double, 6, 1> wi = -eq.di.transpose() * lambda;
      add(mi.position, wi.head<3>(), wi.tail<3>());
    }
    if (c.j.body == b) {
      const Eigen::Matrix<double, 6, 1> wj = -eq.dj.transpose() * lambda;
      add(mj.position, wj.head<3>(), wj.tail<3>());
    }
  }
}

std::pair<double, double> Model::constraint_violation(double t, const double* y) const {
  if (n_eq_ == 0) return {0.0, 0.0};
  Eigen::MatrixXd cm;
  Eigen::VectorXd phi, phi_t;
  constraint_matrix(t, y, cm, phi, phi_t);
  Eigen::VectorXd w(n_w_);
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const auto v = velocities(static_cast<int>(b), y);
    for (std::size_t k = 0; k < v.size(); ++k) w[w_global_offset_[b] + static_cast<int>(k)] = v[k];
  }
  const Eigen::VectorXd vel = cm * w + phi_t;
  double p_max = 0, v_max = 0;
  for (const auto& c : constraints)
    for (int e = 0; e < c.constraint->size(); ++e)
      if (c.active[e]) {
        p_max = std::max(p_max, std::abs(phi[c.first_row + e]));
        v_max = std::max(v_max, std::abs(vel[c.first_row + e]));
      }
  return {p_max, v_max};
}

double Model::clock_angle(const double* y) const {
  if (clock_index_ < 0) return 0.0;
  constexpr double kTurn = 2 * std::numbers::pi;
  const double measured =
      relative_angle(marker_motion(clock->i, y), marker_motion(clock->j, y)) - clock->zero_angle;
  return measured + kTurn * std::round((y[clock_index_] - measured) / kTurn);
}

double Model::total_kinetic_energy(const double* y) const {
  double e = 0;
  for (std::size_t b = 0; b < bodies.size(); ++b)
    e += bodies[b]->kinetic_energy(positions(b, y), velocities(b, y));
  return e;
}

EnergyBalance Model::energy(double t, const double* y, const double* yp) const {
  EnergyBalance e;
  e.kinetic = total_kinetic_energy(y);
  for (std::size_t b = 0; b < bodies.size(); ++b)
    e.potential += bodies[b]->potential_energy(positions(static_cast<int>(b), y), gravity);
  std::vector<MarkerMotion> markers;
  for (const auto& f : forces) e.potential += f.element->energy(element_input(f, t, y, yp, markers)).stored;
  e.dissipated = y[energy_offset_];
  e.input = y[energy_offset_ + 1];
  return e;
}

}  // namespace nvh::solve
