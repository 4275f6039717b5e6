// The model's state layout, residual and consistent initial conditions (see model.hpp for the equations).
#include "solve/model.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "common/error.hpp"

namespace nvh::solve {

void Model::finalize() {
  body_offset_.clear();
  w_global_offset_.clear();
  int k = 0;
  n_w_ = 0;
  for (const auto& b : bodies) {
    body_offset_.push_back(k);
    k += b->state_count();
    w_global_offset_.push_back(n_w_);
    n_w_ += b->velocity_count();
  }
  clock_index_ = clock ? k++ : -1;
  n_eq_ = 0;
  for (auto& c : constraints) {
    c.first_row = n_eq_;
    n_eq_ += c.constraint->size();
    c.active.assign(c.constraint->size(), 1);
  }
  lambda_offset_ = k;
  mu_offset_ = k + n_eq_;
  size_ = k + 2 * n_eq_;
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

ForceContext Model::context(double t, const double* y) const { return {t, crank_angle(y)}; }

Eigen::VectorXd Model::differential_mask() const {
  Eigen::VectorXd id = Eigen::VectorXd::Zero(size_);
  for (std::size_t b = 0; b < bodies.size(); ++b)
    id.segment(body_offset_[b], bodies[b]->position_count() + bodies[b]->velocity_count()).setOnes();
  if (clock_index_ >= 0) id[clock_index_] = 1;
  return id;
}

std::string Model::describe_state(int k) const {
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const int o = body_offset_[b], nq = bodies[b]->position_count(), nw = bodies[b]->velocity_count();
    if (k >= o && k < o + bodies[b]->state_count()) {
      const int r = k - o;
      std::string what = r < nq ? "q[" + std::to_string(r) + "]"
                         : r < nq + nw ? "w[" + std::to_string(r - nq) + "]"
                                       : "normalization";
      return "body '" + bodies[b]->name() + "' " + what;
    }
  }
  if (k == clock_index_) return "clock angle";
  for (const auto& c : constraints) {
    for (int e = 0; e < c.constraint->size(); ++e) {
      const auto name = c.constraint->equation_names()[e];
      if (k == lambda_offset_ + c.first_row + e) return c.constraint->type() + " '" + c.name + "' velocity equation " + name;
      if (k == mu_offset_ + c.first_row + e) return c.constraint->type() + " '" + c.name + "' position equation " + name;
    }
  }
  return "state " + std::to_string(k);
}

namespace {
// Body-level generalized force from force F and torque T (global) at a point attached to a marker.
void add_generalized_force(const MarkerJacobian& j, const Vec3& force, const Vec3& torque, double* q) {
  const int n = static_cast<int>(j.jv.cols());
  Eigen::Map<Eigen::VectorXd>(q, n) += j.jv.transpose() * force + j.jw.transpose() * torque;
}
}  // namespace

void Model::residual(double t, const double* y, const double* yp, double* f) const {
  // Generalized forces Q, C^T lambda and C^T mu, stacked over all bodies' velocities.
  Eigen::VectorXd q_force = Eigen::VectorXd::Zero(n_w_), ct_lambda = Eigen::VectorXd::Zero(n_w_),
                  ct_mu = Eigen::VectorXd::Zero(n_w_);

  // Constraints: their rows and their reactions.
  for (const auto& c : constraints) {
    const MarkerMotion mi = marker_motion(c.i, y), mj = marker_motion(c.j, y);
    ConstraintEquations eq(c.constraint->size());
    c.constraint->evaluate(t, mi, mj, eq);
    const auto& bi = *bodies[c.i.body];
    const auto& bj = *bodies[c.j.body];
    const MarkerJacobian ji = bi.marker_jacobian(c.i.marker, positions(c.i.body, y));
    const MarkerJacobian jj = bj.marker_jacobian(c.j.marker, positions(c.j.body, y));
    Eigen::MatrixXd ci = eq.di.leftCols<3>() * ji.jv + eq.di.rightCols<3>() * ji.jw;
    Eigen::MatrixXd cj = eq.dj.leftCols<3>() * jj.jv + eq.dj.rightCols<3>() * jj.jw;
    const auto wi = velocities(c.i.body, y), wj = velocities(c.j.body, y);
    for (int e = 0; e < c.constraint->size(); ++e) {
      const int row = c.first_row + e;
      const double lambda = y[lambda_offset_ + row], mu = y[mu_offset_ + row];
      if (!c.active[e]) {
        f[lambda_offset_ + row] = lambda;
        f[mu_offset_ + row] = mu;
        continue;
      }
      double vel = eq.phi_t[e];
      for (int k = 0; k < ci.cols(); ++k) vel += ci(e, k) * wi[k];
      for (int k = 0; k < cj.cols(); ++k) vel += cj(e, k) * wj[k];
      f[lambda_offset_ + row] = vel;
      f[mu_offset_ + row] = eq.phi[e];
      ct_lambda.segment(w_global_offset_[c.i.body], ci.cols()) += ci.row(e).transpose() * lambda;
      ct_lambda.segment(w_global_offset_[c.j.body], cj.cols()) += cj.row(e).transpose() * lambda;
      ct_mu.segment(w_global_offset_[c.i.body], ci.cols()) += ci.row(e).transpose() * mu;
      ct_mu.segment(w_global_offset_[c.j.body], cj.cols()) += cj.row(e).transpose() * mu;
    }
  }

  // Force elements: force on i at a point, the opposite on j at the same point.
  const ForceContext ctx = context(t, y);
  static const MarkerMotion kFixed{};
  for (const auto& fe : forces) {
    const MarkerMotion mi = marker_motion(fe.i, y);
    const MarkerMotion mj = fe.j ? marker_motion(*fe.j, y) : kFixed;
    const ElementForce ef = fe.element->evaluate(ctx, mi, mj);
    const auto& bi = *bodies[fe.i.body];
    if (bi.velocity_count() > 0) {
      const MarkerJacobian ji = bi.marker_jacobian(fe.i.marker, positions(fe.i.body, y)).shifted(ef.point - mi.position);
      add_generalized_force(ji, ef.force, ef.torque, q_force.data() + w_global_offset_[fe.i.body]);
    }
    if (fe.j && bodies[fe.j->body]->velocity_count() > 0) {
      const auto& bj = *bodies[fe.j->body];
      const MarkerJacobian jj = bj.marker_jacobian(fe.j->marker, positions(fe.j->body, y)).shifted(ef.point - mj.position);
      add_generalized_force(jj, -ef.force, -ef.torque, q_force.data() + w_global_offset_[fe.j->body]);
    }
  }

  // Body rows.
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const auto& body = *bodies[b];
    const int o = body_offset_[b], nq = body.position_count(), nw = body.velocity_count(), na = body.algebraic_count();
    if (nq + nw == 0) continue;
    const int wo = w_global_offset_[b];
    const Eigen::VectorXd w_eff = Eigen::Map<const Eigen::VectorXd>(y + o + nq, nw) - ct_mu.segment(wo, nw);
    body.kinematic_residual({y + o, std::size_t(nq)}, {yp + o, std::size_t(nq)}, {w_eff.data(), std::size_t(nw)},
                            {y + o + nq + nw, std::size_t(na)}, {f + o, std::size_t(nq)},
                            {f + o + nq + nw, std::size_t(na)});
    body.inertia_residual({y + o, std::size_t(nq)}, {y + o + nq, std::size_t(nw)}, {yp + o + nq, std::size_t(nw)},
                          gravity, {f + o + nq, std::size_t(nw)});
    Eigen::Map<Eigen::VectorXd>(f + o + nq, nw) += ct_lambda.segment(wo, nw) - q_force.segment(wo, nw);
  }

  if (clock_index_ >= 0) {
    const MarkerMotion mi = marker_motion(clock->i, y), mj = marker_motion(clock->j, y);
    f[clock_index_] = yp[clock_index_] - mj.axes.col(2).dot(mi.angular_velocity - mj.angular_velocity);
  }
}

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
  auto apply_velocity_step = [&](const Eigen::VectorXd& dw) {  // q += H(q) dw, Euler parameters renormalized
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      const int nq = bodies[b]->position_count(), nw = bodies[b]->velocity_count();
      if (nq == 0) continue;
      const Eigen::VectorXd dq = bodies[b]->position_rates(positions(b, y.data()), {dw.data() + w_global_offset_[b], std::size_t(nw)});
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
      constraint_matrix(t0, y.data(), cm, phi, phi_t);
      if (it == 0) initial_violation = phi.lpNorm<Eigen::Infinity>();
      if (phi.lpNorm<Eigen::Infinity>() < 1e-13) break;
      apply_velocity_step(-cm.completeOrthogonalDecomposition().solve(phi));
      if (it == 49) throw Error("the initial positions cannot be assembled: the joints' position equations are "
                                "still violated by " + std::to_string(phi.lpNorm<Eigen::Infinity>()) +
                                " after 50 corrections (check the markers' positions and axes)");
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
            msg << " " << c.constraint->type() << " '" << c.name << "' " << c.constraint->equation_names()[e] << ";";
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
    w.segment(w_global_offset_[b], bodies[b]->velocity_count()) = y.segment(velocity_offset(b), bodies[b]->velocity_count());
  auto store_w = [&] {
    for (std::size_t b = 0; b < bodies.size(); ++b)
      y.segment(velocity_offset(b), bodies[b]->velocity_count()) = w.segment(w_global_offset_[b], bodies[b]->velocity_count());
  };

  // 3. Velocities onto C w + Phi_t = 0: the correction of least kinetic energy (the mass-weighted projection
  //    dw = -M^-1 C^T (C M^-1 C^T)^-1 (C w + Phi_t)), so a body whose velocity the user left out takes the
  //    velocity the joints impose with the least change of momentum.
  Eigen::MatrixXd mass = Eigen::MatrixXd::Zero(n_w_, n_w_);
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const int nw = bodies[b]->velocity_count();
    if (nw > 0) mass.block(w_global_offset_[b], w_global_offset_[b], nw, nw) = bodies[b]->mass_matrix(positions(b, y.data()));
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
    yp.segment(velocity_offset(b), bodies[b]->velocity_count()) = sol.segment(w_global_offset_[b], bodies[b]->velocity_count());
  for (int k = 0; k < na; ++k) y[lambda_offset_ + keep[k]] = sol[n_w_ + k];
}

SparsityPattern Model::jacobian_pattern() const {
  // Block structure: a "block" is a body's states, the clock, or a constraint's lambda and mu.
  const int nb = static_cast<int>(bodies.size());
  const int nblocks = nb + 1 + static_cast<int>(constraints.size());
  std::vector<std::pair<int, int>> range(nblocks);  // [begin, end) pairs; constraint blocks handled apart
  for (int b = 0; b < nb; ++b) range[b] = {body_offset_[b], body_offset_[b] + bodies[b]->state_count()};
  range[nb] = clock_index_ >= 0 ? std::pair{clock_index_, clock_index_ + 1} : std::pair{0, 0};
  std::vector<std::set<int>> deps(nblocks);  // row block -> column blocks
  for (int k = 0; k < nblocks; ++k) deps[k].insert(k);
  for (std::size_t c = 0; c < constraints.size(); ++c) {
    const int cb = nb + 1 + static_cast<int>(c);
    for (int b : {constraints[c].i.body, constraints[c].j.body}) {
      deps[b].insert(cb);
      deps[cb].insert(b);
      deps[b].insert(constraints[c].i.body);
      deps[b].insert(constraints[c].j.body);
    }
  }
  for (const auto& fe : forces) {
    std::vector<int> bs = {fe.i.body};
    if (fe.j) bs.push_back(fe.j->body);
    for (int a : bs)
      for (int b : bs) deps[a].insert(b);
    if (clock_index_ >= 0)
      for (int a : bs) deps[a].insert(nb);
  }
  if (clock_index_ >= 0) {
    deps[nb].insert(clock->i.body);
    deps[nb].insert(clock->j.body);
  }
  auto rows_of = [&](int block, std::vector<int>& out) {
    if (block <= nb) {
      for (int r = range[block].first; r < range[block].second; ++r) out.push_back(r);
    } else {
      const auto& c = constraints[block - nb - 1];
      for (int e = 0; e < c.constraint->size(); ++e) {
        out.push_back(lambda_offset_ + c.first_row + e);
        out.push_back(mu_offset_ + c.first_row + e);
      }
    }
  };
  // Column sets: for each column block, the row blocks that depend on it.
  std::vector<std::set<int>> col_deps(nblocks);
  for (int r = 0; r < nblocks; ++r)
    for (int c : deps[r]) col_deps[c].insert(r);
  std::vector<std::vector<int>> columns(size_);
  for (int cb = 0; cb < nblocks; ++cb) {
    std::vector<int> cols, rows;
    rows_of(cb, cols);
    for (int rb : col_deps[cb]) rows_of(rb, rows);
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    for (int c : cols) columns[c] = rows;
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

Vec3 Model::marker_acceleration(const MarkerRef& m, const double* y, const double* yp) const {
  const auto& body = *bodies[m.body];
  const int nq = body.position_count(), nw = body.velocity_count();
  if (nw == 0) return Vec3::Zero();
  const auto q = positions(m.body, y);
  const auto w = velocities(m.body, y);
  const Eigen::Map<const Eigen::VectorXd> wv(w.data(), nw), wdot(yp + velocity_offset(m.body), nw);
  const MarkerJacobian j0 = body.marker_jacobian(m.marker, q);
  // d(Jv)/dt w by a central difference along q' = H w
  const Eigen::VectorXd qd = body.position_rates(q, w);
  const double h = 1e-6;
  Eigen::VectorXd qp = Eigen::Map<const Eigen::VectorXd>(q.data(), nq) + h * qd;
  Eigen::VectorXd qm = Eigen::Map<const Eigen::VectorXd>(q.data(), nq) - h * qd;
  const MarkerJacobian jp = body.marker_jacobian(m.marker, {qp.data(), std::size_t(nq)});
  const MarkerJacobian jm = body.marker_jacobian(m.marker, {qm.data(), std::size_t(nq)});
  return j0.jv * wdot + (jp.jv - jm.jv) * wv / (2 * h);
}

void Model::reaction(int ci, const double* y, Vec3& force, Vec3& torque) const {
  // The reaction on body i is -C_i^T lambda; written as a force and torque at marker i by solving
  // Jv^T F + Jw^T T = -C_i^T lambda through the marker's 6 D Jacobian (exact for rigid bodies and point masses).
  const auto& c = constraints[ci];
  const MarkerMotion mi = marker_motion(c.i, y), mj = marker_motion(c.j, y);
  ConstraintEquations eq(c.constraint->size());
  c.constraint->evaluate(0.0, mi, mj, eq);
  Eigen::VectorXd lambda(c.constraint->size());
  for (int e = 0; e < c.constraint->size(); ++e) lambda[e] = c.active[e] ? y[lambda_offset_ + c.first_row + e] : 0.0;
  // In marker-twist space the generalized reaction is -Di^T lambda = [F; T] directly.
  const Eigen::Matrix<double, 6, 1> ft = -eq.di.transpose() * lambda;
  force = ft.head<3>();
  torque = ft.tail<3>();
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

double Model::total_kinetic_energy(const double* y) const {
  double e = 0;
  for (std::size_t b = 0; b < bodies.size(); ++b) e += bodies[b]->kinetic_energy(positions(b, y), velocities(b, y));
  return e;
}

}  // namespace nvh::solve
