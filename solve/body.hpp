#pragma once
// A body of the multibody system: its coordinates, its markers, its inertia.
//
// Coordinates per body (SI units): positions q (translation in m, Euler parameters, modal coordinates), velocities
// w (translational velocity of the reference point in global axes in m/s, angular velocity in BODY axes in rad/s,
// modal velocities), and algebraic multipliers (the Euler parameter normalization). The kinematic equations
// are q' = H(q) w; the equations of motion M(q) w' + h(q, w) = Q + Q_gravity - C^T lambda.
//
// A marker is a frame on a body (origin and axes). A body tells, for each marker, its motion in global axes and
// the Jacobians of the marker's velocity and angular velocity with respect to w:
//   v_marker = Jv w,  omega_marker = Jw w   (global axes).
// By virtual power, a force F and torque T (global) acting at the marker give the generalized force
//   Q = Jv^T F + Jw^T T,
// which is how every force element and constraint reaction enters the equations.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "solve/rotation.hpp"

namespace nvh::solve {

/// A marker's pose and motion in global axes.
struct MarkerMotion {
  Vec3 position = Vec3::Zero();
  Mat3 axes = Mat3::Identity();  // columns: the marker's x, y, z in global axes
  Vec3 velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
};

/// d(velocity)/dw and d(angular velocity)/dw of a marker: 3 x (body's velocity count), global axes.
struct MarkerJacobian {
  Mat3X jv;
  Mat3X jw;
  /// The same for a point rigidly attached to the marker at global offset d from its origin.
  MarkerJacobian shifted(const Vec3& d) const { return {jv - skew(d) * jw, jw}; }
};

/// The words for the first states of a floating frame, q = [r, p, ...], w = [v, omega, ...] (rigid and
/// flexible bodies): r-th position (0 <= r < 7) or velocity (0 <= r < 6) of the frame.
std::string frame_position_meaning(int r);
std::string frame_velocity_meaning(int r);

/// d/dq and d/dw of the kinematic rows r' - v, p' - 1/2 L(p)^T omega + beta (p.p - 1) p of a floating frame
/// (position, Euler parameters p, velocity, angular velocity omega in body axes): the first 7 rows of d_q
/// (nq columns) and d_w (nw columns); everything else zeroed. Rigid and flexible bodies share it.
void floating_frame_kinematic_jacobian(const Vec4& p, const Vec3& omega, double beta,
                                       Eigen::Ref<Eigen::MatrixXd> d_q, Eigen::Ref<Eigen::MatrixXd> d_w);

/// A marker as defined on the body, in the body's reference frame.
struct MarkerDefinition {
  std::string name;
  Vec3 position = Vec3::Zero();  // m, body axes, from the body reference point
  Mat3 axes = Mat3::Identity();  // columns x, y, z in body axes
  int node = -1;                 // flexible bodies: the superelement point it sits on
};

class Body {
 public:
  explicit Body(std::string name) : name_(std::move(name)) {}
  virtual ~Body() = default;

  const std::string& name() const { return name_; }
  virtual std::string kind() const = 0;

  virtual int position_count() const = 0;   // size of q
  virtual int velocity_count() const = 0;   // size of w
  virtual int algebraic_count() const { return 0; }  // multipliers owned by the body (normalization)
  int state_count() const { return position_count() + velocity_count() + algebraic_count(); }
  /// What the body's r-th state is, in words, for messages and the run's summary (q first, then w, then the
  /// multipliers): "velocity y", "modal velocity 15, 40.00 kHz". Empty if the body does not say.
  virtual std::string state_meaning(int) const { return {}; }

  /// Initial q and w (set by the scene), in the layout of this body.
  virtual Eigen::VectorXd initial_positions() const = 0;
  virtual Eigen::VectorXd initial_velocities() const = 0;

  /// Kinematic residual rows (size of q): q' - H(q) w_eff, and the algebraic rows (e.g. p.p - 1).
  /// `alg` are the body's algebraic variables; for Euler parameters the GGL form q' = H w_eff + p nu.
  virtual void kinematic_residual(std::span<const double> q, std::span<const double> qdot,
                                  std::span<const double> w_eff, std::span<const double> alg,
                                  std::span<double> rows, std::span<double> alg_rows) const = 0;
  /// q' = H(q) w for given w (consistent initial derivatives; projections).
  virtual Eigen::VectorXd position_rates(std::span<const double> q, std::span<const double> w) const = 0;

  /// Inertial rows (size of w): M(q) w' + h(q, w) - Q_gravity.
  virtual void inertia_residual(std::span<const double> q, std::span<const double> w,
                                std::span<const double> wdot, const Vec3& gravity,
                                std::span<double> rows) const = 0;
  /// The mass matrix M(q) (nw x nw) into `m`, without heap allocation (the model's Jacobian takes it per call).
  virtual void mass_matrix(std::span<const double> q, Eigen::Ref<Eigen::MatrixXd> m) const = 0;
  /// The same as a new matrix (consistent initial accelerations, energies, tests).
  Eigen::MatrixXd mass_matrix(std::span<const double> q) const {
    Eigen::MatrixXd m(velocity_count(), velocity_count());
    mass_matrix(q, m);
    return m;
  }

  /// Markers. Virtual for bodies that keep a second body's markers in step (flexible_rotor_body.hpp).
  virtual int add_marker(MarkerDefinition m) {
    markers_.push_back(std::move(m));
    return static_cast<int>(markers_.size()) - 1;
  }
  const std::vector<MarkerDefinition>& markers() const { return markers_; }
  int find_marker(const std::string& name) const;

  virtual MarkerMotion marker_motion(int marker, std::span<const double> q,
                                     std::span<const double> w) const = 0;
  /// d(marker velocity, angular velocity)/dw: Jv and Jw (3 x nw each) into the given blocks, without heap
  /// allocation.
  virtual void marker_jacobian(int marker, std::span<const double> q, Eigen::Ref<Mat3X> jv,
                               Eigen::Ref<Mat3X> jw) const = 0;
  /// The same as a new MarkerJacobian.
  MarkerJacobian marker_jacobian(int marker, std::span<const double> q) const {
    MarkerJacobian j{Mat3X(3, velocity_count()), Mat3X(3, velocity_count())};
    marker_jacobian(marker, q, j.jv, j.jw);
    return j;
  }
  /// [Jv w; Jw w]: the marker's velocity and angular velocity as the constraints' velocity rows use them
  /// (C w = D [Jv w; Jw w]; equal to marker_motion's on |p| = 1). Default: from marker_jacobian.
  virtual void marker_twist(int marker, std::span<const double> q, std::span<const double> w, Vec3& velocity,
                            Vec3& angular_velocity) const;
  /// The marker's acceleration (global, m/s^2) from the velocities w and their rates w' (output). Default:
  /// Jv w' + (dJv/dt) w, the second term by a central difference of Jv along q' = H w; the slider and the
  /// rotor give their closed forms.
  virtual Vec3 marker_acceleration(int marker, std::span<const double> q, std::span<const double> w,
                                   std::span<const double> wdot) const;

  /// Position of the body reference point and its rotation (output; identity where not defined).
  virtual Vec3 reference_position(std::span<const double> q) const = 0;
  virtual Mat3 rotation(std::span<const double> q) const = 0;
  /// Kinetic energy (tests, output).
  virtual double kinetic_energy(std::span<const double> q, std::span<const double> w) const = 0;
  /// Potential energy of gravity (-m g . r_cm) and elastic strain, J; power of structural damping, W.
  virtual double potential_energy(std::span<const double> q, const Vec3& gravity) const = 0;
  virtual double dissipated_power(std::span<const double>, std::span<const double>) const { return 0; }

  /// Q += Jv^T F + Jw^T T: the generalized force (size of w) of a force F and torque T (global) at a marker's
  /// origin, by virtual power. The default forms the marker Jacobian; bodies override it without allocating.
  virtual void add_wrench(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                          std::span<double> generalized) const;

  // --- Derivatives for the analytic Jacobian of the model (model.hpp). The defaults differentiate the
  // functions above by local finite differences (this body alone); rigid bodies and point masses override
  // them with closed forms. The kinematic rows must have the form q' - f(q, w_eff).
  /// d[p; theta; v; omega]/dq of a marker at (q, w): 12 x nq, theta a small rotation of the marker frame in
  /// global axes (dA = theta~ A). The derivatives with respect to w are marker_jacobian's Jv and Jw.
  virtual void marker_sensitivity(int marker, std::span<const double> q, std::span<const double> w,
                                  Eigen::Ref<Eigen::MatrixXd> out) const;
  /// out += d(Jv^T F + Jw^T T)/dq at fixed F and T (nw x nq).
  virtual void add_wrench_derivative(int marker, std::span<const double> q, const Vec3& force,
                                     const Vec3& torque, Eigen::Ref<Eigen::MatrixXd> out) const;
  /// Kinematic rows q' - f(q, w_eff): d/dq (nq x nq) and d/dw_eff (nq x nw), written (not added).
  virtual void kinematic_jacobian(std::span<const double> q, std::span<const double> w_eff,
                                  Eigen::Ref<Eigen::MatrixXd> d_q, Eigen::Ref<Eigen::MatrixXd> d_w) const;
  /// Inertial rows M(q) w' + h(q, w) - Q_gravity: d/dq (nw x nq) and d/dw (nw x nw), written; d/dw' = M(q).
  virtual void inertia_jacobian(std::span<const double> q, std::span<const double> w,
                                std::span<const double> wdot, const Vec3& gravity, Eigen::Ref<Eigen::MatrixXd> d_q,
                                Eigen::Ref<Eigen::MatrixXd> d_w) const;

 private:
  std::string name_;
  std::vector<MarkerDefinition> markers_;
};

/// The fixed ground: no coordinates; markers never move.
class Ground final : public Body {
 public:
  using Body::Body;
  std::string kind() const override { return "ground"; }
  int position_count() const override { return 0; }
  int velocity_count() const override { return 0; }
  Eigen::VectorXd initial_positions() const override { return {}; }
  Eigen::VectorXd initial_velocities() const override { return {}; }
  void kinematic_residual(std::span<const double>, std::span<const double>, std::span<const double>,
                          std::span<const double>, std::span<double>, std::span<double>) const override {}
  Eigen::VectorXd position_rates(std::span<const double>, std::span<const double>) const override { return {}; }
  void inertia_residual(std::span<const double>, std::span<const double>, std::span<const double>,
                        const Vec3&, std::span<double>) const override {}
  using Body::mass_matrix;
  using Body::marker_jacobian;
  void mass_matrix(std::span<const double>, Eigen::Ref<Eigen::MatrixXd>) const override {}
  MarkerMotion marker_motion(int marker, std::span<const double>, std::span<const double>) const override;
  void marker_jacobian(int, std::span<const double>, Eigen::Ref<Mat3X>, Eigen::Ref<Mat3X>) const override {}
  Vec3 reference_position(std::span<const double>) const override { return Vec3::Zero(); }
  Mat3 rotation(std::span<const double>) const override { return Mat3::Identity(); }
  double kinetic_energy(std::span<const double>, std::span<const double>) const override { return 0; }
  double potential_energy(std::span<const double>, const Vec3&) const override { return 0; }
  void add_wrench(int, std::span<const double>, const Vec3&, const Vec3&, std::span<double>) const override {}
  void marker_twist(int, std::span<const double>, std::span<const double>, Vec3& v, Vec3& omega) const override {
    v.setZero(), omega.setZero();
  }
};

/// The kinematic rows of a floating frame, q = [r (3), p (4), ...], w = [v (3), omega_body (3), ...]:
/// r' - v and p' - 1/2 L(p)^T omega + beta (p.p - 1) p (rows 0..6). Shared by rigid and flexible bodies.
void frame_kinematic_residual(std::span<const double> q, std::span<const double> qdot,
                              std::span<const double> w_eff, double beta, std::span<double> rows);

/// Initial pose and motion of a body (global axes).
struct InitialState {
  Vec3 position = Vec3::Zero();            // m, of the reference point
  Mat3 orientation = Mat3::Identity();     // body -> global
  Vec3 velocity = Vec3::Zero();            // m/s
  Vec3 angular_velocity = Vec3::Zero();    // rad/s, global axes
};

/// A rigid body: reference point at the centre of mass; q = [r (3), p (4)], w = [v (3, global), omega (3, body)].
/// Euler parameter normalization by a stabilized kinematic equation p' = 1/2 L^T omega - beta (p.p - 1) p
/// (an algebraic multiplier for p.p = 1 would be an index-2 variable that spoils Newton's convergence test
/// at small steps; the invariant form keeps the exact solution and needs none).
class RigidBody final : public Body {
 public:
  RigidBody(std::string name, double mass, const Mat3& inertia_cm, InitialState init);
  std::string kind() const override { return "rigid"; }
  std::string state_meaning(int r) const override;
  int position_count() const override { return 7; }
  int velocity_count() const override { return 6; }
  Eigen::VectorXd initial_positions() const override;
  static constexpr double kNormalizationRate = 100.0;  // beta, 1/s
  Eigen::VectorXd initial_velocities() const override;
  void kinematic_residual(std::span<const double> q, std::span<const double> qdot,
                          std::span<const double> w_eff, std::span<const double> alg, std::span<double> rows,
                          std::span<double> alg_rows) const override;
  Eigen::VectorXd position_rates(std::span<const double> q, std::span<const double> w) const override;
  void inertia_residual(std::span<const double> q, std::span<const double> w, std::span<const double> wdot,
                        const Vec3& gravity, std::span<double> rows) const override;
  using Body::mass_matrix;      // the allocating overloads, hidden otherwise
  using Body::marker_jacobian;
  void mass_matrix(std::span<const double> q, Eigen::Ref<Eigen::MatrixXd> m) const override;
  MarkerMotion marker_motion(int marker, std::span<const double> q,
                             std::span<const double> w) const override;
  void marker_jacobian(int marker, std::span<const double> q, Eigen::Ref<Mat3X> jv,
                       Eigen::Ref<Mat3X> jw) const override;
  Vec3 reference_position(std::span<const double> q) const override;
  Mat3 rotation(std::span<const double> q) const override;
  double kinetic_energy(std::span<const double> q, std::span<const double> w) const override;
  double potential_energy(std::span<const double> q, const Vec3& gravity) const override;
  void add_wrench(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                  std::span<double> generalized) const override;
  void marker_twist(int marker, std::span<const double> q, std::span<const double> w, Vec3& velocity,
                    Vec3& angular_velocity) const override;
  Vec3 marker_acceleration(int marker, std::span<const double> q, std::span<const double> w,
                           std::span<const double> wdot) const override;
  void marker_sensitivity(int marker, std::span<const double> q, std::span<const double> w,
                          Eigen::Ref<Eigen::MatrixXd> out) const override;
  void add_wrench_derivative(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                             Eigen::Ref<Eigen::MatrixXd> out) const override;
  void kinematic_jacobian(std::span<const double> q, std::span<const double> w_eff, Eigen::Ref<Eigen::MatrixXd> d_q,
                          Eigen::Ref<Eigen::MatrixXd> d_w) const override;
  void inertia_jacobian(std::span<const double> q, std::span<const double> w, std::span<const double> wdot,
                        const Vec3& gravity, Eigen::Ref<Eigen::MatrixXd> d_q,
                        Eigen::Ref<Eigen::MatrixXd> d_w) const override;

  double mass() const { return mass_; }
  const Mat3& inertia() const { return inertia_; }

 private:
  double mass_;
  Mat3 inertia_;  // kg m^2 about the centre of mass, body axes
  InitialState init_;
};

/// A point mass (multi-mass chains): q = r (3), w = v (3); markers sit on the point, axes parallel to global.
class PointMass final : public Body {
 public:
  PointMass(std::string name, double mass, InitialState init);
  std::string kind() const override { return "point-mass"; }
  std::string state_meaning(int r) const override;
  int position_count() const override { return 3; }
  int velocity_count() const override { return 3; }
  Eigen::VectorXd initial_positions() const override;
  Eigen::VectorXd initial_velocities() const override;
  void kinematic_residual(std::span<const double> q, std::span<const double> qdot,
                          std::span<const double> w_eff, std::span<const double> alg, std::span<double> rows,
                          std::span<double> alg_rows) const override;
  Eigen::VectorXd position_rates(std::span<const double> q, std::span<const double> w) const override;
  void inertia_residual(std::span<const double> q, std::span<const double> w, std::span<const double> wdot,
                        const Vec3& gravity, std::span<double> rows) const override;
  using Body::mass_matrix;      // the allocating overloads, hidden otherwise
  using Body::marker_jacobian;
  void mass_matrix(std::span<const double> q, Eigen::Ref<Eigen::MatrixXd> m) const override;
  MarkerMotion marker_motion(int marker, std::span<const double> q,
                             std::span<const double> w) const override;
  void marker_jacobian(int marker, std::span<const double> q, Eigen::Ref<Mat3X> jv,
                       Eigen::Ref<Mat3X> jw) const override;
  Vec3 reference_position(std::span<const double> q) const override;
  Mat3 rotation(std::span<const double>) const override { return Mat3::Identity(); }
  double kinetic_energy(std::span<const double> q, std::span<const double> w) const override;
  double potential_energy(std::span<const double> q, const Vec3& gravity) const override;
  void add_wrench(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                  std::span<double> generalized) const override;
  void marker_twist(int marker, std::span<const double> q, std::span<const double> w, Vec3& velocity,
                    Vec3& angular_velocity) const override;
  void marker_sensitivity(int marker, std::span<const double> q, std::span<const double> w,
                          Eigen::Ref<Eigen::MatrixXd> out) const override;
  void add_wrench_derivative(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                             Eigen::Ref<Eigen::MatrixXd> out) const override;
  void kinematic_jacobian(std::span<const double> q, std::span<const double> w_eff, Eigen::Ref<Eigen::MatrixXd> d_q,
                          Eigen::Ref<Eigen::MatrixXd> d_w) const override;
  void inertia_jacobian(std::span<const double> q, std::span<const double> w, std::span<const double> wdot,
                        const Vec3& gravity, Eigen::Ref<Eigen::MatrixXd> d_q,
                        Eigen::Ref<Eigen::MatrixXd> d_w) const override;
  double mass() const { return mass_; }

 private:
  double mass_;
  InitialState init_;
};

}  // namespace nvh::solve
