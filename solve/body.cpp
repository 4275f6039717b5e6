// Ground, rigid bodies and point masses (see body.hpp for the coordinates and equations).
#include "solve/body.hpp"

namespace nvh::solve {
namespace {
Eigen::Map<const Vec3> vec3(std::span<const double> s, int at) { return Eigen::Map<const Vec3>(s.data() + at); }
Eigen::Map<const Vec4> vec4(std::span<const double> s, int at) { return Eigen::Map<const Vec4>(s.data() + at); }
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

// ---------------------------------------------------------------- ground
MarkerMotion Ground::marker_motion(int marker, std::span<const double>, std::span<const double>) const {
  const auto& m = markers()[marker];
  return {m.position, m.axes, Vec3::Zero(), Vec3::Zero()};
}
MarkerJacobian Ground::marker_jacobian(int, std::span<const double>) const {
  return {Eigen::Matrix<double, 3, Eigen::Dynamic>(3, 0), Eigen::Matrix<double, 3, Eigen::Dynamic>(3, 0)};
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

Eigen::MatrixXd RigidBody::mass_matrix(std::span<const double>) const {
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(6, 6);
  m.topLeftCorner<3, 3>() = mass_ * Mat3::Identity();
  m.bottomRightCorner<3, 3>() = inertia_;
  return m;
}

MarkerMotion RigidBody::marker_motion(int marker, std::span<const double> q, std::span<const double> w) const {
  const auto& m = markers()[marker];
  const Mat3 a = rotation_matrix(vec4(q, 3));
  const Vec3 s = a * m.position;
  const Vec3 omega = a * vec3(w, 3);
  return {vec3(q, 0) + s, a * m.axes, vec3(w, 0) + omega.cross(s), omega};
}

// v_P = v + A (omega_b x s) = v - A s~ omega_b;  omega_P = A omega_b.
MarkerJacobian RigidBody::marker_jacobian(int marker, std::span<const double> q) const {
  const Mat3 a = rotation_matrix(vec4(q, 3));
  MarkerJacobian j{Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, 6),
                   Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, 6)};
  j.jv.leftCols<3>() = Mat3::Identity();
  j.jv.rightCols<3>() = -a * skew(markers()[marker].position);
  j.jw.rightCols<3>() = a;
  return j;
}

Vec3 RigidBody::reference_position(std::span<const double> q) const { return vec3(q, 0); }
Mat3 RigidBody::rotation(std::span<const double> q) const { return rotation_matrix(vec4(q, 3)); }
double RigidBody::kinetic_energy(std::span<const double>, std::span<const double> w) const {
  const Vec3 omega = vec3(w, 3);
  return 0.5 * mass_ * vec3(w, 0).squaredNorm() + 0.5 * omega.dot(inertia_ * omega);
}

// ---------------------------------------------------------------- point mass
PointMass::PointMass(std::string name, double mass, InitialState init)
    : Body(std::move(name)), mass_(mass), init_(init) {}

Eigen::VectorXd PointMass::initial_positions() const { return init_.position; }
Eigen::VectorXd PointMass::initial_velocities() const { return init_.velocity; }

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
Eigen::MatrixXd PointMass::mass_matrix(std::span<const double>) const {
  return mass_ * Eigen::MatrixXd::Identity(3, 3);
}
MarkerMotion PointMass::marker_motion(int marker, std::span<const double> q, std::span<const double> w) const {
  return {vec3(q, 0), markers()[marker].axes, vec3(w, 0), Vec3::Zero()};
}
MarkerJacobian PointMass::marker_jacobian(int, std::span<const double>) const {
  MarkerJacobian j{Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, 3),
                   Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, 3)};
  j.jv = Mat3::Identity();
  return j;
}
Vec3 PointMass::reference_position(std::span<const double> q) const { return vec3(q, 0); }
double PointMass::kinetic_energy(std::span<const double>, std::span<const double> w) const {
  return 0.5 * mass_ * vec3(w, 0).squaredNorm();
}

}  // namespace nvh::solve
