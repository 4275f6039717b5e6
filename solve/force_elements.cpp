// Force elements (see force_elements.hpp for the laws and references).
#include "solve/force_elements.hpp"

#include <cmath>
#include <numbers>

#include "solve/constraint.hpp"

namespace nvh::solve {

// ---------------------------------------------------------------- spring-damper
namespace {
struct LineState {
  Vec3 e;            // unit vector from j to i
  double length;     // m
  double rate;       // m/s
};
LineState line(const MarkerMotion& i, const MarkerMotion& j) {
  const Vec3 d = i.position - j.position;
  const double l = d.norm();
  const Vec3 e = l > 1e-12 ? Vec3(d / l) : Vec3::UnitZ();
  return {e, l, e.dot(i.velocity - j.velocity)};
}
}  // namespace

ElementForce SpringDamper::evaluate(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j) const {
  const LineState s = line(i, j);
  const double dx = s.length - p_.free_length;
  const double ratio2 = (dx / p_.xb) * (dx / p_.xb);
  const double k = p_.k0 + p_.kb * ratio2;
  const double d = p_.d0 + p_.db * ratio2;
  const double tension = k * dx + d * s.rate + p_.preload;
  return {-tension * s.e, Vec3::Zero(), i.position};
}

void SpringDamper::channels(const ForceContext& c, const MarkerMotion& i, const MarkerMotion& j,
                            std::span<double> out) const {
  const LineState s = line(i, j);
  out[0] = s.length - p_.free_length;
  out[1] = s.rate;
  out[2] = -evaluate(c, i, j).force.dot(s.e);
}

// ---------------------------------------------------------------- bushing
ElementForce Bushing::evaluate(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j) const {
  const Mat3& aj = j.axes;
  Eigen::Matrix<double, 6, 1> u, ud;
  u.head<3>() = aj.transpose() * (i.position - j.position);
  const Eigen::AngleAxisd rel(aj.transpose() * i.axes);  // rotation of i relative to j, in j's axes
  u.tail<3>() = rel.angle() * rel.axis();
  // velocity of i's origin relative to the frame j, in j's axes
  const Vec3 d = i.position - j.position;
  ud.head<3>() = aj.transpose() * (i.velocity - j.velocity - j.angular_velocity.cross(d));
  ud.tail<3>() = aj.transpose() * (i.angular_velocity - j.angular_velocity);
  const Eigen::Matrix<double, 6, 1> f = -(k_ * u + d_ * ud);
  return {aj * f.head<3>(), aj * f.tail<3>(), i.position};
}

// ---------------------------------------------------------------- torsional spring-damper
ElementForce TorsionalSpringDamper::evaluate(const ForceContext&, const MarkerMotion& i,
                                             const MarkerMotion& j) const {
  const Vec3 z = j.axes.col(2);
  double phi = relative_angle(i, j) - phi0_;
  phi = std::remainder(phi, 2 * std::numbers::pi);
  const double rate = z.dot(i.angular_velocity - j.angular_velocity);
  return {Vec3::Zero(), -(k_ * phi + d_ * rate) * z, i.position};
}
void TorsionalSpringDamper::channels(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j,
                                     std::span<double> out) const {
  out[0] = std::remainder(relative_angle(i, j) - phi0_, 2 * std::numbers::pi);
}

// ---------------------------------------------------------------- contact
namespace {
struct ContactState {
  double delta, delta_rate;
  Vec3 n, vt;
};
ContactState contact_state(const MarkerMotion& i, const MarkerMotion& j, double clearance) {
  const Vec3 n = j.axes.col(2);
  const Vec3 d = i.position - j.position;
  // velocity of i's point relative to the material point of j beneath it
  const Vec3 vrel = i.velocity - j.velocity - j.angular_velocity.cross(d);
  const double vn = n.dot(vrel);
  return {-(clearance + n.dot(d)), -vn, n, vrel - vn * n};
}
}  // namespace

ElementForce Contact::evaluate(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j) const {
  const ContactState s = contact_state(i, j, p_.clearance);
  if (s.delta <= 0) return {Vec3::Zero(), Vec3::Zero(), i.position};
  const double fn = std::max(0.0, p_.stiffness * std::pow(s.delta, p_.exponent) * (1.0 + alpha() * s.delta_rate));
  Vec3 f = fn * s.n;
  const double vt = s.vt.norm();
  if (p_.mu_static > 0 || p_.mu_dynamic > 0) {
    const double x = vt / p_.stribeck_speed;
    const double mu = (p_.mu_dynamic + (p_.mu_static - p_.mu_dynamic) * std::exp(-x * x)) *
                      std::tanh(vt / p_.regularization_speed);
    if (vt > 0) f -= mu * fn * s.vt / vt;
  }
  return {f, Vec3::Zero(), i.position};
}
void Contact::channels(const ForceContext& c, const MarkerMotion& i, const MarkerMotion& j,
                       std::span<double> out) const {
  const ContactState s = contact_state(i, j, p_.clearance);
  out[0] = -s.delta;
  out[1] = evaluate(c, i, j).force.dot(s.n);
  out[2] = s.vt.norm();
}

// ---------------------------------------------------------------- table force, motor, loads
ElementForce TableForce::evaluate(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j) const {
  const Vec3 z = j.axes.col(2);
  return {table_(z.dot(i.position - j.position)) * z, Vec3::Zero(), i.position};
}

namespace {
double relative_rpm(const MarkerMotion& i, const MarkerMotion& j) {
  return j.axes.col(2).dot(i.angular_velocity - j.angular_velocity) * 60.0 / (2 * std::numbers::pi);
}
}  // namespace
ElementForce MotorTorque::evaluate(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j) const {
  return {Vec3::Zero(), table_(relative_rpm(i, j)) * j.axes.col(2), i.position};
}
void MotorTorque::channels(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j,
                           std::span<double> out) const {
  out[0] = relative_rpm(i, j);
  out[1] = table_(out[0]);
}

double TableLoad::magnitude(const ForceContext& c) const {
  const double x = p_.abscissa == Abscissa::kTime ? c.time : c.crank_angle * 180.0 / std::numbers::pi - p_.offset_deg;
  return p_.scale * table_(x);
}
ElementForce TableLoad::evaluate(const ForceContext& c, const MarkerMotion& i, const MarkerMotion&) const {
  const Vec3 dir = p_.marker_axes ? Vec3(i.axes * p_.direction) : p_.direction;
  const Vec3 v = magnitude(c) * dir;
  if (p_.torque) return {Vec3::Zero(), v, i.position};
  return {v, Vec3::Zero(), i.position};
}
void TableLoad::channels(const ForceContext& c, const MarkerMotion&, const MarkerMotion&,
                         std::span<double> out) const {
  out[0] = magnitude(c);
}

ElementForce HarmonicLoad::evaluate(const ForceContext& c, const MarkerMotion& i, const MarkerMotion&) const {
  const Vec3 dir = p_.marker_axes ? Vec3(i.axes * p_.direction) : p_.direction;
  const Vec3 v = p_.amplitude * std::sin(2 * std::numbers::pi * p_.frequency_hz * c.time + p_.phase_rad) * dir;
  if (p_.torque) return {Vec3::Zero(), v, i.position};
  return {v, Vec3::Zero(), i.position};
}

}  // namespace nvh::solve
