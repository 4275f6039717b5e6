// A plain bearing as a spring-damper (the engine paper's eq. 8, f = k dx + d dx', for big ends, small ends
// and main bearings): marker i (the journal, its z the shaft axis) in marker j (the bore, z the bore axis),
// radial and axial springs and dampers on the journal centre's displacement in j's axes, a tilt spring and
// damper on the misalignment of the axes, and the spin about the axis free - through any number of turns,
// which the bushing's rotation vector cannot follow (singular at pi). SI units:
//   u = A_j^T (p_i - p_j),  u' = A_j^T (v_i - v_j - omega_j x (p_i - p_j))
//   f = -(K u + D u'),  K = diag(k_r, k_r, k_a),  D = diag(d_r, d_r, d_a)      force on i in j's axes (N)
//   T = -k_t (z_j x z_i) - d_t P (omega_i - omega_j),  P = 1 - z_j z_j^T       moment on i, global (N m)
// applied at marker i, body j taking the reaction. The tilt spring is conservative with the stored energy
// k_t (1 - z_i . z_j) = k_t (1 - cos alpha) ~ k_t alpha^2 / 2 (alpha the misalignment); stored energy
// u^T K u / 2 + k_t (1 - z_i . z_j), dissipated power u'^T D u' + d_t |P (omega_i - omega_j)|^2.
#include <cmath>

#include "common/error.hpp"
#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"

namespace nvh::solve {
namespace {

struct BearingSpringParameters {
  double radial_k = 0, radial_d = 0, axial_k = 0, axial_d = 0, tilt_k = 0, tilt_d = 0;
};

class BearingSpring final : public ForceElement {
 public:
  explicit BearingSpring(const BearingSpringParameters& p) : p_(p) {
    k_ = Vec3(p.radial_k, p.radial_k, p.axial_k).asDiagonal();
    d_ = Vec3(p.radial_d, p.radial_d, p.axial_d).asDiagonal();
  }
  std::string type() const override { return "bearing-spring"; }
  int marker_count() const override { return 2; }

  void evaluate(const ElementInput& in, ElementOutput& out) const override {
    const State s = state(in);
    apply_at_i(in, out, in.markers[1].axes * s.f, s.torque, in.markers[0].position);
  }

  // Columns (per marker 12: dp, dtheta, dv, domega): i at 0, j at 12; a small rotation dtheta turns a
  // body-fixed vector a into a + dtheta x a = a - a~ dtheta. The force's rows as the bushing's (bushing.cpp):
  //   u:  dp_i A_j^T, dp_j -A_j^T, dtheta_j A_j^T d~
  //   u': dp_i -A_j^T omega_j~, dp_j A_j^T omega_j~, dv_i A_j^T, dv_j -A_j^T, domega_j A_j^T d~,
  //       dtheta_j A_j^T vr~;   F = A_j f: dF = A_j df - F~ dtheta_j
  // The moment, global: d(z_j x z_i) = -z_j~ z_i~ dtheta_i + z_i~ z_j~ dtheta_j, so the spring's
  //   dT/dtheta_i = k_t z_j~ z_i~,  dT/dtheta_j = -k_t z_i~ z_j~;
  // the damper's, w = omega_i - omega_j: dT/domega_i = -d_t P, dT/domega_j = d_t P,
  //   dT/dtheta_j = -d_t ((z_j . w) z_j~ + z_j w^T z_j~).
  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override {
    using Matrix3x24 = Eigen::Matrix<double, 3, 24>;
    const MarkerMotion &i = in.markers[0], &j = in.markers[1];
    const Mat3& aj = j.axes;
    const Mat3 ajt = aj.transpose();
    const State s = state(in);
    Matrix3x24 du = Matrix3x24::Zero(), dud = Matrix3x24::Zero();
    du.block<3, 3>(0, 0) = ajt;
    du.block<3, 3>(0, 12) = -ajt;
    du.block<3, 3>(0, 15) = ajt * skew(s.d);
    dud.block<3, 3>(0, 0) = -ajt * skew(j.angular_velocity);
    dud.block<3, 3>(0, 12) = ajt * skew(j.angular_velocity);
    dud.block<3, 3>(0, 6) = ajt;
    dud.block<3, 3>(0, 18) = -ajt;
    dud.block<3, 3>(0, 21) = ajt * skew(s.d);
    dud.block<3, 3>(0, 15) = ajt * skew(s.vr);
    const Vec3 force = aj * s.f;
    ElementRows dforce = zero_rows(jac), dtorque = zero_rows(jac);
    dforce.leftCols<24>() = aj * (-(k_ * du + d_ * dud));
    dforce.block<3, 3>(0, 15) -= skew(force);
    const Vec3 zi = i.axes.col(2), zj = j.axes.col(2), w = i.angular_velocity - j.angular_velocity;
    const Mat3 zit = skew(zi), zjt = skew(zj);
    const Mat3 p = Mat3::Identity() - zj * zj.transpose();
    dtorque.block<3, 3>(0, 3) = p_.tilt_k * zjt * zit;
    dtorque.block<3, 3>(0, 15) =
        -p_.tilt_k * zit * zjt - p_.tilt_d * (zj.dot(w) * zjt + zj * (w.transpose() * zjt));
    dtorque.block<3, 3>(0, 9) = -p_.tilt_d * p;
    dtorque.block<3, 3>(0, 21) = p_.tilt_d * p;
    jacobian_at_i(in, jac, dforce, dtorque, force);
    return true;
  }

  std::vector<Channel> channels() const override {
    return {{"force_x", "N"},
            {"force_y", "N"},
            {"force_z", "N"},
            {"radial_displacement", "m"},
            {"axial_displacement", "m"},
            {"misalignment", "rad"},
            {"tilt_moment", "N m"}};
  }
  void channel_values(const ElementInput& in, std::span<double> out) const override {
    const State s = state(in);
    const Vec3 zi = in.markers[0].axes.col(2), zj = in.markers[1].axes.col(2);
    out[0] = s.f.x(), out[1] = s.f.y(), out[2] = s.f.z();
    out[3] = std::hypot(s.u.x(), s.u.y());
    out[4] = s.u.z();
    out[5] = std::atan2(zj.cross(zi).norm(), zj.dot(zi));
    out[6] = p_.tilt_k * zj.cross(zi).norm();
  }
  ElementEnergy energy(const ElementInput& in) const override {
    const State s = state(in);
    const Vec3 zi = in.markers[0].axes.col(2), zj = in.markers[1].axes.col(2);
    const Vec3 w = in.markers[0].angular_velocity - in.markers[1].angular_velocity;
    const Vec3 wp = w - zj * zj.dot(w);
    return {0.5 * s.u.dot(k_ * s.u) + p_.tilt_k * (1.0 - zi.dot(zj)),
            s.ud.dot(d_ * s.ud) + p_.tilt_d * wp.squaredNorm()};
  }

 private:
  struct State {
    Vec3 d, vr, u, ud, f, torque;
  };
  State state(const ElementInput& in) const {
    const MarkerMotion &i = in.markers[0], &j = in.markers[1];
    State s;
    s.d = i.position - j.position;
    s.vr = i.velocity - j.velocity - j.angular_velocity.cross(s.d);
    s.u = j.axes.transpose() * s.d;
    s.ud = j.axes.transpose() * s.vr;
    s.f = -(k_ * s.u + d_ * s.ud);
    const Vec3 zi = i.axes.col(2), zj = j.axes.col(2), w = i.angular_velocity - j.angular_velocity;
    s.torque = -p_.tilt_k * zj.cross(zi) - p_.tilt_d * (w - zj * zj.dot(w));
    return s;
  }
  BearingSpringParameters p_;
  Mat3 k_, d_;
};

}  // namespace

void register_bearing_spring(ElementRegistry& r) {
  r.add({"force",
         "bearing-spring",
         "a plain bearing as spring-damper (eq. 8): radial_stiffness, radial_damping, axial_stiffness, "
         "axial_damping, tilt_stiffness, tilt_damping; spin about z free",
         {"i", "j"},
         [](ElementContext& c) -> std::unique_ptr<ForceElement> {
           const auto& t = c.table;
           const auto range = input::Range::closed(0.0, bounds::kCoefficient);
           BearingSpringParameters p;
           p.radial_k = t.number("radial_stiffness", range);
           p.radial_d = t.number_or("radial_damping", 0.0, range);
           p.axial_k = t.number_or("axial_stiffness", 0.0, range);
           p.axial_d = t.number_or("axial_damping", 0.0, range);
           p.tilt_k = t.number_or("tilt_stiffness", 0.0, range);
           p.tilt_d = t.number_or("tilt_damping", 0.0, range);
           return std::make_unique<BearingSpring>(p);
         }});
}

}  // namespace nvh::solve
