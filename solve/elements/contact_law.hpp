#pragma once
// The point-against-plane contact law of one point, shared by `contact` (one point, contact.cpp),
// `valve-seat` (the law along the seat's axis, valve_seat.cpp) and `point-set-contact` (many points against
// one plane, point_set_contact.cpp).
//
// Point p (a marker's origin) against the plane through marker j normal to z_j (pointing out of j's material),
// with clearance: gap = z_j . (p - p_j) + clearance, penetration delta = -gap (> 0 in contact).
// Normal force (Hunt & Crossley, J. Appl. Mech. 42, 1975, eq. 5):  fn = k delta^n (1 + alpha delta'),
// alpha = 3 (1 - e) / (2 v_ref), never pulling (fn >= 0). Regularized Coulomb friction in the plane:
// ft = -mu(|vt|) fn vt/|vt|,  mu = (mu_d + (mu_s - mu_d) exp(-(|vt|/v_s)^2)) tanh(|vt|/v_eps) (smooth stick-slip).
// The force F = fn z_j + ft acts on p's body at p; j's body gets the reaction.
// Stored energy k delta^(n+1)/(n+1); dissipated: the damping part's power and the friction power.
#include <array>
#include <span>

#include "common/input.hpp"
#include "solve/force_element.hpp"

namespace nvh::solve::contact {

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

/// The keys of the law (for the registry's summary) and their reader (located errors).
inline constexpr const char* kKeys =
    "stiffness, exponent, restitution, reference_speed, clearance, mu_static, mu_dynamic, stribeck_speed, "
    "regularization_speed";
Parameters read_parameters(const input::Table& t);
/// Only the friction keys (mu_static, mu_dynamic, stribeck_speed, regularization_speed) into `p`: for an
/// element with its own normal law and the friction of this one (flat_face_cam.cpp).
void read_friction(const input::Table& t, Parameters& p);

/// The kinematics of a point against the plane.
struct State {
  double delta, delta_rate;  // penetration (m) and its rate (m/s)
  Vec3 n, vt;                // the plane's normal z_j, the slip velocity in the plane (m/s)
};

/// d(force on the point) (3 x 24): columns the point marker's 12 (dp, dtheta, dv, domega), then j's 12.
using PointJacobian = Eigen::Matrix<double, 3, 24>;

class Law {
 public:
  explicit Law(Parameters p) : p_(p) {}
  State state(const MarkerMotion& point, const MarkerMotion& j) const;
  double normal_force(const State& s) const;
  double mu(double slip_speed) const;
  /// d mu / d v: mu(v) is odd in v (tanh), so mu(v) fn is also the friction of a signed slip speed v.
  double mu_derivative(double slip_speed) const;
  /// The force on the point at its origin (N): fn n + ft, zero when open.
  Vec3 force(const State& s) const;
  /// dF by the point's and j's motion; false (df untouched) where there is no force (open, or the clamp fn = 0).
  bool jacobian(const MarkerMotion& point, const MarkerMotion& j, PointJacobian& df) const;
  /// Stored energy (J) and dissipated power (W).
  ElementEnergy energy(const State& s) const;
  /// The channels' values: gap (m), normal force (N), slip speed (m/s).
  std::array<double, 3> channel_values(const State& s) const { return {-s.delta, normal_force(s), s.vt.norm()}; }

 private:
  double alpha() const { return 3.0 * (1.0 - p_.restitution) / (2.0 * p_.reference_speed); }
  Parameters p_;
};

/// A force element that is one point on the law: marker i's origin against marker j's plane. Its force,
/// Jacobian, energy and contact event are the law's; an element derived from it adds its type and channels
/// (contact.cpp, valve_seat.cpp).
class PointElement : public ForceElement {
 public:
  explicit PointElement(Parameters p) : law_(p) {}
  int marker_count() const override { return 2; }
  State state(const ElementInput& in) const { return law_.state(in.markers[0], in.markers[1]); }
  void evaluate(const ElementInput& in, ElementOutput& out) const override;
  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override;
  ElementEnergy energy(const ElementInput& in) const override { return law_.energy(state(in)); }
  int gap_count() const override { return 1; }
  void gaps(const ElementInput& in, std::span<double> out) const override { out[0] = -state(in).delta; }

 protected:
  Law law_;
};

}  // namespace nvh::solve::contact
