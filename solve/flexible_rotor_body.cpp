// The flexible body on a fixed axis (flexible_rotor_body.hpp for the coordinates and the equations): every
// function evaluates the floating-frame body of the same superelement at Q(q), B w, B w' and projects.
//
// Layouts: q = [theta, eta], w = [theta', eta'] (n modes); the floating frame's Q = [r, p, eta] (7 + n), W =
// [v, omega_body, eta'] (6 + n). B^T X keeps a_b^T X_omega and X_eta; X B keeps X_omega a_b and X_eta; X dQ
// keeps X_p dp/dtheta and X_eta.
#include "solve/flexible_rotor_body.hpp"

#include <cmath>

#include "common/error.hpp"

namespace nvh::solve {
namespace {
std::span<const double> cs(const Eigen::VectorXd& v) {
  return {v.data(), static_cast<std::size_t>(v.size())};
}
std::span<double> ms(Eigen::VectorXd& v) {
  return {v.data(), static_cast<std::size_t>(v.size())};
}
}  // namespace

FlexibleRotorBody::FlexibleRotorBody(FlexibleBody frame, const Vec3& axis, double speed)
    : Body(frame.name()),
      frame_(std::move(frame)),
      n_(frame_.modes()),
      axis_(axis.normalized()),
      speed_(speed) {
  const Eigen::VectorXd q0 = frame_.initial_positions();
  pivot_ = q0.head<3>();
  p0_ = q0.segment<4>(3);
  axis_b_ = rotation_matrix(p0_).transpose() * axis_;
  bp0_ = rate_matrix(axis_b_) * p0_;
  for (const MarkerDefinition& m : frame_.markers()) Body::add_marker(m);
  fq_.resize(7 + n_);
  fw_.resize(6 + n_);
  fwd_.resize(6 + n_);
  rows_.resize(6 + n_);
  gen_.resize(6 + n_);
  fm_.resize(6 + n_, 6 + n_);
  fdq_.resize(6 + n_, 7 + n_);
  fdw_.resize(6 + n_, 6 + n_);
  sens_.resize(12, 7 + n_);
  jv_.resize(3, 6 + n_);
  jw_.resize(3, 6 + n_);
}

int FlexibleRotorBody::add_marker(MarkerDefinition m) {
  frame_.add_marker(m);
  return Body::add_marker(std::move(m));
}

std::string FlexibleRotorBody::state_meaning(int r) const {
  if (r == 0) return "angle theta";
  if (r == 1 + n_) return "angular speed theta'";
  // the floating frame's words for its modal states: q index 7 + k, w index 13 + n + k
  if (r < 1 + n_) return frame_.state_meaning(7 + (r - 1));
  if (r < 2 + 2 * n_) return frame_.state_meaning(7 + n_ + 6 + (r - 2 - n_));
  return {};
}

Vec4 FlexibleRotorBody::euler_parameters(double theta) const {
  return std::cos(0.5 * theta) * p0_ + std::sin(0.5 * theta) * bp0_;
}
Vec4 FlexibleRotorBody::dp_dtheta(double theta) const {
  return 0.5 * (-std::sin(0.5 * theta) * p0_ + std::cos(0.5 * theta) * bp0_);
}

void FlexibleRotorBody::lift(std::span<const double> q) const {
  fq_.head<3>() = pivot_;
  fq_.segment<4>(3) = euler_parameters(q[0]);
  fq_.tail(n_) = Eigen::Map<const Eigen::VectorXd>(q.data() + 1, n_);
}
void FlexibleRotorBody::lift_rates(std::span<const double> w, Eigen::VectorXd& out) const {
  out.head<3>().setZero();
  out.segment<3>(3) = axis_b_ * w[0];
  out.tail(n_) = Eigen::Map<const Eigen::VectorXd>(w.data() + 1, n_);
}

Eigen::VectorXd FlexibleRotorBody::initial_positions() const {
  Eigen::VectorXd q(1 + n_);
  q << 0.0, frame_.initial_positions().tail(n_);
  return q;
}
Eigen::VectorXd FlexibleRotorBody::initial_velocities() const {
  Eigen::VectorXd w(1 + n_);
  w << speed_, frame_.initial_velocities().tail(n_);
  return w;
}

void FlexibleRotorBody::kinematic_residual(std::span<const double>, std::span<const double> qdot,
                                           std::span<const double> w_eff, std::span<const double>,
                                           std::span<double> rows, std::span<double>) const {
  for (int k = 0; k <= n_; ++k) rows[k] = qdot[k] - w_eff[k];
}
Eigen::VectorXd FlexibleRotorBody::position_rates(std::span<const double>, std::span<const double> w) const {
  return Eigen::Map<const Eigen::VectorXd>(w.data(), 1 + n_);
}
void FlexibleRotorBody::kinematic_jacobian(std::span<const double>, std::span<const double>,
                                           Eigen::Ref<Eigen::MatrixXd> d_q,
                                           Eigen::Ref<Eigen::MatrixXd> d_w) const {
  d_q.setZero();
  d_w.setZero();
  d_w.diagonal().setConstant(-1.0);
}

// B^T (M W' + h - Q_g + [0; 0; K eta + D eta']).
void FlexibleRotorBody::inertia_residual(std::span<const double> q, std::span<const double> w,
                                         std::span<const double> wdot, const Vec3& gravity,
                                         std::span<double> rows) const {
  lift(q);
  lift_rates(w, fw_);
  lift_rates(wdot, fwd_);
  frame_.inertia_residual(cs(fq_), cs(fw_), cs(fwd_), gravity, ms(rows_));
  rows[0] = axis_b_.dot(rows_.segment<3>(3));
  Eigen::Map<Eigen::VectorXd>(rows.data() + 1, n_) = rows_.tail(n_);
}

// out = B^T X B of a (6 + n) x (6 + n) matrix X in the floating frame's velocities.
void FlexibleRotorBody::project_velocities(const Eigen::MatrixXd& x, Eigen::Ref<Eigen::MatrixXd> out) const {
  out(0, 0) = axis_b_.dot(x.block<3, 3>(3, 3) * axis_b_);
  out.block(0, 1, 1, n_).noalias() = axis_b_.transpose() * x.block(3, 6, 3, n_);
  out.block(1, 0, n_, 1).noalias() = x.block(6, 3, n_, 3) * axis_b_;
  out.bottomRightCorner(n_, n_) = x.bottomRightCorner(n_, n_);
}

// out = (or += with `add`) B^T X dQ/dq of a (6 + n) x (7 + n) matrix X: rows in the floating frame's
// velocities, columns in its coordinates. No heap allocation (noalias products into the blocks).
void FlexibleRotorBody::project_positions(const Eigen::MatrixXd& x, double theta,
                                          Eigen::Ref<Eigen::MatrixXd> out, bool add) const {
  const Vec4 dp = dp_dtheta(theta);
  const double corner = axis_b_.dot(x.block<3, 4>(3, 3) * dp);
  auto row = out.block(0, 1, 1, n_);
  auto col = out.block(1, 0, n_, 1);
  if (add) {
    out(0, 0) += corner;
    row.noalias() += axis_b_.transpose() * x.block(3, 7, 3, n_);
    col.noalias() += x.block(6, 3, n_, 4) * dp;
    out.bottomRightCorner(n_, n_) += x.bottomRightCorner(n_, n_);
  } else {
    out(0, 0) = corner;
    row.noalias() = axis_b_.transpose() * x.block(3, 7, 3, n_);
    col.noalias() = x.block(6, 3, n_, 4) * dp;
    out.bottomRightCorner(n_, n_) = x.bottomRightCorner(n_, n_);
  }
}

void FlexibleRotorBody::mass_matrix(std::span<const double> q, Eigen::Ref<Eigen::MatrixXd> m) const {
  lift(q);
  frame_.mass_matrix(cs(fq_), fm_);
  project_velocities(fm_, m);
}

MarkerMotion FlexibleRotorBody::marker_motion(int marker, std::span<const double> q,
                                              std::span<const double> w) const {
  lift(q);
  lift_rates(w, fw_);
  return frame_.marker_motion(marker, cs(fq_), cs(fw_));
}
void FlexibleRotorBody::marker_jacobian(int marker, std::span<const double> q, Eigen::Ref<Mat3X> jv,
                                        Eigen::Ref<Mat3X> jw) const {
  lift(q);
  frame_.marker_jacobian(marker, cs(fq_), jv_, jw_);
  jv.col(0) = jv_.block<3, 3>(0, 3) * axis_b_;
  jv.rightCols(n_) = jv_.rightCols(n_);
  jw.col(0) = jw_.block<3, 3>(0, 3) * axis_b_;
  jw.rightCols(n_) = jw_.rightCols(n_);
}
void FlexibleRotorBody::marker_twist(int marker, std::span<const double> q, std::span<const double> w,
                                     Vec3& velocity, Vec3& angular_velocity) const {
  lift(q);
  lift_rates(w, fw_);
  frame_.marker_twist(marker, cs(fq_), cs(fw_), velocity, angular_velocity);
}
Vec3 FlexibleRotorBody::marker_acceleration(int marker, std::span<const double> q, std::span<const double> w,
                                            std::span<const double> wdot) const {
  lift(q);
  lift_rates(w, fw_);
  lift_rates(wdot, fwd_);
  return frame_.marker_acceleration(marker, cs(fq_), cs(fw_), cs(fwd_));
}

Vec3 FlexibleRotorBody::reference_position(std::span<const double>) const {
  return pivot_;
}
Mat3 FlexibleRotorBody::rotation(std::span<const double> q) const {
  return rotation_matrix(euler_parameters(q[0]));
}

double FlexibleRotorBody::kinetic_energy(std::span<const double> q, std::span<const double> w) const {
  lift(q);
  lift_rates(w, fw_);
  return frame_.kinetic_energy(cs(fq_), cs(fw_));
}
double FlexibleRotorBody::potential_energy(std::span<const double> q, const Vec3& gravity) const {
  lift(q);
  return frame_.potential_energy(cs(fq_), gravity);
}
double FlexibleRotorBody::dissipated_power(std::span<const double> q, std::span<const double> w) const {
  lift(q);
  lift_rates(w, fw_);
  return frame_.dissipated_power(cs(fq_), cs(fw_));
}

void FlexibleRotorBody::add_wrench(int marker, std::span<const double> q, const Vec3& force,
                                   const Vec3& torque, std::span<double> generalized) const {
  lift(q);
  gen_.setZero();
  frame_.add_wrench(marker, cs(fq_), force, torque, ms(gen_));
  generalized[0] += axis_b_.dot(gen_.segment<3>(3));
  Eigen::Map<Eigen::VectorXd>(generalized.data() + 1, n_) += gen_.tail(n_);
}

// d[p; theta; v; omega]/dq = (the floating frame's, at fixed W) dQ/dq: W = B w does not depend on q.
void FlexibleRotorBody::marker_sensitivity(int marker, std::span<const double> q, std::span<const double> w,
                                           Eigen::Ref<Eigen::MatrixXd> out) const {
  lift(q);
  lift_rates(w, fw_);
  frame_.marker_sensitivity(marker, cs(fq_), cs(fw_), sens_);
  out.col(0).noalias() = sens_.middleCols<4>(3) * dp_dtheta(q[0]);
  out.rightCols(n_) = sens_.rightCols(n_);
}

void FlexibleRotorBody::add_wrench_derivative(int marker, std::span<const double> q, const Vec3& force,
                                              const Vec3& torque, Eigen::Ref<Eigen::MatrixXd> out) const {
  lift(q);
  fdq_.setZero();
  frame_.add_wrench_derivative(marker, cs(fq_), force, torque, fdq_);
  project_positions(fdq_, q[0], out, true);
}

void FlexibleRotorBody::inertia_jacobian(std::span<const double> q, std::span<const double> w,
                                         std::span<const double> wdot, const Vec3& gravity,
                                         Eigen::Ref<Eigen::MatrixXd> d_q,
                                         Eigen::Ref<Eigen::MatrixXd> d_w) const {
  lift(q);
  lift_rates(w, fw_);
  lift_rates(wdot, fwd_);
  frame_.inertia_jacobian(cs(fq_), cs(fw_), cs(fwd_), gravity, fdq_, fdw_);
  project_positions(fdq_, q[0], d_q, false);
  project_velocities(fdw_, d_w);
}

SupportWrench FlexibleRotorBody::support_wrench(std::span<const double> q, std::span<const double> w,
                                                std::span<const double> wdot, const Vec3& gravity,
                                                const Vec3& force, const Vec3& torque_about_pivot) const {
  lift(q);
  lift_rates(w, fw_);
  lift_rates(wdot, fwd_);
  frame_.inertia_residual(cs(fq_), cs(fw_), cs(fwd_), gravity, ms(rows_));
  const Mat3 a = rotation_matrix(fq_.segment<4>(3));
  return {rows_.head<3>() - force, a * rows_.segment<3>(3) - torque_about_pivot};
}

const FlexibleBody* flexible_part(const Body& body) {
  if (const auto* rotor = dynamic_cast<const FlexibleRotorBody*>(&body)) return &rotor->frame();
  return dynamic_cast<const FlexibleBody*>(&body);
}

std::string fixed_axis_basis_problem(const FlexibleData& data, const std::string& file) {
  if (data.rigid_body_modes > 0)
    return file + " holds " + std::to_string(data.rigid_body_modes) +
           " rigid-body modes (a free component): on a fixed axis the frame is the pivot's, so the "
           "superelement "
           "must be condensed with the pivot clamped ([[fix]] at the pivot, dofs = \"all\"; "
           "docs/scene-flexible.md)";
  for (const FlexibleData::Point& p : data.points) {
    if (p.position.norm() > 1e-6) continue;
    const double moves = std::max(p.translation.cwiseAbs().maxCoeff(), p.rotation.cwiseAbs().maxCoeff());
    if (moves > 1e-9)
      return file + ": its point '" + p.name +
             "' at the frame's origin (the pivot) moves with the elastic coordinates (by up to " +
             std::to_string(moves) + " per unit coordinate): condense the component with that point fixed";
  }
  return {};
}

}  // namespace nvh::solve
