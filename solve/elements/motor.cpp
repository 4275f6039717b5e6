// A motor torque-speed curve: torque about z_j on i (the rotor) and the reaction on j (the stator) from a table
// of torque (N m) against the relative speed in rpm, n = z_j . (omega_i - omega_j) 60 / (2 pi): an induction
// motor's characteristic. A source: its input power is T n 2 pi / 60.
#include <numbers>

#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"

namespace nvh::solve {
namespace {

constexpr double kRpm = 60.0 / (2 * std::numbers::pi);

class MotorTorque final : public ForceElement {
 public:
  explicit MotorTorque(Table1D t) : table_(std::move(t)) {}
  std::string type() const override { return "motor"; }
  int marker_count() const override { return 2; }
  bool is_source() const override { return true; }
  static double rpm(const ElementInput& in) {
    return in.markers[1].axes.col(2).dot(in.markers[0].angular_velocity - in.markers[1].angular_velocity) * kRpm;
  }
  void evaluate(const ElementInput& in, ElementOutput& out) const override {
    apply_at_i(in, out, Vec3::Zero(), table_(rpm(in)) * in.markers[1].axes.col(2), in.markers[0].position);
  }

  // r = n.(omega_i - omega_j) kRpm, n = z_j (dn = -n~ dtheta_j; marker i's omega at column 9, j's at 12 + 9,
  // j's dtheta at 12 + 3):  dr = kRpm (n^T (domega_i - domega_j) - dw^T n~ dtheta_j),  dw = omega_i - omega_j.
  // T = tau(r) n:  dT = n tau'(r) dr - tau(r) n~ dtheta_j; no force, so the reaction on j is -dT.
  // tau' is the slope of the curve's piece (0 beyond its ends).
  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override {
    const Vec3 n = in.markers[1].axes.col(2);
    const Vec3 dw = in.markers[0].angular_velocity - in.markers[1].angular_velocity;
    const double r = rpm(in), tau = table_(r);
    const Mat3 nx = skew(n);
    Eigen::Matrix<double, 1, 24> dr = Eigen::Matrix<double, 1, 24>::Zero();
    dr.segment<3>(9) = kRpm * n.transpose();          // domega_i
    dr.segment<3>(21) = -kRpm * n.transpose();        // domega_j
    dr.segment<3>(15) = -kRpm * dw.transpose() * nx;  // dtheta_j
    ElementRows dt = zero_rows(jac);
    dt.leftCols<24>() = table_.slope(r) * n * dr;
    dt.block<3, 3>(0, 15) -= tau * nx;
    jacobian_at_i(in, jac, zero_rows(jac), dt, Vec3::Zero());
    return true;
  }
  std::vector<Channel> channels() const override { return {{"speed", "rpm"}, {"motor_torque", "N m"}}; }
  void channel_values(const ElementInput& in, std::span<double> out) const override {
    out[0] = rpm(in);
    out[1] = table_(out[0]);
  }

 private:
  Table1D table_;
};

}  // namespace

void register_motor(ElementRegistry& r) {
  auto make = [](ElementContext& c) -> std::unique_ptr<ForceElement> {
    return std::make_unique<MotorTorque>(c.table_from("motor torque-speed curve (rpm, N m)"));
  };
  r.add({"driver", "motor", "motor torque-speed curve (rpm, N m) between rotor i and stator j", {"i", "j"}, make});
  r.add({"force", "motor", "motor torque-speed curve (rpm, N m) between rotor i and stator j", {"i", "j"}, make});
}

}  // namespace nvh::solve
