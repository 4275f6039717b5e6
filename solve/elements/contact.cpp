// Unilateral contact of marker i's origin against the plane through marker j normal to z_j (pointing out of j's
// material), with clearance: gap = z_j . (p_i - p_j) + clearance, penetration delta = -gap (> 0 in contact).
// With the markers at the nominal (line-to-line) geometry, `clearance` is the free play.
// Normal force (Hunt & Crossley, J. Appl. Mech. 42, 1975, eq. 5):  fn = k delta^n (1 + alpha delta'),
// alpha = 3 (1 - e) / (2 v_ref), never pulling (fn >= 0). Regularized Coulomb friction in the plane:
// ft = -mu(|vt|) fn vt/|vt|,  mu = (mu_d + (mu_s - mu_d) exp(-(|vt|/v_s)^2)) tanh(|vt|/v_eps) (smooth stick-slip).
// Stored energy k delta^(n+1)/(n+1); dissipated: the damping part's power and the friction power.
// The gap is reported to the integrators as a contact event (onset and release are step boundaries).
#include <algorithm>
#include <cmath>

#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"

namespace nvh::solve {
namespace {

struct Parameters {
  double stiffness = 0;                  // N/m^n
  double exponent = 1.5;                 // 1.5 Hertz sphere on plane, 1 linear penalty
  double restitution = 1.0;              // e at the reference impact speed
  double reference_speed = 1.0;          // m/s
  double clearance = 0;                  // m
  double mu_static = 0, mu_dynamic = 0;  // friction coefficients
  double stribeck_speed = 0.01;          // m/s
  double regularization_speed = 1e-4;    // m/s
};

struct State {
  double delta, delta_rate;
  Vec3 n, vt;
};
State state(const ElementInput& in, double clearance) {
  const MarkerMotion &i = in.markers[0], &j = in.markers[1];
  const Vec3 n = j.axes.col(2);
  const Vec3 d = i.position - j.position;
  // velocity of i's point relative to the material point of j beneath it
  const Vec3 vrel = i.velocity - j.velocity - j.angular_velocity.cross(d);
  const double vn = n.dot(vrel);
  return {-(clearance + n.dot(d)), -vn, n, vrel - vn * n};
}

class Contact final : public ForceElement {
 public:
  explicit Contact(Parameters p) : p_(p) {}
  std::string type() const override { return "contact"; }
  int marker_count() const override { return 2; }
  double alpha() const { return 3.0 * (1.0 - p_.restitution) / (2.0 * p_.reference_speed); }

  double normal_force(const State& s) const {
    if (s.delta <= 0) return 0.0;
    return std::max(0.0, p_.stiffness * std::pow(s.delta, p_.exponent) * (1.0 + alpha() * s.delta_rate));
  }
  double mu(double vt) const {
    const double x = vt / p_.stribeck_speed;
    return (p_.mu_dynamic + (p_.mu_static - p_.mu_dynamic) * std::exp(-x * x)) * std::tanh(vt / p_.regularization_speed);
  }
  Vec3 force(const State& s) const {
    const double fn = normal_force(s);
    Vec3 f = fn * s.n;
    const double vt = s.vt.norm();
    if ((p_.mu_static > 0 || p_.mu_dynamic > 0) && vt > 0) f -= mu(vt) * fn * s.vt / vt;
    return f;
  }

  void evaluate(const ElementInput& in, ElementOutput& out) const override {
    const State s = state(in, p_.clearance);
    if (s.delta <= 0) return;
    apply_at_i(in, out, force(s), Vec3::Zero(), in.markers[0].position);
  }

  // Columns: marker i at 0 (dp 0, dtheta 3, dv 6, domega 9), marker j at 12 (15, 18, 21). With d = p_i - p_j,
  // n = z_j (dn = -n~ dtheta_j), vr = v_i - v_j - omega_j x d:
  //   dd  = dp_i - dp_j;   dvr = dv_i - dv_j + d~ domega_j - omega_j~ (dp_i - dp_j)
  //   delta = -(clearance + n.d):  d delta = -n^T dd + d^T n~ dtheta_j
  //   vn = n.vr:                   d vn = n^T dvr - vr^T n~ dtheta_j,  delta' = -vn
  //   vt = vr - vn n:              d vt = dvr - n d vn - vn dn
  // Normal: fn = k delta^e (1 + alpha delta'); out of contact or in the clamp (fn <= 0) no force, no Jacobian.
  // Friction: ft = -fn g(s) vt with s = |vt|, g = mu(s)/s = m(s) th(x)/eps, x = s/eps, th(x) = tanh(x)/x,
  //   m(s) = mu_d + (mu_s - mu_d) exp(-(s/v_s)^2): g is smooth in vt (even in s), also at vt = 0, and
  //   d ft = -g vt d fn - fn (g d vt + g'(s) vt (vt/s)^T d vt) with g'(s) s finite as s -> 0.
  // F = fn n + ft on i at its origin (dF = n dfn + fn dn + dft); the reaction on j by jacobian_at_i.
  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override {
    using Rows3 = Eigen::Matrix<double, 3, 24>;
    using Row = Eigen::Matrix<double, 1, 24>;
    const State s = state(in, p_.clearance);
    if (s.delta <= 0) return true;  // open: no force
    const double fn = normal_force(s);
    if (fn <= 0) return true;       // the clamp: no force around here
    const MarkerMotion &i = in.markers[0], &j = in.markers[1];
    const Vec3 d = i.position - j.position;
    const Vec3 vr = i.velocity - j.velocity - j.angular_velocity.cross(d);
    const double vn = -s.delta_rate;
    const Mat3 nx = skew(s.n), wx = skew(j.angular_velocity), eye = Mat3::Identity();
    Rows3 dd = Rows3::Zero(), dvr = Rows3::Zero(), dn = Rows3::Zero();
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
    Rows3 df = s.n * dfn + fn * dn;
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
      const Rows3 dvt = dvr - s.n * dvn - vn * dn;
      Mat3 dft_dvt = -fn * g * eye;
      if (sn > 0) dft_dvt -= fn * gs / (sn * sn) * s.vt * s.vt.transpose();
      df += -g * s.vt * dfn + dft_dvt * dvt;
    }
    ElementRows dforce = zero_rows(jac);
    dforce.leftCols<24>() = df;
    jacobian_at_i(in, jac, dforce, zero_rows(jac), force(s));
    return true;
  }

  std::vector<Channel> channels() const override {
    return {{"gap", "m"}, {"normal_force", "N"}, {"slip_speed", "m/s"}};
  }
  void channel_values(const ElementInput& in, std::span<double> out) const override {
    const State s = state(in, p_.clearance);
    out[0] = -s.delta;
    out[1] = normal_force(s);
    out[2] = s.vt.norm();
  }
  ElementEnergy energy(const ElementInput& in) const override {
    const State s = state(in, p_.clearance);
    if (s.delta <= 0) return {};
    const double elastic = p_.stiffness * std::pow(s.delta, p_.exponent);
    const double fn = normal_force(s);
    const double vt = s.vt.norm();
    // Power into the element: fn delta' (normal) + mu fn |vt| (friction); the elastic part is stored.
    return {elastic * s.delta / (p_.exponent + 1.0), (fn - elastic) * s.delta_rate + mu(vt) * fn * vt};
  }
  int gap_count() const override { return 1; }
  void gaps(const ElementInput& in, std::span<double> out) const override { out[0] = -state(in, p_.clearance).delta; }

 private:
  Parameters p_;
};

}  // namespace

void register_contact(ElementRegistry& r) {
  r.add({"force", "contact",
         "unilateral point-plane contact with clearance, Hunt-Crossley damping, Coulomb/Stribeck friction: "
         "stiffness, exponent, restitution, reference_speed, clearance, mu_static, mu_dynamic, stribeck_speed, "
         "regularization_speed",
         {"i", "j"}, [](ElementContext& c) -> std::unique_ptr<ForceElement> {
           using input::Range;
           const auto& t = c.table;
           Parameters p;
           p.stiffness = t.number("stiffness", Range::positive());
           p.exponent = t.number_or("exponent", 1.5, Range::closed(1.0, 3.0));
           p.restitution = t.number_or("restitution", 1.0, Range::open(0.0, 1.0 + 1e-12));
           p.reference_speed = t.number_or("reference_speed", 1.0, Range::positive());
           p.clearance = t.number_or("clearance", 0.0);
           p.mu_static = t.number_or("mu_static", 0.0, Range::non_negative());
           p.mu_dynamic = t.number_or("mu_dynamic", p.mu_static, Range::non_negative());
           p.stribeck_speed = t.number_or("stribeck_speed", 0.01, Range::positive());
           p.regularization_speed = t.number_or("regularization_speed", 1e-4, Range::positive());
           return std::make_unique<Contact>(p);
         }});
}

}  // namespace nvh::solve
