// 6-DOF bushing: relative displacement and small rotation of marker i against marker j in j's axes,
//   [F; T]_j = -K [u; theta] - D [u'; theta'],  applied at marker i (body j gets the reaction),
// u = A_j^T (p_i - p_j), theta the axis-angle vector of A_j^T A_i (small angles in practice),
// u' = A_j^T (v_i - v_j - omega_j x (p_i - p_j)), theta' = A_j^T (omega_i - omega_j) (small-angle rate).
// Stored energy 1/2 [u; theta]^T K_sym [u; theta] (exact for a symmetric K); dissipated [u'; theta']^T D [u'; theta'].
// Jacobian: closed form, with the exact derivative of the rotation vector (inverse left Jacobian of SO(3));
// singular only at theta = pi, where the rotation vector itself jumps.
#include <cmath>

#include <Eigen/Geometry>

#include "common/error.hpp"
#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"

namespace nvh::solve {
namespace {

using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

struct Relative {
  Vector6 u, ud;
};
Relative relative(const ElementInput& in) {
  const MarkerMotion &i = in.markers[0], &j = in.markers[1];
  const Mat3& aj = j.axes;
  Relative r;
  const Vec3 d = i.position - j.position;
  r.u.head<3>() = aj.transpose() * d;
  const Eigen::AngleAxisd rel(aj.transpose() * i.axes);
  r.u.tail<3>() = rel.angle() * rel.axis();
  r.ud.head<3>() = aj.transpose() * (i.velocity - j.velocity - j.angular_velocity.cross(d));
  r.ud.tail<3>() = aj.transpose() * (i.angular_velocity - j.angular_velocity);
  return r;
}

/// J_l^-1(theta): the inverse left Jacobian of SO(3), d(log R) = J_l^-1(theta) eps for R -> (I + eps~) R:
///   J_l^-1 = I - theta~/2 + c theta~^2,  c = 1/theta^2 - (1 + cos theta) / (2 theta sin theta),
/// c by its series 1/12 + theta^2/720 + theta^4/30240 below theta = 0.01 (where the closed form cancels).
Mat3 inverse_left_jacobian(const Vec3& theta) {
  const double a = theta.norm(), a2 = a * a;
  const double c = a < 1e-2 ? 1.0 / 12.0 + a2 / 720.0 + a2 * a2 / 30240.0
                            : 1.0 / a2 - (1.0 + std::cos(a)) / (2.0 * a * std::sin(a));
  const Mat3 t = skew(theta);
  return Mat3::Identity() - 0.5 * t + c * t * t;
}

class Bushing final : public ForceElement {
 public:
  Bushing(Matrix6 k, Matrix6 d) : k_(k), d_(d) {}
  std::string type() const override { return "bushing"; }
  int marker_count() const override { return 2; }
  void evaluate(const ElementInput& in, ElementOutput& out) const override {
    const Relative r = relative(in);
    const Vector6 f = -(k_ * r.u + d_ * r.ud);
    const Mat3& aj = in.markers[1].axes;
    apply_at_i(in, out, aj * f.head<3>(), aj * f.tail<3>(), in.markers[0].position);
  }

  // Columns (per marker 12: dp, dtheta, dv, domega): i at 0, j at 12. With d = p_i - p_j, a small rotation
  // dtheta_j turns A_j^T x into A_j^T x + A_j^T x~ dtheta_j, so for any global x: d(A_j^T x)/dtheta_j = A_j^T x~.
  //   u      = A_j^T d:                 dp_i A_j^T, dp_j -A_j^T, dtheta_j A_j^T d~
  //   theta  = log(A_j^T A_i):          dtheta_i J_l^-1 A_j^T, dtheta_j -J_l^-1 A_j^T
  //            (A_i -> (I + e~) A_i turns R = A_j^T A_i into (I + (A_j^T e)~) R; A_j the opposite)
  //   u'     = A_j^T vr, vr = v_i - v_j - omega_j x d:
  //            dp_i -A_j^T omega_j~, dp_j A_j^T omega_j~, dv_i A_j^T, dv_j -A_j^T, domega_j A_j^T d~, dtheta_j A_j^T vr~
  //   theta' = A_j^T (omega_i - omega_j): domega_i A_j^T, domega_j -A_j^T, dtheta_j A_j^T (omega_i - omega_j)~
  // f = -(K u + D u') in j's axes; F = A_j f_t, T = A_j f_r: dF = A_j df_t - F~ dtheta_j (and T alike);
  // apply_at_i's reaction on j by jacobian_at_i.
  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override {
    using Matrix6x24 = Eigen::Matrix<double, 6, 24>;
    const MarkerMotion &i = in.markers[0], &j = in.markers[1];
    const Mat3& aj = j.axes;
    const Mat3 ajt = aj.transpose();
    const Relative r = relative(in);
    const Vec3 d = i.position - j.position;
    const Vec3 vr = i.velocity - j.velocity - j.angular_velocity.cross(d);
    const Vec3 dw = i.angular_velocity - j.angular_velocity;
    const Mat3 jt = inverse_left_jacobian(r.u.tail<3>()) * ajt;
    Matrix6x24 du = Matrix6x24::Zero(), dud = Matrix6x24::Zero();
    du.block<3, 3>(0, 0) = ajt;                              // dp_i
    du.block<3, 3>(0, 12) = -ajt;                            // dp_j
    du.block<3, 3>(0, 15) = ajt * skew(d);                   // dtheta_j
    du.block<3, 3>(3, 3) = jt;                               // dtheta_i
    du.block<3, 3>(3, 15) = -jt;                             // dtheta_j
    dud.block<3, 3>(0, 0) = -ajt * skew(j.angular_velocity);  // dp_i
    dud.block<3, 3>(0, 12) = ajt * skew(j.angular_velocity);  // dp_j
    dud.block<3, 3>(0, 6) = ajt;                             // dv_i
    dud.block<3, 3>(0, 18) = -ajt;                           // dv_j
    dud.block<3, 3>(0, 21) = ajt * skew(d);                  // domega_j
    dud.block<3, 3>(0, 15) = ajt * skew(vr);                 // dtheta_j
    dud.block<3, 3>(3, 9) = ajt;                             // domega_i
    dud.block<3, 3>(3, 21) = -ajt;                           // domega_j
    dud.block<3, 3>(3, 15) = ajt * skew(dw);                 // dtheta_j
    const Matrix6x24 df = -(k_ * du + d_ * dud);
    const Vector6 f = -(k_ * r.u + d_ * r.ud);
    const Vec3 force = aj * f.head<3>(), torque = aj * f.tail<3>();
    ElementRows dforce = zero_rows(jac), dtorque = zero_rows(jac);
    dforce.leftCols<24>() = aj * df.topRows<3>();
    dtorque.leftCols<24>() = aj * df.bottomRows<3>();
    dforce.block<3, 3>(0, 15) -= skew(force);
    dtorque.block<3, 3>(0, 15) -= skew(torque);
    jacobian_at_i(in, jac, dforce, dtorque, force);
    return true;
  }
  std::vector<Channel> channels() const override {
    return {{"displacement_x", "m"}, {"displacement_y", "m"}, {"displacement_z", "m"},
            {"rotation_x", "rad"},   {"rotation_y", "rad"},   {"rotation_z", "rad"}};
  }
  void channel_values(const ElementInput& in, std::span<double> out) const override {
    const Relative r = relative(in);
    for (int k = 0; k < 6; ++k) out[k] = r.u[k];
  }
  ElementEnergy energy(const ElementInput& in) const override {
    const Relative r = relative(in);
    const Matrix6 ks = 0.5 * (k_ + k_.transpose());
    return {0.5 * r.u.dot(ks * r.u), r.ud.dot(d_ * r.ud)};
  }

 private:
  Matrix6 k_, d_;
};

}  // namespace

void register_bushing(ElementRegistry& r) {
  r.add({"force", "bushing",
         "6-DOF bushing in marker j's axes: stiffness, damping (6 diagonal values or a 6 x 6 matrix, row by row)",
         {"i", "j"}, [](ElementContext& c) -> std::unique_ptr<ForceElement> {
           const auto& t = c.table;
           auto matrix6 = [&](const char* key) {
             Matrix6 m = Matrix6::Zero();
             if (!t.has(key)) return m;
             const auto v = t.numbers(key, input::Range::magnitude(bounds::kCoefficient));
             if (v.size() == 6) {
               for (int k = 0; k < 6; ++k) m(k, k) = v[k];
             } else if (v.size() == 36) {
               for (int k = 0; k < 36; ++k) m(k / 6, k % 6) = v[k];
             } else {
               t.fail(key, "expected 6 diagonal values [x, y, z, rx, ry, rz] or 36 values of a 6 x 6 matrix, row by row");
             }
             return m;
           };
           return std::make_unique<Bushing>(matrix6("stiffness"), matrix6("damping"));
         }});
}

}  // namespace nvh::solve
