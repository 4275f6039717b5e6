// 6-DOF bushing: relative displacement and small rotation of marker i against marker j in j's axes,
//   [F; T]_j = -K [u; theta] - D [u'; theta'],  applied at marker i (body j gets the reaction),
// u = A_j^T (p_i - p_j), theta the axis-angle vector of A_j^T A_i (small angles in practice),
// u' = A_j^T (v_i - v_j - omega_j x (p_i - p_j)), theta' = A_j^T (omega_i - omega_j) (small-angle rate).
// Stored energy 1/2 [u; theta]^T K_sym [u; theta] (exact for a symmetric K); dissipated [u'; theta']^T D [u'; theta'].
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
             const auto v = t.numbers(key);
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
