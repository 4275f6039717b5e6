// Point-to-point spring-damper along the line from marker j to marker i (engine paper 000, eq. 8):
//   tension = k(dx) dx + d(dx) dx' + preload,   dx = |p_i - p_j| - free_length,   F_i = -tension e,
// linear: k = k0, d = d0; non-linear (eq. 9-10 as read here): k = k0 + kB (dx/xB)^2, d = d0 + dB (dx/xB)^2.
// e = (p_i - p_j) / |p_i - p_j|; tension positive pulls i towards j.
// Stored energy V = k0 dx^2/2 + kB dx^4/(4 xB^2) + preload dx (dV/d(dx) = spring part of the tension);
// dissipated power d(dx) dx'^2.
#include <cmath>

#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"

namespace nvh::solve {
namespace {

struct Parameters {
  double k0 = 0, d0 = 0;            // N/m, N s/m
  double kb = 0, db = 0, xb = 1.0;  // N/m, N s/m, m
  double free_length = 0;           // m
  double preload = 0;               // N
};

struct Line {
  Vec3 e;         // unit vector j -> i
  double length;  // m
  Vec3 v;         // v_i - v_j
  double rate;    // m/s
};
Line line(const ElementInput& in) {
  const Vec3 d = in.markers[0].position - in.markers[1].position;
  const double l = d.norm();
  const Vec3 e = l > 1e-12 ? Vec3(d / l) : Vec3::UnitZ();
  const Vec3 v = in.markers[0].velocity - in.markers[1].velocity;
  return {e, l, v, e.dot(v)};
}

class SpringDamper final : public ForceElement {
 public:
  explicit SpringDamper(Parameters p) : p_(p) {}
  std::string type() const override { return "spring-damper"; }
  int marker_count() const override { return 2; }

  double stiffness(double dx) const { return p_.k0 + p_.kb * (dx / p_.xb) * (dx / p_.xb); }
  double damping(double dx) const { return p_.d0 + p_.db * (dx / p_.xb) * (dx / p_.xb); }
  double tension(const Line& s) const {
    const double dx = s.length - p_.free_length;
    return stiffness(dx) * dx + damping(dx) * s.rate + p_.preload;
  }

  void evaluate(const ElementInput& in, ElementOutput& out) const override {
    const Line s = line(in);
    apply_at_i(in, out, -tension(s) * s.e, Vec3::Zero(), in.markers[0].position);
  }

  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override {
    const Line s = line(in);
    if (s.length <= 1e-12) return false;
    const double dx = s.length - p_.free_length, x2 = 1.0 / (p_.xb * p_.xb);
    const double tau = tension(s);
    const double dtau_dx = p_.k0 + 3 * p_.kb * dx * dx * x2 + 2 * p_.db * dx * x2 * s.rate;
    const double c = damping(dx);
    const Mat3 proj = (Mat3::Identity() - s.e * s.e.transpose()) / s.length;  // de/dd
    // d(tension)/dd = dtau_dx e^T + c v^T de/dd;  F = -tension e.
    const Eigen::RowVector3d dtau_dd = dtau_dx * s.e.transpose() + c * s.v.transpose() * proj;
    const Mat3 df_dd = -s.e * dtau_dd - tau * proj;
    const Mat3 df_dv = -c * s.e * s.e.transpose();
    ElementRows df = zero_rows(jac);
    df.block<3, 3>(0, 0) = df_dd;    // dp_i
    df.block<3, 3>(0, 12) = -df_dd;  // dp_j
    df.block<3, 3>(0, 6) = df_dv;    // dv_i
    df.block<3, 3>(0, 18) = -df_dv;  // dv_j
    jacobian_at_i(in, jac, df, zero_rows(jac), -tau * s.e);
    return true;
  }

  std::vector<Channel> channels() const override {
    return {{"deflection", "m"}, {"deflection_rate", "m/s"}, {"tension", "N"}};
  }
  void channel_values(const ElementInput& in, std::span<double> out) const override {
    const Line s = line(in);
    out[0] = s.length - p_.free_length;
    out[1] = s.rate;
    out[2] = tension(s);
  }
  ElementEnergy energy(const ElementInput& in) const override {
    const Line s = line(in);
    const double dx = s.length - p_.free_length;
    return {0.5 * p_.k0 * dx * dx + 0.25 * p_.kb * dx * dx * dx * dx / (p_.xb * p_.xb) + p_.preload * dx,
            damping(dx) * s.rate * s.rate};
  }

 private:
  Parameters p_;
};

}  // namespace

void register_spring_damper(ElementRegistry& r) {
  r.add({"force", "spring-damper",
         "point-to-point spring-damper, linear or non-linear (k = k0 + kB (dx/xB)^2): k, d, kB, dB, xB, "
         "free_length, preload",
         {"i", "j"}, [](ElementContext& c) -> std::unique_ptr<ForceElement> {
           using input::Range;
           const auto& t = c.table;
           Parameters p;
           const Range coefficient = Range::closed(0.0, bounds::kCoefficient);
           p.k0 = t.number_or("k", 0.0, coefficient);
           p.d0 = t.number_or("d", 0.0, coefficient);
           p.kb = t.number_or("kB", 0.0, Range::magnitude(bounds::kCoefficient));
           p.db = t.number_or("dB", 0.0, Range::magnitude(bounds::kCoefficient));
           p.xb = t.number_or("xB", 1.0, Range::closed(1e-9, bounds::kLength));  // (dx / xB)^2 stays finite
           p.preload = t.number_or("preload", 0.0, Range::magnitude(bounds::kCoefficient));
           // Without free_length: the initial distance, so there is no force at the start.
           p.free_length = t.has("free_length") ? t.number("free_length", Range::closed(0.0, bounds::kLength))
                                                : (c.initial[0].position - c.initial[1].position).norm();
           return std::make_unique<SpringDamper>(p);
         }});
}

}  // namespace nvh::solve
