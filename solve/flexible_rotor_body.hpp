#pragma once
// A flexible body on a fixed axis of the ground: the superelement's frame turns about the axis in one
// coordinate, as the rigid rotor does (fixed_axis_body.hpp), and deforms in its modal coordinates. A rocker
// on its shaft, a cam lever on its pin, a flywheel or a fan on a rigid bearing.
//
// Why. A flexible body on a revolute joint to the ground carries a floating frame (7 positions, 6
// velocities) and the joint 10 unknowns (five equations at the velocity and the position level, each with its
// multiplier): 23 unknowns for one rigid degree of freedom. Here that degree of freedom is theta: q = [theta,
// eta], w = [theta', eta'], 2 (1 + n) unknowns instead of 2 n + 23, no joint to drift and no Euler parameter
// to normalize.
//
// The basis. The frame is attached to the body at the pivot (Shabana, Dynamics of Multibody Systems, 4th ed.
// 2020, section 6.5, the choice of the deformable body's reference conditions): its origin is the pivot on
// the axis and the elastic coordinates are those of the component clamped there, so that the material at the
// pivot neither leaves the axis nor tilts off it. A superelement condensed with the pivot fixed ([[fix]] at
// the pivot, all six DOF) has no rigid-body content; a free one would pin its frame, not its material, and
// is refused.
//
// Equations. With p(theta) = cos(theta/2) p0 + sin(theta/2) B(a_b) p0 the frame's Euler parameters (the
// solution of p' = 1/2 L(p)^T a_b theta', rotation.hpp's rate_matrix B) and a_b = A0^T a the axis in body
// axes (constant), the floating frame's coordinates are Q(q) = [c, p(theta), eta] and its velocities
// W = B w, the constant map B: v = 0, omega_body = a_b theta', eta' = eta'. The equations are the floating
// frame's (flexible_body.hpp, Shabana 2005 eq. 5.99-5.115) projected by virtual power:
//   B^T (M(Q) B w' + h(Q, B w) - Q_gravity + [0; 0; K eta + D eta'] - Q_forces) = 0,
// the Lagrange equations of the constrained coordinates (Shabana 2020 section 5.3; Kane's method). Every
// derivative is the floating frame's chained with B and dQ/dq = [0; dp/dtheta; 0 | 0; 0; I].
//
// The support. The axis's reaction is the part of the floating frame's equations that B^T drops: with the
// applied forces' resultant F and their moment T_c about the pivot (global),
//   F_support = R_r - F,  T_support = A R_omega - T_c,
// R_r, R_omega the frame rows of M W' + h - Q_gravity; its moment about the axis is zero up to the
// integration error (solve writes it as /bodies/NAME/support_force and support_torque).
#include "solve/fixed_axis_body.hpp"
#include "solve/flexible_body.hpp"

namespace nvh::solve {

class FlexibleRotorBody final : public Body {
 public:
  /// `frame` is the floating-frame body of the same superelement, placed at coordinate 0 (its position the
  /// pivot, on the axis; its velocities are not used: the initial rates are `speed` and the frame's modal
  /// velocities). `axis` is global; the axis passes through the frame's origin.
  FlexibleRotorBody(FlexibleBody frame, const Vec3& axis, double speed);

  std::string kind() const override { return "flexible-rotor"; }
  std::string state_meaning(int r) const override;
  int position_count() const override { return 1 + n_; }
  int velocity_count() const override { return 1 + n_; }
  Eigen::VectorXd initial_positions() const override;
  Eigen::VectorXd initial_velocities() const override;
  void kinematic_residual(std::span<const double> q, std::span<const double> qdot,
                          std::span<const double> w_eff, std::span<const double> alg, std::span<double> rows,
                          std::span<double> alg_rows) const override;
  Eigen::VectorXd position_rates(std::span<const double> q, std::span<const double> w) const override;
  void inertia_residual(std::span<const double> q, std::span<const double> w, std::span<const double> wdot,
                        const Vec3& gravity, std::span<double> rows) const override;
  using Body::marker_jacobian;
  using Body::mass_matrix;  // the allocating overloads, hidden otherwise
  void mass_matrix(std::span<const double> q, Eigen::Ref<Eigen::MatrixXd> m) const override;
  int add_marker(MarkerDefinition m) override;
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
  double dissipated_power(std::span<const double> q, std::span<const double> w) const override;
  void add_wrench(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                  std::span<double> generalized) const override;
  void marker_sensitivity(int marker, std::span<const double> q, std::span<const double> w,
                          Eigen::Ref<Eigen::MatrixXd> out) const override;
  void add_wrench_derivative(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                             Eigen::Ref<Eigen::MatrixXd> out) const override;
  void kinematic_jacobian(std::span<const double> q, std::span<const double> w_eff,
                          Eigen::Ref<Eigen::MatrixXd> d_q, Eigen::Ref<Eigen::MatrixXd> d_w) const override;
  void inertia_jacobian(std::span<const double> q, std::span<const double> w, std::span<const double> wdot,
                        const Vec3& gravity, Eigen::Ref<Eigen::MatrixXd> d_q,
                        Eigen::Ref<Eigen::MatrixXd> d_w) const override;

  /// The axis's reaction at the pivot (global, N and N m) from the resultant of every other force on the
  /// body: `force` and `torque_about_pivot` (gravity excluded: the body adds it). `wdot` = [theta'', eta''].
  SupportWrench support_wrench(std::span<const double> q, std::span<const double> w,
                               std::span<const double> wdot, const Vec3& gravity, const Vec3& force,
                               const Vec3& torque_about_pivot) const;

  const FlexibleBody& frame() const { return frame_; }
  const Vec3& axis() const { return axis_; }  // unit, global
  int modes() const { return n_; }
  /// The floating frame's Euler parameters at coordinate theta (output: /bodies/NAME/euler_parameters).
  Vec4 euler_parameters(double theta) const;

 private:
  /// The floating frame's coordinates Q(q), velocities B w and rates B w' into the workspace.
  void lift(std::span<const double> q) const;
  void lift_rates(std::span<const double> w, Eigen::VectorXd& out) const;
  Vec4 dp_dtheta(double theta) const;
  /// B^T X B (velocities by velocities) and B^T X dQ/dq (velocities by coordinates) of the floating frame's
  /// matrices, into the body's layout (flexible_rotor_body.cpp).
  void project_velocities(const Eigen::MatrixXd& x, Eigen::Ref<Eigen::MatrixXd> out) const;
  void project_positions(const Eigen::MatrixXd& x, double theta, Eigen::Ref<Eigen::MatrixXd> out,
                         bool add) const;

  FlexibleBody frame_;
  int n_;
  Vec3 axis_;     // global, unit
  Vec3 axis_b_;   // body axes (constant)
  Vec3 pivot_;    // the frame's origin, global
  Vec4 p0_;       // the frame's Euler parameters at theta = 0
  Vec4 bp0_;      // B(a_b) p0
  double speed_;  // rad/s at the start
  // Workspace in the floating frame's layout (7 + n positions, 6 + n velocities); not thread-safe, as the
  // model.
  mutable Eigen::VectorXd fq_, fw_, fwd_, rows_, gen_;
  mutable Eigen::MatrixXd fm_, fdq_, fdw_, sens_;
  mutable Mat3X jv_, jw_;
};

/// The floating-frame body of a flexible body: `body` itself, or the frame of one on a fixed axis; null for
/// any other body. Its data() are the superelement's as the scene uses them; its modal coordinates are the
/// last modes() of the body's positions either way.
const FlexibleBody* flexible_part(const Body& body);

/// Why a superelement cannot turn on a fixed axis through its frame's origin (empty if it can): it must
/// have no rigid-body content (condensed with the pivot fixed), and a point of it at the origin must not
/// move elastically.
std::string fixed_axis_basis_problem(const FlexibleData& data, const std::string& file);

}  // namespace nvh::solve
