// Ground, rigid bodies and point masses (see body.hpp for the coordinates and equations).
#include "solve/body.hpp"

#include <algorithm>
#include <cmath>

namespace nvh::solve {
namespace {
Eigen::Map<const Vec3> vec3(std::span<const double> s, int at) {
  return Eigen::Map<const Vec3>(s.data() + at);
}
Eigen::Map<const Vec4> vec4(std::span<const double> s, int at) {
  return Eigen::Map<const Vec4>(s.data() + at);
}
}  // namespace

void frame_kinematic_residual(std::span<const double> q, std::span<const double> qdot,
                              std::span<const double> w_eff, double beta, std::span<double> rows) {
  const Vec4 p = vec4(q, 3);
  Eigen::Map<Vec3>(rows.data()) = vec3(qdot, 0) - vec3(w_eff, 0);
  // The constraint p.p = 1 is an invariant of p' = 1/2 L^T omega; the last term makes it attractive
  // (drift decays at the rate 2 beta) without changing the exact solution.
  Eigen::Map<Vec4>(rows.data() + 3) =
      vec4(qdot, 3) - 0.5 * l_matrix(p).transpose() * vec3(w_eff, 3) + beta * (p.squaredNorm() - 1.0) * p;
}

int Body::find_marker(const std::string& name) const {
  for (std::size_t k = 0; k < markers_.size(); ++k)
    if (markers_[k].name == name) return static_cast<int>(k);
  return -1;
}

// ---------------------------------------------------------------- defaults: local differences
namespace {
/// The increment of a local difference in coordinate x.
double increment(double x) {
  return 1e-7 * std::max(1.0, std::abs(x));
}
/// The small rotation theta with B = exp(theta~) A for nearby rotations A, B (to second order).
Vec3 rotation_between(const Mat3& a, const Mat3& b) {
  const Mat3 r = b * a.transpose();
  return 0.5 * Vec3(r(2, 1) - r(1, 2), r(0, 2) - r(2, 0), r(1, 0) - r(0, 1));
}
}  // namespace

void Body::add_wrench(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                      std::span<double> generalized) const {
  const MarkerJacobian j = marker_jacobian(marker, q);
  Eigen::Map<Eigen::VectorXd>(generalized.data(), j.jv.cols()) +=
      j.jv.transpose() * force + j.jw.transpose() * torque;
}

void Body::marker_twist(int marker, std::span<const double> q, std::span<const double> w, Vec3& velocity,
                        Vec3& angular_velocity) const {
  const MarkerJacobian j = marker_jacobian(marker, q);
  const Eigen::Map<const Eigen::VectorXd> wv(w.data(), j.jv.cols());
  velocity = j.jv * wv;
  angular_velocity = j.jw * wv;
}

Vec3 Body::marker_acceleration(int marker, std::span<const double> q, std::span<const double> w,
                               std::span<const double> wdot) const {
  const int nq = position_count(), nw = velocity_count();
  const Eigen::Map<const Eigen::VectorXd> wv(w.data(), nw), wd(wdot.data(), nw);
  const MarkerJacobian j0 = marker_jacobian(marker, q);
  const Eigen::VectorXd qd = position_rates(q, w);
  const double h = 1e-6;
  const Eigen::VectorXd qp = Eigen::Map<const Eigen::VectorXd>(q.data(), nq) + h * qd;
  const Eigen::VectorXd qm = Eigen::Map<const Eigen::VectorXd>(q.data(), nq) - h * qd;
  const MarkerJacobian jp = marker_jacobian(marker, {qp.data(), std::size_t(nq)});
  const MarkerJacobian jm = marker_jacobian(marker, {qm.data(), std::size_t(nq)});
  return j0.jv * wd + (jp.jv - jm.jv) * wv / (2 * h);
}

void Body::marker_sensitivity(int marker, std::span<const double> q, std::span<const double> w,
                              Eigen::Ref<Eigen::MatrixXd> out) const {
  std::vector<double> qq(q.begin(), q.end());
  for (int k = 0; k < position_count(); ++k) {
    const double h = increment(q[k]);
    qq[k] = q[k] + h;
    const MarkerMotion p = marker_motion(marker, qq, w);
    qq[k] = q[k] - h;
    const MarkerMotion m = marker_motion(marker, qq, w);
    qq[k] = q[k];
    out.block<3, 1>(0, k) = (p.position - m.position) / (2 * h);
    out.block<3, 1>(3, k) = rotation_between(m.axes, p.axes) / (2 * h);
    out.block<3, 1>(6, k) = (p.velocity - m.velocity) / (2 * h);
    out.block<3, 1>(9, k) = (p.angular_velocity - m.angular_velocity) / (2 * h);
  }
}

void Body::add_wrench_derivative(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                                 Eigen::Ref<Eigen::MatrixXd> out) const {
  std::vector<double> qq(q.begin(), q.end());
  Eigen::VectorXd gp(velocity_count()), gm(velocity_count());
  for (int k = 0; k < position_count(); ++k) {
    const double h = increment(q[k]);
    gp.setZero();
    gm.setZero();
    qq[k] = q[k] + h;
    add_wrench(marker, qq, force, torque, {gp.data(), std::size_t(gp.size())});
    qq[k] = q[k] - h;
    add_wrench(marker, qq, force, torque, {gm.data(), std::size_t(gm.size())});
    qq[k] = q[k];
    out.col(k) += (gp - gm) / (2 * h);
  }
}

namespace {
// d(rows)/dq and d(rows)/dw by central differences of eval(q, w, rows) (the defaults of the two below).
template <class Rows>
void differences(std::span<const double> q, std::span<const double> w, int rows, const Rows& eval,
                 Eigen::Ref<Eigen::MatrixXd> d_q, Eigen::Ref<Eigen::MatrixXd> d_w) {
  std::vector<double> qq(q.begin(), q.end()), ww(w.begin(), w.end());
  Eigen::VectorXd rp(rows), rm(rows);
  auto column = [&](std::vector<double>& x, double x0, int k, Eigen::Ref<Eigen::MatrixXd> out) {
    const double h = increment(x0);
    x[k] = x0 + h, eval(qq, ww, rp);
    x[k] = x0 - h, eval(qq, ww, rm);
    x[k] = x0;
    out.col(k) = (rp - rm) / (2 * h);
  };
  for (std::size_t k = 0; k < q.size(); ++k) column(qq, q[k], static_cast<int>(k), d_q);
  for (std::size_t k = 0; k < w.size(); ++k) column(ww, w[k], static_cast<int>(k), d_w);
}
}  // namespace

void Body::kinematic_jacobian(std::span<const double> q, std::span<const double> w_eff,
                              Eigen::Ref<Eigen::MatrixXd> d_q, Eigen::Ref<Eigen::MatrixXd> d_w) const {
  const int nq = position_count();
  const std::vector<double> zero(nq, 0.0);
  differences(
      q, w_eff, nq,
      [&](const std::vector<double>& qq, const std::vector<double>& ww, Eigen::VectorXd& r) {
        kinematic_residual(qq, zero, ww, {}, {r.data(), std::size_t(nq)}, {});
      },
      d_q, d_w);
}

void Body::inertia_jacobian(std::span<const double> q, std::span<const double> w,
                            std::span<const double> wdot, const Vec3& gravity,
                            Eigen::Ref<Eigen::MatrixXd> d_q, Eigen::Ref<Eigen::MatrixXd> d_w) const {
  const int nw = velocity_count();
  differences(
      q, w, nw,
      [&](const std::vector<double>& qq, const std::vector<double>& ww, Eigen::VectorXd& r) {
        inertia_residual(qq, ww, wdot, gravity, {r.data(), std::size_t(nw)});
      },
      d_q, d_w);
}

// ---------------------------------------------------------------- ground
MarkerMotion Ground::marker_motion(int marker, std::span<const double>, std::span<const double>) const {
  const auto& m = markers()[marker];
  return {m.position, m.axes, Vec3::Zero(), Vec3::Zero()};
}

// ---------------------------------------------------------------- rigid body
RigidBody::RigidBody(std::string name, double mass, const Mat3& inertia_cm, InitialState init)
    : Body(std::move(name)), mass_(mass), inertia_(inertia_cm), init_(init) {}

Eigen::VectorXd RigidBody::initial_positions() const {
  Eigen::VectorXd q(7);
  q << init_.position, euler_parameters(init_.orientation);
  return q;
}
Eigen::VectorXd RigidBody::initial_velocities() const {
  Eigen::VectorXd w(6);
  w << init_.velocity, init_.orientation.transpose() * init_.angular_velocity;  // omega in body axes
  return w;
}

void RigidBody::kinematic_residual(std::span<const double> q, std::span<const double> qdot,
                                   std::span<const double> w_eff, std::span<const double>,
                                   std::span<double> rows, std::span<double>) const {
  frame_kinematic_residual(q, qdot, w_eff, kNormalizationRate, rows);
}

Eigen::VectorXd RigidBody::position_rates(std::span<const double> q, std::span<const double> w) const {
  Eigen::VectorXd qd(7);
  qd << vec3(w, 0), 0.5 * l_matrix(vec4(q, 3)).transpose() * vec3(w, 3);
  return qd;
}

// Newton-Euler equations about the centre of mass in body axes:
//   m v' = F + m g,   J omega' + omega x J omega = T   (Shabana, Dynamics of Multibody Systems, eq. 7.133)
void RigidBody::inertia_residual(std::span<const double>, std::span<const double> w,
                                 std::span<const double> wdot, const Vec3& gravity,
                                 std::span<double> rows) const {
  const Vec3 omega = vec3(w, 3);
  Eigen::Map<Vec3>(rows.data()) = mass_ * (vec3(wdot, 0) - gravity);
  Eigen::Map<Vec3>(rows.data() + 3) = inertia_ * vec3(wdot, 3) + omega.cross(inertia_ * omega);
}

void RigidBody::mass_matrix(std::span<const double>, Eigen::Ref<Eigen::MatrixXd> m) const {
  m.setZero();
  m.topLeftCorner<3, 3>() = mass_ * Mat3::Identity();
  m.bottomRightCorner<3, 3>() = inertia_;
}

MarkerMotion RigidBody::marker_motion(int marker, std::span<const double> q,
                                      std::span<const double> w) const {
  const auto& m = markers()[marker];
  const Mat3 a = rotation_matrix(vec4(q, 3));
  const Vec3 s = a * m.position;
  const Vec3 omega = a * vec3(w, 3);
  return {vec3(q, 0) + s, a * m.axes, vec3(w, 0) + omega.cross(s), omega};
}

// a_P = v' + A (omega_b' x s + omega_b x (omega_b x s)): v' global, omega_b and its rate in body axes.
Vec3 RigidBody::marker_acceleration(int marker, std::span<const double> q, std::span<const double> w,
                                    std::span<const double> wdot) const {
  const Vec3& s = markers()[marker].position;
  const Vec3 omega = vec3(w, 3);
  return vec3(wdot, 0) + rotation_matrix(vec4(q, 3)) * (vec3(wdot, 3).cross(s) + omega.cross(omega.cross(s)));
}

// v_P = v + A (omega_b x s) = v - A s~ omega_b;  omega_P = A omega_b.
void RigidBody::marker_jacobian(int marker, std::span<const double> q, Eigen::Ref<Mat3X> jv,
                                Eigen::Ref<Mat3X> jw) const {
  const Mat3 a = rotation_matrix(vec4(q, 3));
  jv.leftCols<3>() = Mat3::Identity();
  jv.rightCols<3>() = -a * skew(markers()[marker].position);
  jw.leftCols<3>().setZero();
  jw.rightCols<3>() = a;
}

// Derivatives (Theta = d theta / dp, rotation.hpp): with s = A s0 the marker offset, every rotating vector
// x = A x0 changes by dtheta x x = -x~ dtheta, so
//   dp_m/dp = -s~ Theta,  dv_m/dp = -(A (omega x s0))~ Theta,  domega_m/dp = -(A omega)~ Theta.
void RigidBody::marker_sensitivity(int marker, std::span<const double> q, std::span<const double> w,
                                   Eigen::Ref<Eigen::MatrixXd> out) const {
  const Vec4 p = vec4(q, 3);
  const Mat3 a = rotation_matrix(p);
  const Mat34 theta = rotation_sensitivity(p);
  const Vec3 s0 = markers()[marker].position, omega = vec3(w, 3);
  out.setZero();
  out.block<3, 3>(0, 0) = Mat3::Identity();
  out.block<3, 4>(0, 3) = -skew(a * s0) * theta;
  out.block<3, 4>(3, 3) = theta;
  out.block<3, 4>(6, 3) = -skew(a * omega.cross(s0)) * theta;
  out.block<3, 4>(9, 3) = -skew(a * omega) * theta;
}

// Jv w = v - A s0~ omega = v + A (omega x s0),  Jw w = A omega.
void RigidBody::marker_twist(int marker, std::span<const double> q, std::span<const double> w, Vec3& velocity,
                             Vec3& angular_velocity) const {
  const Mat3 a = rotation_matrix(vec4(q, 3));
  const Vec3 omega = vec3(w, 3);
  velocity = vec3(w, 0) + a * omega.cross(markers()[marker].position);
  angular_velocity = a * omega;
}
void PointMass::marker_twist(int, std::span<const double>, std::span<const double> w, Vec3& velocity,
                             Vec3& angular_velocity) const {
  velocity = vec3(w, 0);
  angular_velocity.setZero();
}

// Q = [F; s0~ A^T F + A^T T]; d(A^T x)/dp = A^T x~ Theta.
void RigidBody::add_wrench(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                           std::span<double> generalized) const {
  const Mat3 a = rotation_matrix(vec4(q, 3));
  const Vec3 s0 = markers()[marker].position;
  Eigen::Map<Vec3>(generalized.data()) += force;
  Eigen::Map<Vec3>(generalized.data() + 3) += s0.cross(a.transpose() * force) + a.transpose() * torque;
}
void RigidBody::add_wrench_derivative(int marker, std::span<const double> q, const Vec3& force,
                                      const Vec3& torque, Eigen::Ref<Eigen::MatrixXd> out) const {
  const Vec4 p = vec4(q, 3);
  const Mat3 at = rotation_matrix(p).transpose();
  const Mat34 theta = rotation_sensitivity(p);
  out.block<3, 4>(3, 3) += (skew(markers()[marker].position) * at * skew(force) + at * skew(torque)) * theta;
}

std::string frame_position_meaning(int r) {
  static const char* const kNames[7] = {"position x",         "position y",         "position z",
                                        "Euler parameter p0", "Euler parameter p1", "Euler parameter p2",
                                        "Euler parameter p3"};
  return r >= 0 && r < 7 ? kNames[r] : std::string();
}

std::string frame_velocity_meaning(int r) {
  static const char* const kNames[6] = {"velocity x",
                                        "velocity y",
                                        "velocity z",
                                        "angular velocity x (body axes)",
                                        "angular velocity y (body axes)",
                                        "angular velocity z (body axes)"};
  return r >= 0 && r < 6 ? kNames[r] : std::string();
}

std::string RigidBody::state_meaning(int r) const {
  return r < 7 ? frame_position_meaning(r) : frame_velocity_meaning(r - 7);
}

std::string PointMass::state_meaning(int r) const {
  static const char* const kNames[6] = {"position x", "position y", "position z",
                                        "velocity x", "velocity y", "velocity z"};
  return r >= 0 && r < 6 ? kNames[r] : std::string();
}

// Rows r' - v, p' - 1/2 L(p)^T omega + beta (p.p - 1) p  (L(p)^T omega = B(omega) p, rotation.hpp) of a
// floating frame (rigid and flexible bodies): written into the first 7 rows, the rest zeroed.
void floating_frame_kinematic_jacobian(const Vec4& p, const Vec3& omega, double beta,
                                       Eigen::Ref<Eigen::MatrixXd> d_q, Eigen::Ref<Eigen::MatrixXd> d_w) {
  d_q.setZero();
  d_w.setZero();
  d_q.block<4, 4>(3, 3) =
      -0.5 * rate_matrix(omega) +
      beta * ((p.squaredNorm() - 1.0) * Eigen::Matrix4d::Identity() + 2.0 * p * p.transpose());
  d_w.block<3, 3>(0, 0) = -Mat3::Identity();
  d_w.block<4, 3>(3, 3) = -0.5 * l_matrix(p).transpose();
}

void RigidBody::kinematic_jacobian(std::span<const double> q, std::span<const double> w_eff,
                                   Eigen::Ref<Eigen::MatrixXd> d_q, Eigen::Ref<Eigen::MatrixXd> d_w) const {
  floating_frame_kinematic_jacobian(vec4(q, 3), vec3(w_eff, 3), kNormalizationRate, d_q, d_w);
}

// Rows m (v' - g), J omega' + omega x J omega.
void RigidBody::inertia_jacobian(std::span<const double>, std::span<const double> w, std::span<const double>,
                                 const Vec3&, Eigen::Ref<Eigen::MatrixXd> d_q,
                                 Eigen::Ref<Eigen::MatrixXd> d_w) const {
  const Vec3 omega = vec3(w, 3);
  d_q.setZero();
  d_w.setZero();
  d_w.block<3, 3>(3, 3) = skew(omega) * inertia_ - skew(inertia_ * omega);
}

double RigidBody::potential_energy(std::span<const double> q, const Vec3& gravity) const {
  return -mass_ * gravity.dot(vec3(q, 0));
}

Vec3 RigidBody::reference_position(std::span<const double> q) const {
  return vec3(q, 0);
}
Mat3 RigidBody::rotation(std::span<const double> q) const {
  return rotation_matrix(vec4(q, 3));
}
double RigidBody::kinetic_energy(std::span<const double>, std::span<const double> w) const {
  const Vec3 omega = vec3(w, 3);
  return 0.5 * mass_ * vec3(w, 0).squaredNorm() + 0.5 * omega.dot(inertia_ * omega);
}

// ---------------------------------------------------------------- point mass
PointMass::PointMass(std::string name, double mass, InitialState init)
    : Body(std::move(name)), mass_(mass), init_(init) {}

Eigen::VectorXd PointMass::initial_positions() const {
  return init_.position;
}
Eigen::VectorXd PointMass::initial_velocities() const {
  return init_.velocity;
}

void PointMass::kinematic_residual(std::span<const double>, std::span<const double> qdot,
                                   std::span<const double> w_eff, std::span<const double>,
                                   std::span<double> rows, std::span<double>) const {
  Eigen::Map<Vec3>(rows.data()) = vec3(qdot, 0) - vec3(w_eff, 0);
}
Eigen::VectorXd PointMass::position_rates(std::span<const double>, std::span<const double> w) const {
  return vec3(w, 0);
}
void PointMass::inertia_residual(std::span<const double>, std::span<const double>,
                                 std::span<const double> wdot, const Vec3& gravity,
                                 std::span<double> rows) const {
  Eigen::Map<Vec3>(rows.data()) = mass_ * (vec3(wdot, 0) - gravity);
}
void PointMass::mass_matrix(std::span<const double>, Eigen::Ref<Eigen::MatrixXd> m) const {
  m = mass_ * Mat3::Identity();
}
MarkerMotion PointMass::marker_motion(int marker, std::span<const double> q,
                                      std::span<const double> w) const {
  return {vec3(q, 0), markers()[marker].axes, vec3(w, 0), Vec3::Zero()};
}
void PointMass::marker_jacobian(int, std::span<const double>, Eigen::Ref<Mat3X> jv,
                                Eigen::Ref<Mat3X> jw) const {
  jv = Mat3::Identity();
  jw.setZero();
}
void PointMass::add_wrench(int, std::span<const double>, const Vec3& force, const Vec3&,
                           std::span<double> generalized) const {
  Eigen::Map<Vec3>(generalized.data()) += force;
}
void PointMass::marker_sensitivity(int, std::span<const double>, std::span<const double>,
                                   Eigen::Ref<Eigen::MatrixXd> out) const {
  out.setZero();
  out.block<3, 3>(0, 0) = Mat3::Identity();
}
void PointMass::add_wrench_derivative(int, std::span<const double>, const Vec3&, const Vec3&,
                                      Eigen::Ref<Eigen::MatrixXd>) const {}
void PointMass::kinematic_jacobian(std::span<const double>, std::span<const double>,
                                   Eigen::Ref<Eigen::MatrixXd> d_q, Eigen::Ref<Eigen::MatrixXd> d_w) const {
  d_q.setZero();
  d_w = -Eigen::MatrixXd::Identity(3, 3);
}
void PointMass::inertia_jacobian(std::span<const double>, std::span<const double>, std::span<const double>,
                                 const Vec3&, Eigen::Ref<Eigen::MatrixXd> d_q,
                                 Eigen::Ref<Eigen::MatrixXd> d_w) const {
  d_q.setZero();
  d_w.setZero();
}
double PointMass::potential_energy(std::span<const double> q, const Vec3& gravity) const {
  return -mass_ * gravity.dot(vec3(q, 0));
}

Vec3 PointMass::reference_position(std::span<const double> q) const {
  return vec3(q, 0);
}
double PointMass::kinetic_energy(std::span<const double>, std::span<const double> w) const {
  return 0.5 * mass_ * vec3(w, 0).squaredNorm();
}

}  // namespace nvh::solve
