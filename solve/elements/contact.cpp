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
