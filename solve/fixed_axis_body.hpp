#pragma once
// Rigid bodies on a fixed axis of the ground, in one coordinate each: the slider (a valve in its guide, a
// tappet in its bore, a crosshead) translates along the axis, the rotor (a rocker on its shaft, a camshaft, a
// crank, a flywheel) turns about it.
//
// Why. A rigid body jointed to the ground by a prismatic or revolute joint carries 13 states (7 positions, 6
// velocities) and the joint 10 (five equations at the velocity and the position level, each with its
// multiplier): 23 unknowns for one degree of freedom, and dense 13 x 13 blocks and constraint rows in IDA's
// Newton matrix. A valvetrain is mostly such bodies: with them as sliders and rotors the single-valve scene
// falls from 114 to 30 unknowns and its Newton matrix from 3,952 stored entries to 290, and runs 2.4 times
// faster (bench/README.md "IDA's vector kernels and KLU, and bodies on a fixed axis"). The relative-coordinate
// (joint-coordinate) formulation of Simpack and of Simbody's mobilizers, for the bodies whose joint is to the
// ground.
//
// Coordinates (SI): q = [s] (m) or [theta] (rad), w = [s'] or [theta']; the kinematic row s' - w = 0. The
// equation of motion is Lagrange's for the one coordinate (Shabana, Dynamics of Multibody Systems, 4th ed.,
// section 5.3): M w' = Q + Q_gravity with Q = Jv^T F + Jw^T T of every force and reaction at a marker.
//   slider: r(s) = r0 + s a, axes fixed (A0); Jv = a, Jw = 0; M = m.
//   rotor:  A(theta) = R(a, theta) A0 about the axis a through the pivot c; a point at d0 from c at theta = 0
//           is at c + R d0; Jv = a x (R d0), Jw = a; M = a^T (A J A^T) a + m |a x (r - c)|^2 (constant).
// What the fixed axis does - the support's reaction, which a joint would report as its multiplier - is not an
// unknown here; `support_wrench` gives it from the body's Newton-Euler equations and the wrenches acting on
// it (solve writes it as /bodies/NAME/support_force and support_torque).
#include "solve/body.hpp"

namespace nvh::solve {

/// The wrench (global axes, N and N m) the fixed axis exerts on a body, at the body's support point (the
/// rotor's pivot, the slider's reference point), from the resultant of every other force on it: m a_cm =
/// F_applied + m g + F_support, dH_cm/dt = T_applied + T_support (about the centre of mass).
struct SupportWrench {
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();
};

/// A body of one coordinate on a fixed axis of the ground (the slider and the rotor below).
class FixedAxisBody : public Body {
 public:
  FixedAxisBody(std::string name, double mass, const Mat3& inertia_cm, const Vec3& axis, const Vec3& support,
                InitialState init)
      : Body(std::move(name)),
        mass_(mass),
        inertia_(inertia_cm),
        axis_(axis.normalized()),
        support_(support),
        init_(init) {}

  int position_count() const override { return 1; }
  int velocity_count() const override { return 1; }
  Eigen::VectorXd initial_positions() const override { return Eigen::VectorXd::Zero(1); }
  void kinematic_residual(std::span<const double> q, std::span<const double> qdot,
                          std::span<const double> w_eff, std::span<const double> alg, std::span<double> rows,
                          std::span<double> alg_rows) const override;
  Eigen::VectorXd position_rates(std::span<const double> q, std::span<const double> w) const override;
  void kinematic_jacobian(std::span<const double> q, std::span<const double> w_eff,
                          Eigen::Ref<Eigen::MatrixXd> d_q, Eigen::Ref<Eigen::MatrixXd> d_w) const override;
  using Body::marker_jacobian;
  using Body::mass_matrix;  // the allocating overloads, hidden otherwise

  double mass() const { return mass_; }
  const Vec3& axis() const { return axis_; }  // unit, global
  const Vec3& support_point() const {
    return support_;
  }  // global: the pivot, or the reference point at s = 0
  /// The reaction of the fixed axis at the support point, given the resultant of every other force on the
  /// body (gravity excluded: the body adds m g) as a force and a torque about the centre of mass, global
  /// axes.
  virtual SupportWrench support_wrench(std::span<const double> q, std::span<const double> w,
                                       std::span<const double> wdot, const Vec3& gravity, const Vec3& force,
                                       const Vec3& torque_about_cm) const = 0;
  /// Velocity of the centre of mass, global (output).
  virtual Vec3 reference_velocity(std::span<const double> q, std::span<const double> w) const = 0;

 protected:
  double mass_;
  Mat3 inertia_;  // kg m^2 about the centre of mass, body axes
  Vec3 axis_;
  Vec3 support_;
  InitialState init_;  // the pose at coordinate 0 (centre of mass, axes) and the rate along the axis
};

/// The slider: translates along `axis` (global); its axes keep their initial orientation. Reference point:
/// the centre of mass, at `init.position` for s = 0. The support wrench is the guide's side force and tilting
/// torque at the centre of mass (its component along the axis is zero up to the integration error).
class SliderBody final : public FixedAxisBody {
 public:
  SliderBody(std::string name, double mass, const Vec3& axis, InitialState init)
      : FixedAxisBody(std::move(name), mass, Mat3::Zero(), axis, init.position, init) {}
  std::string kind() const override { return "slider"; }
  std::string state_meaning(int r) const override { return r == 0 ? "travel s" : "speed s'"; }
  Eigen::VectorXd initial_velocities() const override;
  void inertia_residual(std::span<const double> q, std::span<const double> w, std::span<const double> wdot,
                        const Vec3& gravity, std::span<double> rows) const override;
  void mass_matrix(std::span<const double> q, Eigen::Ref<Eigen::MatrixXd> m) const override;
  MarkerMotion marker_motion(int marker, std::span<const double> q, std::span<const double> w) const override;
  void marker_jacobian(int marker, std::span<const double> q, Eigen::Ref<Mat3X> jv,
                       Eigen::Ref<Mat3X> jw) const override;
  void marker_twist(int marker, std::span<const double> q, std::span<const double> w, Vec3& velocity,
                    Vec3& angular_velocity) const override;
  Vec3 marker_acceleration(int marker, std::span<const double> q, std::span<const double> w,
                           std::span<const double> wdot) const override;
  Vec3 reference_position(std::span<const double> q) const override;
  Mat3 rotation(std::span<const double>) const override { return init_.orientation; }
  double kinetic_energy(std::span<const double> q, std::span<const double> w) const override;
  double potential_energy(std::span<const double> q, const Vec3& gravity) const override;
  void add_wrench(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                  std::span<double> generalized) const override;
  void marker_sensitivity(int marker, std::span<const double> q, std::span<const double> w,
                          Eigen::Ref<Eigen::MatrixXd> out) const override;
  void add_wrench_derivative(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                             Eigen::Ref<Eigen::MatrixXd> out) const override;
  void inertia_jacobian(std::span<const double> q, std::span<const double> w, std::span<const double> wdot,
                        const Vec3& gravity, Eigen::Ref<Eigen::MatrixXd> d_q,
                        Eigen::Ref<Eigen::MatrixXd> d_w) const override;
  SupportWrench support_wrench(std::span<const double> q, std::span<const double> w,
                               std::span<const double> wdot, const Vec3& gravity, const Vec3& force,
                               const Vec3& torque_about_cm) const override;
  Vec3 reference_velocity(std::span<const double> q, std::span<const double> w) const override;
};

/// The rotor: turns about the axis through `pivot` along `axis` (global, right-handed). Reference point: the
/// centre of mass, at `init.position` with axes `init.orientation` for theta = 0. The support wrench is the
/// bearing's force and its moment perpendicular to the axis, at the pivot (its moment about the axis is zero
/// up to the integration error).
class RotorBody final : public FixedAxisBody {
 public:
  RotorBody(std::string name, double mass, const Mat3& inertia_cm, const Vec3& axis, const Vec3& pivot,
            InitialState init);
  std::string kind() const override { return "rotor"; }
  std::string state_meaning(int r) const override { return r == 0 ? "angle theta" : "angular speed theta'"; }
  Eigen::VectorXd initial_velocities() const override;
  void inertia_residual(std::span<const double> q, std::span<const double> w, std::span<const double> wdot,
                        const Vec3& gravity, std::span<double> rows) const override;
  void mass_matrix(std::span<const double> q, Eigen::Ref<Eigen::MatrixXd> m) const override;
  MarkerMotion marker_motion(int marker, std::span<const double> q, std::span<const double> w) const override;
  void marker_jacobian(int marker, std::span<const double> q, Eigen::Ref<Mat3X> jv,
                       Eigen::Ref<Mat3X> jw) const override;
  void marker_twist(int marker, std::span<const double> q, std::span<const double> w, Vec3& velocity,
                    Vec3& angular_velocity) const override;
  Vec3 marker_acceleration(int marker, std::span<const double> q, std::span<const double> w,
                           std::span<const double> wdot) const override;
  Vec3 reference_position(std::span<const double> q) const override;
  Mat3 rotation(std::span<const double> q) const override;
  double kinetic_energy(std::span<const double> q, std::span<const double> w) const override;
  double potential_energy(std::span<const double> q, const Vec3& gravity) const override;
  void add_wrench(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                  std::span<double> generalized) const override;
  void marker_sensitivity(int marker, std::span<const double> q, std::span<const double> w,
                          Eigen::Ref<Eigen::MatrixXd> out) const override;
  void add_wrench_derivative(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                             Eigen::Ref<Eigen::MatrixXd> out) const override;
  void inertia_jacobian(std::span<const double> q, std::span<const double> w, std::span<const double> wdot,
                        const Vec3& gravity, Eigen::Ref<Eigen::MatrixXd> d_q,
                        Eigen::Ref<Eigen::MatrixXd> d_w) const override;
  SupportWrench support_wrench(std::span<const double> q, std::span<const double> w,
                               std::span<const double> wdot, const Vec3& gravity, const Vec3& force,
                               const Vec3& torque_about_cm) const override;
  Vec3 reference_velocity(std::span<const double> q, std::span<const double> w) const override;
  /// kg m^2: the moment of inertia about the axis.
  double axial_inertia() const { return axial_inertia_; }

 private:
  Mat3 turn(double theta) const;  // R(a, theta)
  /// The offset from the pivot at theta = 0 (global) of a marker, or of the centre of mass (marker -1).
  Vec3 offset0(int marker) const;
  double axial_inertia_;
};

}  // namespace nvh::solve
