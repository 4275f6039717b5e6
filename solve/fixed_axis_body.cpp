// The slider and the rotor: rigid bodies of one coordinate on a fixed axis (see fixed_axis_body.hpp for the
// coordinates and equations).
#include "solve/fixed_axis_body.hpp"

namespace nvh::solve {

// ---------------------------------------------------------------- both: the kinematic row q' - w = 0
void FixedAxisBody::kinematic_residual(std::span<const double>, std::span<const double> qdot,
                                       std::span<const double> w_eff, std::span<const double>,
                                       std::span<double> rows, std::span<double>) const {
  rows[0] = qdot[0] - w_eff[0];
}
Eigen::VectorXd FixedAxisBody::position_rates(std::span<const double>, std::span<const double> w) const {
  return Eigen::VectorXd::Constant(1, w[0]);
}
void FixedAxisBody::kinematic_jacobian(std::span<const double>, std::span<const double>,
                                       Eigen::Ref<Eigen::MatrixXd> d_q,
                                       Eigen::Ref<Eigen::MatrixXd> d_w) const {
  d_q(0, 0) = 0;
  d_w(0, 0) = -1;
}

// ---------------------------------------------------------------- slider
Eigen::VectorXd SliderBody::initial_velocities() const {
  return Eigen::VectorXd::Constant(1, axis_.dot(init_.velocity));
}

// m s'' = a . F + m a . g
void SliderBody::inertia_residual(std::span<const double>, std::span<const double>,
                                  std::span<const double> wdot, const Vec3& gravity,
                                  std::span<double> rows) const {
  rows[0] = mass_ * (wdot[0] - axis_.dot(gravity));
}
void SliderBody::mass_matrix(std::span<const double>, Eigen::Ref<Eigen::MatrixXd> m) const {
  m(0, 0) = mass_;
}

MarkerMotion SliderBody::marker_motion(int marker, std::span<const double> q,
                                       std::span<const double> w) const {
  const auto& m = markers()[marker];
  return {init_.position + q[0] * axis_ + init_.orientation * m.position, init_.orientation * m.axes,
          w[0] * axis_, Vec3::Zero()};
}
void SliderBody::marker_jacobian(int, std::span<const double>, Eigen::Ref<Mat3X> jv,
                                 Eigen::Ref<Mat3X> jw) const {
  jv.col(0) = axis_;
  jw.col(0).setZero();
}
void SliderBody::marker_twist(int, std::span<const double>, std::span<const double> w, Vec3& velocity,
                              Vec3& angular_velocity) const {
  velocity = w[0] * axis_;
  angular_velocity.setZero();
}

// s'' a: every point of the slider moves along the axis.
Vec3 SliderBody::marker_acceleration(int, std::span<const double>, std::span<const double>,
                                     std::span<const double> wdot) const {
  return wdot[0] * axis_;
}

Vec3 SliderBody::reference_position(std::span<const double> q) const {
  return init_.position + q[0] * axis_;
}
Vec3 SliderBody::reference_velocity(std::span<const double>, std::span<const double> w) const {
  return w[0] * axis_;
}
double SliderBody::kinetic_energy(std::span<const double>, std::span<const double> w) const {
  return 0.5 * mass_ * w[0] * w[0];
}
double SliderBody::potential_energy(std::span<const double> q, const Vec3& gravity) const {
  return -mass_ * gravity.dot(reference_position(q));
}

// Q = a . F (a torque does no work on a translation)
void SliderBody::add_wrench(int, std::span<const double>, const Vec3& force, const Vec3&,
                            std::span<double> generalized) const {
  generalized[0] += axis_.dot(force);
}
void SliderBody::marker_sensitivity(int, std::span<const double>, std::span<const double>,
                                    Eigen::Ref<Eigen::MatrixXd> out) const {
  out.setZero();
  out.block<3, 1>(0, 0) = axis_;
}
void SliderBody::add_wrench_derivative(int, std::span<const double>, const Vec3&, const Vec3&,
                                       Eigen::Ref<Eigen::MatrixXd>) const {}  // Jv, Jw constant
void SliderBody::inertia_jacobian(std::span<const double>, std::span<const double>, std::span<const double>,
                                  const Vec3&, Eigen::Ref<Eigen::MatrixXd> d_q,
                                  Eigen::Ref<Eigen::MatrixXd> d_w) const {
  d_q(0, 0) = 0;
  d_w(0, 0) = 0;
}

// m a s'' = F + m g + F_s;  0 = T + T_s (no rotation, about the centre of mass)
SupportWrench SliderBody::support_wrench(std::span<const double>, std::span<const double>,
                                         std::span<const double> wdot, const Vec3& gravity, const Vec3& force,
                                         const Vec3& torque_about_cm) const {
  return {mass_ * (wdot[0] * axis_ - gravity) - force, -torque_about_cm};
}

// ---------------------------------------------------------------- rotor
RotorBody::RotorBody(std::string name, double mass, const Mat3& inertia_cm, const Vec3& axis,
                     const Vec3& pivot, InitialState init)
    : FixedAxisBody(std::move(name), mass, inertia_cm, axis, pivot, init) {
  const Vec3 d = offset0(-1);
  axial_inertia_ = axis_.dot(init_.orientation * inertia_ * init_.orientation.transpose() * axis_) +
                   mass_ * axis_.cross(d).squaredNorm();  // parallel axes (Steiner)
}

Mat3 RotorBody::turn(double theta) const {
  return Eigen::AngleAxisd(theta, axis_).toRotationMatrix();
}
Vec3 RotorBody::offset0(int marker) const {
  const Vec3 cm = init_.position - support_;
  return marker < 0 ? cm : Vec3(cm + init_.orientation * markers()[marker].position);
}

Eigen::VectorXd RotorBody::initial_velocities() const {
  return Eigen::VectorXd::Constant(1, axis_.dot(init_.angular_velocity));
}

// J theta'' = (a x d) . m g, d = R d0 the centre of mass from the pivot
void RotorBody::inertia_residual(std::span<const double> q, std::span<const double>,
                                 std::span<const double> wdot, const Vec3& gravity,
                                 std::span<double> rows) const {
  const Vec3 d = turn(q[0]) * offset0(-1);
  rows[0] = axial_inertia_ * wdot[0] - mass_ * axis_.cross(d).dot(gravity);
}
void RotorBody::mass_matrix(std::span<const double>, Eigen::Ref<Eigen::MatrixXd> m) const {
  m(0, 0) = axial_inertia_;
}

MarkerMotion RotorBody::marker_motion(int marker, std::span<const double> q,
                                      std::span<const double> w) const {
  const Mat3 r = turn(q[0]);
  const Vec3 d = r * offset0(marker);
  const Vec3 omega = w[0] * axis_;
  return {support_ + d, r * init_.orientation * markers()[marker].axes, omega.cross(d), omega};
}
void RotorBody::marker_jacobian(int marker, std::span<const double> q, Eigen::Ref<Mat3X> jv,
                                Eigen::Ref<Mat3X> jw) const {
  jv.col(0) = axis_.cross(turn(q[0]) * offset0(marker));
  jw.col(0) = axis_;
}
void RotorBody::marker_twist(int marker, std::span<const double> q, std::span<const double> w, Vec3& velocity,
                             Vec3& angular_velocity) const {
  angular_velocity = w[0] * axis_;
  velocity = angular_velocity.cross(turn(q[0]) * offset0(marker));
}

// theta'' a x d + theta'^2 a x (a x d): tangential and centripetal, d = R(theta) d0 from the axis.
Vec3 RotorBody::marker_acceleration(int marker, std::span<const double> q, std::span<const double> w,
                                    std::span<const double> wdot) const {
  const Vec3 ad = axis_.cross(turn(q[0]) * offset0(marker));
  return wdot[0] * ad + w[0] * w[0] * axis_.cross(ad);
}

Vec3 RotorBody::reference_position(std::span<const double> q) const {
  return support_ + turn(q[0]) * offset0(-1);
}
Vec3 RotorBody::reference_velocity(std::span<const double> q, std::span<const double> w) const {
  return w[0] * axis_.cross(turn(q[0]) * offset0(-1));
}
Mat3 RotorBody::rotation(std::span<const double> q) const {
  return turn(q[0]) * init_.orientation;
}
double RotorBody::kinetic_energy(std::span<const double>, std::span<const double> w) const {
  return 0.5 * axial_inertia_ * w[0] * w[0];
}
double RotorBody::potential_energy(std::span<const double> q, const Vec3& gravity) const {
  return -mass_ * gravity.dot(reference_position(q));
}

// Q = (a x d) . F + a . T
void RotorBody::add_wrench(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                           std::span<double> generalized) const {
  generalized[0] += axis_.cross(turn(q[0]) * offset0(marker)).dot(force) + axis_.dot(torque);
}
// d(R d0)/dtheta = a x (R d0): the marker's position, velocity and the lever arm of the force turn with it.
void RotorBody::marker_sensitivity(int marker, std::span<const double> q, std::span<const double> w,
                                   Eigen::Ref<Eigen::MatrixXd> out) const {
  const Vec3 d = turn(q[0]) * offset0(marker);
  const Vec3 ad = axis_.cross(d);
  out.setZero();
  out.block<3, 1>(0, 0) = ad;
  out.block<3, 1>(3, 0) = axis_;
  out.block<3, 1>(6, 0) = w[0] * axis_.cross(ad);
}
void RotorBody::add_wrench_derivative(int marker, std::span<const double> q, const Vec3& force, const Vec3&,
                                      Eigen::Ref<Eigen::MatrixXd> out) const {
  out(0, 0) += axis_.cross(axis_.cross(turn(q[0]) * offset0(marker))).dot(force);
}
void RotorBody::inertia_jacobian(std::span<const double> q, std::span<const double>, std::span<const double>,
                                 const Vec3& gravity, Eigen::Ref<Eigen::MatrixXd> d_q,
                                 Eigen::Ref<Eigen::MatrixXd> d_w) const {
  const Vec3 d = turn(q[0]) * offset0(-1);
  d_q(0, 0) = -mass_ * axis_.cross(axis_.cross(d)).dot(gravity);
  d_w(0, 0) = 0;
}

// Newton-Euler with the support wrench as the unknown: m a_cm = F + m g + F_s, with a_cm = alpha x d + omega
// x (omega x d); J_g alpha + omega x J_g omega = T + T_s about the centre of mass (J_g = A J A^T); T_s moved
// to the pivot: T_s + d x F_s.
SupportWrench RotorBody::support_wrench(std::span<const double> q, std::span<const double> w,
                                        std::span<const double> wdot, const Vec3& gravity, const Vec3& force,
                                        const Vec3& torque_about_cm) const {
  const Mat3 a = rotation(q);
  const Vec3 d = turn(q[0]) * offset0(-1);
  const Vec3 omega = w[0] * axis_, alpha = wdot[0] * axis_;
  const Mat3 jg = a * inertia_ * a.transpose();
  SupportWrench s;
  s.force = mass_ * (alpha.cross(d) + omega.cross(omega.cross(d)) - gravity) - force;
  s.torque = jg * alpha + omega.cross(jg * omega) - torque_about_cm + d.cross(s.force);
  return s;
}

}  // namespace nvh::solve
