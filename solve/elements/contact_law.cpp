// The point-against-plane contact law (contact_law.hpp).
#include "solve/elements/contact_law.hpp"

#include <algorithm>
#include <cmath>

#include "solve/element_registry.hpp"

namespace nvh::solve::contact {

Parameters read_parameters(const input::Table& t) {
  using input::Range;
  Parameters p;
  // Speeds from 1 nm/s: below, the damping 3 (1 - e) / (2 v_ref) and the friction's tanh(v / v_eps) have
  // scales that overflow.
  const Range speed = Range::closed(1e-9, bounds::kSpeed);
  p.stiffness = t.number("stiffness", Range{0.0, bounds::kCoefficient, true, false});
  p.exponent = t.number_or("exponent", 1.5, Range::closed(1.0, 3.0));
  p.restitution = t.number_or("restitution", 1.0, Range::open(0.0, 1.0 + 1e-12));
  p.reference_speed = t.number_or("reference_speed", 1.0, speed);
  p.clearance = t.number_or("clearance", 0.0, Range::magnitude(bounds::kClearance));
  read_friction(t, p);
  return p;
}

void read_friction(const input::Table& t, Parameters& p) {
  using input::Range;
  const Range speed = Range::closed(1e-9, bounds::kSpeed);  // from 1 nm/s: read_parameters
  p.mu_static = t.number_or("mu_static", 0.0, Range::closed(0.0, 10.0));
  p.mu_dynamic = t.number_or("mu_dynamic", p.mu_static, Range::closed(0.0, 10.0));
  p.stribeck_speed = t.number_or("stribeck_speed", 0.01, speed);
  p.regularization_speed = t.number_or("regularization_speed", 1e-4, speed);
}

State Law::state(const MarkerMotion& point, const MarkerMotion& j) const {
  const Vec3 n = j.axes.col(2);
  const Vec3 d = point.position - j.position;
  // velocity of the point relative to the material point of j beneath it
  const Vec3 vrel = point.velocity - j.velocity - j.angular_velocity.cross(d);
  const double vn = n.dot(vrel);
  return {-(p_.clearance + n.dot(d)), -vn, n, vrel - vn * n};
}

double Law::normal_force(const State& s) const {
  if (s.delta <= 0) return 0.0;
  return std::max(0.0, p_.stiffness * std::pow(s.delta, p_.exponent) * (1.0 + alpha() * s.delta_rate));
}

double Law::mu(double vt) const {
  const double x = vt / p_.stribeck_speed;
  return (p_.mu_dynamic + (p_.mu_static - p_.mu_dynamic) * std::exp(-x * x)) * std::tanh(vt / p_.regularization_speed);
}

double Law::mu_derivative(double vt) const {
  const double x = vt / p_.stribeck_speed, th = std::tanh(vt / p_.regularization_speed);
  const double m = p_.mu_dynamic + (p_.mu_static - p_.mu_dynamic) * std::exp(-x * x);
  const double dm = -2.0 * x / p_.stribeck_speed * (p_.mu_static - p_.mu_dynamic) * std::exp(-x * x);
  return dm * th + m * (1.0 - th * th) / p_.regularization_speed;
}

Vec3 Law::force(const State& s) const {
  const double fn = normal_force(s);
  Vec3 f = fn * s.n;
  const double vt = s.vt.norm();
  if ((p_.mu_static > 0 || p_.mu_dynamic > 0) && vt > 0) f -= mu(vt) * fn * s.vt / vt;
  return f;
}

// Columns: the point at 0 (dp 0, dtheta 3, dv 6, domega 9), marker j at 12 (15, 18, 21). With d = p - p_j,
// n = z_j (dn = -n~ dtheta_j), vr = v - v_j - omega_j x d:
//   dd  = dp - dp_j;   dvr = dv - dv_j + d~ domega_j - omega_j~ (dp - dp_j)
//   delta = -(clearance + n.d):  d delta = -n^T dd + d^T n~ dtheta_j
//   vn = n.vr:                   d vn = n^T dvr - vr^T n~ dtheta_j,  delta' = -vn
//   vt = vr - vn n:              d vt = dvr - n d vn - vn dn
// Normal: fn = k delta^e (1 + alpha delta'); out of contact or in the clamp (fn <= 0) no force, no Jacobian.
// Friction: ft = -fn g(s) vt with s = |vt|, g = mu(s)/s = m(s) th(x)/eps, x = s/eps, th(x) = tanh(x)/x,
//   m(s) = mu_d + (mu_s - mu_d) exp(-(s/v_s)^2): g is smooth in vt (even in s), also at vt = 0, and
//   d ft = -g vt d fn - fn (g d vt + g'(s) vt (vt/s)^T d vt) with g'(s) s finite as s -> 0.
// F = fn n + ft (dF = n dfn + fn dn + dft).
bool Law::jacobian(const MarkerMotion& point, const MarkerMotion& j, PointJacobian& df) const {
  using Row = Eigen::Matrix<double, 1, 24>;
  const State s = state(point, j);
  if (s.delta <= 0) return false;  // open: no force
  const double fn = normal_force(s);
  if (fn <= 0) return false;       // the clamp: no force around here
  const Vec3 d = point.position - j.position;
  const Vec3 vr = point.velocity - j.velocity - j.angular_velocity.cross(d);
  const double vn = -s.delta_rate;
  const Mat3 nx = skew(s.n), wx = skew(j.angular_velocity), eye = Mat3::Identity();
  PointJacobian dd = PointJacobian::Zero(), dvr = PointJacobian::Zero(), dn = PointJacobian::Zero();
  dd.block<3, 3>(0, 0) = eye;
  dd.block<3, 3>(0, 12) = -eye;
  dvr.block<3, 3>(0, 6) = eye;
  dvr.block<3, 3>(0, 18) = -eye;
  dvr.block<3, 3>(0, 21) = skew(d);
  dvr.block<3, 3>(0, 0) = -wx;
  dvr.block<3, 3>(0, 12) = wx;
  dn.block<3, 3>(0, 15) = -nx;
  const Row ddelta = -s.n.transpose() * dd - d.transpose() * dn;
  const Row dvn = s.n.transpose() * dvr + vr.transpose() * dn;
  // d fn = k e delta^(e-1) (1 + alpha delta') d delta + k delta^e alpha d delta'
  const double a = alpha(), pe = std::pow(s.delta, p_.exponent);
  const Row dfn = p_.stiffness * (p_.exponent * pe / s.delta * (1.0 + a * s.delta_rate) * ddelta - pe * a * dvn);
  df = s.n * dfn + fn * dn;
  if (p_.mu_static > 0 || p_.mu_dynamic > 0) {
    const double sn = s.vt.norm(), eps = p_.regularization_speed;
    const double x = sn / eps, y = sn / p_.stribeck_speed, ex = std::exp(-y * y);
    const double m = p_.mu_dynamic + (p_.mu_static - p_.mu_dynamic) * ex;
    const double dm = (p_.mu_static - p_.mu_dynamic) * ex * (-2.0 * y / p_.stribeck_speed);  // dm/ds
    double th, dth;  // tanh(x)/x and its derivative, by series near 0
    if (x < 1e-3) {
      th = 1.0 - x * x / 3.0 + 2.0 * x * x * x * x / 15.0;
      dth = -2.0 * x / 3.0 + 8.0 * x * x * x / 15.0;
    } else {
      const double t = std::tanh(x);
      th = t / x;
      dth = ((1.0 - t * t) * x - t) / (x * x);
    }
    const double g = m * th / eps;
    const double gs = dm * th / eps * sn + m * dth / (eps * eps) * sn;  // g'(s) s
    const PointJacobian dvt = dvr - s.n * dvn - vn * dn;
    Mat3 dft_dvt = -fn * g * eye;
    if (sn > 0) dft_dvt -= fn * gs / (sn * sn) * s.vt * s.vt.transpose();
    df += -g * s.vt * dfn + dft_dvt * dvt;
  }
  return true;
}

ElementEnergy Law::energy(const State& s) const {
  if (s.delta <= 0) return {};
  const double elastic = p_.stiffness * std::pow(s.delta, p_.exponent);
  const double fn = normal_force(s);
  const double vt = s.vt.norm();
  // Power into the contact: fn delta' (normal) + mu fn |vt| (friction); the elastic part is stored.
  return {elastic * s.delta / (p_.exponent + 1.0), (fn - elastic) * s.delta_rate + mu(vt) * fn * vt};
}

void PointElement::evaluate(const ElementInput& in, ElementOutput& out) const {
  const State s = state(in);
  if (s.delta <= 0) return;
  apply_at_i(in, out, law_.force(s), Vec3::Zero(), in.markers[0].position);
}

// dF by the law (columns i then j, as the element's); the reaction on j by jacobian_at_i.
bool PointElement::jacobian(const ElementInput& in, ElementJacobian& jac) const {
  PointJacobian df;
  if (!law_.jacobian(in.markers[0], in.markers[1], df)) return true;  // open, or the clamp: no force
  ElementRows dforce = zero_rows(jac);
  dforce.leftCols<24>() = df;
  jacobian_at_i(in, jac, dforce, zero_rows(jac), law_.force(state(in)));
  return true;
}

}  // namespace nvh::solve::contact
