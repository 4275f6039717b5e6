#pragma once
// Rotations by Euler parameters (unit quaternions p = [e0, e1, e2, e3]).
//
// References: A. A. Shabana, Dynamics of Multibody Systems, 4th ed., Cambridge 2020, section 7.4;
// P. E. Nikravesh, Computer-Aided Analysis of Mechanical Systems, Prentice Hall 1988, chapter 6.
//   A(p) = (2 e0^2 - 1) I + 2 (e e^T + e0 e~)          rotation matrix, body -> global   (Nikravesh 6.19)
//   G(p) = [-e,  e~ + e0 I],  L(p) = [-e, -e~ + e0 I]   (3 x 4)                           (Nikravesh 6.37)
//   omega_global = 2 G p',  omega_body = 2 L p',  p' = 1/2 L^T omega_body  when p^T p = 1
#include <Eigen/Dense>

namespace nvh::solve {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec4 = Eigen::Vector4d;
using Mat34 = Eigen::Matrix<double, 3, 4>;
using Mat3X = Eigen::Matrix<double, 3, Eigen::Dynamic>;  // 3 x (a body's velocity count)

/// The cross-product matrix: skew(a) b = a x b.
inline Mat3 skew(const Vec3& a) {
  Mat3 s;
  s << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return s;
}

/// Rotation matrix (body -> global) of Euler parameters p, used as given (the kinematic equation keeps
/// |p| = 1 to round-off). Not normalized on purpose: with A(p / |p|) the position constraints no longer see
/// |p|, and IDA's error test on a spinning body stalled at order 1 (a conical pendulum: 6010 steps against
/// 99); the analytic Jacobian is exact in the directions tangent to |p| = 1 (rotation_sensitivity).
inline Mat3 rotation_matrix(const Vec4& p) {
  const double e0 = p[0];
  const Vec3 e = p.tail<3>();
  return (2 * e0 * e0 - 1) * Mat3::Identity() + 2 * (e * e.transpose() + e0 * skew(e));
}

/// L(p): omega_body = 2 L p'.
inline Mat34 l_matrix(const Vec4& p) {
  Mat34 l;
  l.col(0) = -p.tail<3>();
  l.rightCols<3>() = -skew(p.tail<3>()) + p[0] * Mat3::Identity();
  return l;
}

/// d(theta)/dp: the small global rotation of A(p) per change of p (3 x 4): dA = (Theta dp)~ A with
/// Theta = 2 A(p^) L(p^) / |p| = 2 G(p^) / |p| (omega = 2 G p' for unit p; Nikravesh 6.37), p^ = p / |p|;
/// exact for changes of p tangent to |p| = 1 (the radial change scales A and is no rotation).
inline Mat34 rotation_sensitivity(const Vec4& p_raw) {
  const double n = p_raw.norm();
  const Vec4 p = p_raw / n;
  return 2.0 / n * rotation_matrix(p) * l_matrix(p);
}

/// B(omega) with L(p)^T omega = B(omega) p (4 x 4): the derivative of the Euler parameter rates by p.
inline Eigen::Matrix4d rate_matrix(const Vec3& w) {
  Eigen::Matrix4d b;
  b(0, 0) = 0;
  b.block<1, 3>(0, 1) = -w.transpose();
  b.block<3, 1>(1, 0) = w;
  b.block<3, 3>(1, 1) = -skew(w);
  return b;
}

/// Euler parameters of a rotation matrix (Shepperd's method via Eigen), e0 >= 0.
inline Vec4 euler_parameters(const Mat3& a) {
  Eigen::Quaterniond q(a);
  q.normalize();
  Vec4 p(q.w(), q.x(), q.y(), q.z());
  if (p[0] < 0) p = -p;
  return p;
}

/// The rotation nearest a body's axes in the Gram-Schmidt sense (x kept in direction, y made perpendicular to
/// it, z = x cross y). A rigid body's axes come from Euler parameters whose norm drifts by round-off (held
/// near 1 by a stabilizing term, body.hpp), so A(p) is not exactly a rotation; an equation that measures a
/// length in those axes (a cam's pitch curve at the lobe's radius) follows the drift unless it uses these.
/// Only for such a constraint: a force element stays in the raw axes its markers' positions use (tried on
/// roller-cam: 3-4 % fewer steps, but the forces of three closed-form tests lost an order of accuracy, 1e-3
/// where they had 1e-4).
inline Mat3 orthonormalized(const Mat3& axes) {
  Mat3 a = axes;
  a.col(0).normalize();
  a.col(1) = (a.col(1) - a.col(1).dot(a.col(0)) * a.col(0)).normalized();
  a.col(2) = a.col(0).cross(a.col(1));
  return a;
}

/// An orthonormal frame (columns x, y, z) with the given z axis and x as close as possible to `x_hint`.
inline Mat3 frame_from_z(const Vec3& z_axis, const Vec3& x_hint) {
  const Vec3 z = z_axis.normalized();
  Vec3 x = x_hint - x_hint.dot(z) * z;
  if (x.norm() < 1e-9) {  // hint parallel to z: take any perpendicular
    x = std::abs(z.x()) < 0.9 ? Vec3::UnitX() - z.x() * z : Vec3::UnitY() - z.y() * z;
  }
  x.normalize();
  Mat3 f;
  f.col(0) = x;
  f.col(1) = z.cross(x);
  f.col(2) = z;
  return f;
}

}  // namespace nvh::solve
