#pragma once
// The force elements of a scene (each documented in docs/scene-format.md with its equation).
#include <Eigen/Dense>

#include "solve/force_element.hpp"
#include "solve/table.hpp"

namespace nvh::solve {

/// Point-to-point spring-damper along the line from marker j to marker i (engine paper, eq. 8):
///   f = k(dx) dx + d(dx) dx',  dx = |p_i - p_j| - free_length,
/// linear: k = k0, d = d0; non-linear (eq. 9-10 as implemented here): k = k0 + kB (dx/xB)^2,
/// d = d0 + dB (dx/xB)^2. Tension positive; body i is pulled towards j.
class SpringDamper final : public ForceElement {
 public:
  struct Parameters {
    double k0 = 0, d0 = 0;               // N/m, N s/m
    double kb = 0, db = 0, xb = 1.0;     // non-linear parts and reference length (m)
    double free_length = 0;              // m
    double preload = 0;                  // N (tension at dx = 0)
  };
  explicit SpringDamper(Parameters p) : p_(p) {}
  std::string type() const override { return "spring-damper"; }
  ElementForce evaluate(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j) const override;
  std::vector<std::string> channel_names() const override { return {"deflection_m", "deflection_rate_m_s", "tension_n"}; }
  void channels(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j, std::span<double> out) const override;

 private:
  Parameters p_;
};

/// 6-DOF bushing: relative displacement and small rotation of marker i against marker j in j's axes,
///   [F; T]_j = -K [u; theta] - D [u'; theta'] (+ preload), applied at marker i; theta from the
///   relative rotation's axis-angle vector (small angles in practice).
class Bushing final : public ForceElement {
 public:
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  Bushing(Matrix6 stiffness, Matrix6 damping) : k_(std::move(stiffness)), d_(std::move(damping)) {}
  std::string type() const override { return "bushing"; }
  ElementForce evaluate(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j) const override;

 private:
  Matrix6 k_, d_;
};

/// Torsional spring-damper about marker j's z axis (shaft couplings): T = -k (phi - phi0) - d phi',
/// phi the relative rotation of i about z_j (rad), on body i.
class TorsionalSpringDamper final : public ForceElement {
 public:
  TorsionalSpringDamper(double k, double d, double phi0) : k_(k), d_(d), phi0_(phi0) {}
  std::string type() const override { return "torsional-spring-damper"; }
  ElementForce evaluate(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j) const override;
  std::vector<std::string> channel_names() const override { return {"twist_rad"}; }
  void channels(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j, std::span<double> out) const override;

 private:
  double k_, d_, phi0_;
};

/// Unilateral contact of marker i's origin against the plane through marker j normal to z_j (pointing out of j's
/// material), with clearance: gap = z_j . (p_i - p_j) + clearance, penetration delta = -gap (> 0 in contact).
/// With the markers at the nominal (line-to-line) geometry, `clearance` is the free play. Normal force (Hunt & Crossley, J. Appl.
/// Mech. 42, 1975, eq. 5):  fn = k delta^n (1 + alpha delta'),  alpha = 3 (1 - e) / (2 v_ref),
/// never pulling (fn >= 0). Regularized Coulomb friction in the plane: ft = -mu(|vt|) fn vt/|vt| with
/// mu = mu_d + (mu_s - mu_d) exp(-(|vt|/v_s)^2) times tanh(|vt|/v_eps) (a smooth stick-slip law).
class Contact final : public ForceElement {
 public:
  struct Parameters {
    double stiffness = 0;       // N/m^n
    double exponent = 1.5;      // Hertz: 1.5 for sphere on plane, 1 for a linear penalty
    double restitution = 1.0;   // e at the reference impact speed
    double reference_speed = 1.0;  // m/s, the impact speed for which alpha gives e (Hunt-Crossley: alpha fixed)
    double clearance = 0;       // m
    double mu_static = 0, mu_dynamic = 0;  // friction coefficients
    double stribeck_speed = 0.01;          // m/s
    double regularization_speed = 1e-4;    // m/s
  };
  explicit Contact(Parameters p) : p_(p) {}
  std::string type() const override { return "contact"; }
  ElementForce evaluate(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j) const override;
  std::vector<std::string> channel_names() const override { return {"gap_m", "normal_force_n", "slip_speed_m_s"}; }
  void channels(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j, std::span<double> out) const override;
  /// alpha of the Hunt-Crossley law (s/m).
  double alpha() const { return 3.0 * (1.0 - p_.restitution) / (2.0 * p_.reference_speed); }

 private:
  Parameters p_;
};

/// A force along z_j on i from a table of the deflection along z_j: f = table(z_j . (p_i - p_j)) (N),
/// e.g. a measured mount or spring characteristic.
class TableForce final : public ForceElement {
 public:
  explicit TableForce(Table1D force_of_deflection) : table_(std::move(force_of_deflection)) {}
  std::string type() const override { return "table-force"; }
  ElementForce evaluate(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j) const override;

 private:
  Table1D table_;
};

/// A motor torque-speed curve: torque about z_j on i (and the reaction on j, the stator) from a table of
/// torque (N m) against the relative speed in rpm, e.g. an induction motor's characteristic.
class MotorTorque final : public ForceElement {
 public:
  explicit MotorTorque(Table1D torque_of_rpm) : table_(std::move(torque_of_rpm)) {}
  std::string type() const override { return "motor"; }
  ElementForce evaluate(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j) const override;
  std::vector<std::string> channel_names() const override { return {"speed_rpm", "torque_nm"}; }
  void channels(const ForceContext&, const MarkerMotion& i, const MarkerMotion& j, std::span<double> out) const override;

 private:
  Table1D table_;
};

/// A load on one marker: a force or a torque along a fixed direction (global, or the marker's axes) whose
/// magnitude is scale * table(x), x the time (s) or the crank angle (deg, periodic over `period_deg`,
/// shifted by a firing offset): a cylinder pressure curve times a piston area.
class TableLoad final : public ForceElement {
 public:
  enum class Abscissa { kTime, kCrankAngle };
  struct Parameters {
    bool torque = false;
    Vec3 direction = Vec3::UnitZ();
    bool marker_axes = false;
    Abscissa abscissa = Abscissa::kTime;
    double scale = 1.0;
    double offset_deg = 0.0;  // the load at crank angle a is table(a - offset)
  };
  TableLoad(Table1D table, Parameters p) : table_(std::move(table)), p_(p) {}
  std::string type() const override { return p_.torque ? "torque-load" : "force-load"; }
  ElementForce evaluate(const ForceContext& c, const MarkerMotion& i, const MarkerMotion& j) const override;
  std::vector<std::string> channel_names() const override { return {"magnitude"}; }
  void channels(const ForceContext& c, const MarkerMotion& i, const MarkerMotion& j, std::span<double> out) const override;
  double magnitude(const ForceContext& c) const;

 private:
  Table1D table_;
  Parameters p_;
};

/// A harmonic load on one marker: amplitude * sin(2 pi f t + phase) along a fixed direction (global, or the
/// marker's axes); a force (N) or a torque (N m). For frequency responses and verification.
class HarmonicLoad final : public ForceElement {
 public:
  struct Parameters {
    bool torque = false;
    Vec3 direction = Vec3::UnitZ();
    bool marker_axes = false;
    double amplitude = 0, frequency_hz = 0, phase_rad = 0;
  };
  explicit HarmonicLoad(Parameters p) : p_(p) {}
  std::string type() const override { return p_.torque ? "harmonic-torque" : "harmonic-force"; }
  ElementForce evaluate(const ForceContext& c, const MarkerMotion& i, const MarkerMotion& j) const override;

 private:
  Parameters p_;
};

}  // namespace nvh::solve
