// Torsional spring-damper about marker j's z axis (shaft couplings, dampers):
//   T_i = -(k (phi - phi0) + d phi') z_j,   phi' = z_j . (omega_i - omega_j),
// with the twist phi an internal state integrated from its rate (residual phi' - z_j . (omega_i - omega_j) = 0),
// so it winds up through any number of turns: an angle read from the markers' axes would wrap at 180 deg and
// flip the torque's sign. phi starts at the relative rotation angle of i about z_j in the initial state.
// For markers whose z axes stay aligned (a shaft), phi is the relative rotation angle, unwrapped.
// Stored energy k (phi - phi0)^2 / 2; dissipated power d phi'^2.
#include <numbers>

#include "solve/constraint.hpp"
#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"

namespace nvh::solve {
namespace {

class TorsionalSpringDamper final : public ForceElement {
 public:
  TorsionalSpringDamper(double k, double d, double phi0, double initial)
      : k_(k), d_(d), phi0_(phi0), initial_(initial) {}
  std::string type() const override { return "torsional-spring-damper"; }
  int marker_count() const override { return 2; }
  std::vector<StateDefinition> states() const override { return {{"twist", "rad", true, initial_}}; }

  static double rate(const ElementInput& in) {
    return in.markers[1].axes.col(2).dot(in.markers[0].angular_velocity - in.markers[1].angular_velocity);
  }
  double torque(const ElementInput& in) const { return -(k_ * (in.z[0] - phi0_) + d_ * rate(in)); }

  void evaluate(const ElementInput& in, ElementOutput& out) const override {
    apply_at_i(in, out, Vec3::Zero(), torque(in) * in.markers[1].axes.col(2), in.markers[0].position);
    out.state_residual[0] = in.zp[0] - rate(in);
  }

  // With z = z_j, dw = omega_i - omega_j and dz = dtheta_j x z = -z~ dtheta_j:
  //   d(rate)/dtheta_j = -dw^T z~,  T = tau z:  dT = z dtau + tau (-z~) dtheta_j.
  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override {
    const Vec3 z = in.markers[1].axes.col(2);
    const Vec3 dw = in.markers[0].angular_velocity - in.markers[1].angular_velocity;
    const double tau = torque(in);
    const int sc = jac.state_column(2, 0);
    Eigen::Matrix<double, 1, Eigen::Dynamic, Eigen::RowMajor, 1, 64> drate =
        Eigen::RowVectorXd::Zero(jac.matrix.cols());
    drate.segment<3>(9) = z.transpose();                  // domega_i
    drate.segment<3>(21) = -z.transpose();                // domega_j
    drate.segment<3>(15) = -dw.transpose() * skew(z);     // dtheta_j
    ElementRows dt = -d_ * z * drate;
    dt.col(sc) -= k_ * z;
    dt.block<3, 3>(0, 15) -= tau * skew(z);
    jacobian_at_i(in, jac, zero_rows(jac), dt, Vec3::Zero());
    auto row = jac.matrix.row(12);
    row -= drate;
    row[sc] += jac.cj;
    return true;
  }

  std::vector<Channel> channels() const override { return {{"twist", "rad"}, {"spring_torque", "N m"}}; }
  void channel_values(const ElementInput& in, std::span<double> out) const override {
    out[0] = in.z[0] - phi0_;
    out[1] = torque(in);
  }
  ElementEnergy energy(const ElementInput& in) const override {
    const double phi = in.z[0] - phi0_, r = rate(in);
    return {0.5 * k_ * phi * phi, d_ * r * r};
  }

 private:
  double k_, d_, phi0_, initial_;
};

}  // namespace

void register_torsional_spring_damper(ElementRegistry& r) {
  r.add({"force", "torsional-spring-damper",
         "torque about z_j from the wound-up twist (an internal state): k, d, angle0_deg", {"i", "j"},
         [](ElementContext& c) -> std::unique_ptr<ForceElement> {
           using input::Range;
           const auto& t = c.table;
           return std::make_unique<TorsionalSpringDamper>(
               t.number("k", Range::closed(0.0, bounds::kCoefficient)),
               t.number_or("d", 0.0, Range::closed(0.0, bounds::kCoefficient)),
               t.number_or("angle0_deg", 0.0, Range::magnitude(bounds::kAngleDeg)) * std::numbers::pi / 180.0,
               relative_angle(c.initial[0], c.initial[1]));
         }});
}

}  // namespace nvh::solve
