#pragma once
// Ideal joints and prescribed motions as algebraic constraints between two markers i and j.
//
// A constraint of m equations gives its position-level residual Phi (m), and its velocity-level form
//   d Phi/dt = Di [v_i; omega_i] + Dj [v_j; omega_j] + Phi_t
// in terms of the two markers' velocities and angular velocities (global axes). The model maps Di, Dj onto
// the bodies' velocity coordinates through the marker Jacobians (body.hpp): C = Di [Jv_i; Jw_i] + ...
//
// Joints are built from the classic primitives (Haug, Computer-Aided Kinematics and Dynamics of Mechanical
// Systems, Allyn and Bacon 1989, section 9.2; Nikravesh 1988, chapter 7):
//   point:   p_i - p_j = 0                         (3 equations)
//   dot-1:   a_i . b_j = 0                         (two axes stay perpendicular)
//   dot-2:   b_j . (p_i - p_j) = 0                 (the point of i stays in a plane of j)
//   in-line: dot-2 with b_j = x_j and y_j         (the point of i stays on the z axis of j; Haug's
//            point-on-line, the translational half of a cylindrical joint)
//   angle:   x_i . (cos(theta) y_j - sin(theta) x_j) = 0  (relative rotation about z equals theta(t))
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "solve/body.hpp"

namespace nvh::solve {

struct ConstraintEquations {
  Eigen::VectorXd phi;              // m
  Eigen::Matrix<double, Eigen::Dynamic, 6> di;  // m x 6 ([v; omega] of marker i)
  Eigen::Matrix<double, Eigen::Dynamic, 6> dj;
  Eigen::VectorXd phi_t;            // m

  explicit ConstraintEquations(int m)
      : phi(Eigen::VectorXd::Zero(m)), di(Eigen::MatrixXd::Zero(m, 6)), dj(Eigen::MatrixXd::Zero(m, 6)),
        phi_t(Eigen::VectorXd::Zero(m)) {}
};

class Constraint {
 public:
  virtual ~Constraint() = default;
  virtual std::string type() const = 0;
  /// True for a prescribed motion (phi_t != 0: a speed or lift driver), whose reaction does work on the
  /// system: the model counts its power lambda . phi_t in /energy/input.
  virtual bool is_driver() const { return false; }
  virtual int size() const = 0;
  /// Names of the equations, for the report of redundant ones (e.g. "point-x", "dot1(z_i,x_j)").
  virtual std::vector<std::string> equation_names() const = 0;
  virtual void evaluate(double t, const MarkerMotion& i, const MarkerMotion& j, ConstraintEquations& out) const = 0;
};

enum class JointType { kFixed, kRevolute, kSpherical, kPrismatic, kCylindrical, kInLine };

/// An ideal joint between marker frames i and j (axis: the markers' z). kInLine (point on line): the origin
/// of marker i stays on the z axis of marker j, x_j . d = y_j . d = 0 with d = p_i - p_j (2 equations); it
/// frees the sliding along z_j and all rotations (a piston's pin centre on its bore axis, docs/engine.md).
std::unique_ptr<Constraint> make_joint(JointType type);

/// Distance joint (a rigid massless link with a ball at each end, e.g. a rigid pushrod): |p_i - p_j| = L,
/// written (d.d - L^2) / (2 L) = 0 with d = p_i - p_j, smooth everywhere and in metres near the solution; its
/// multiplier is the link's force along d (N, positive pulling the markers together). 1 equation.
std::unique_ptr<Constraint> make_distance_joint(double length);

/// In-plane joint (point on plane: a closed sliding contact, e.g. a rocker's foot on a valve tip with the
/// lash taken up): the point of marker i keeps the distance `offset` (m) from the x-y plane of marker j,
/// z_j . (p_i - p_j) = offset (the dot-2 primitive). 1 equation.
std::unique_ptr<Constraint> make_in_plane_joint(double offset);

/// The relative rotation angle (rad) of marker i about marker j's z axis: atan2(x_i . y_j, x_i . x_j).
double relative_angle(const MarkerMotion& i, const MarkerMotion& j);

/// Prescribed relative rotation about the z axis of marker j: angle(t) = theta(t) (rad), with its rate.
/// Used by speed drivers (constant rpm or a run-up rpm(t)). Use with a revolute (or cylindrical) joint.
class AngleDriver final : public Constraint {
 public:
  /// theta(t) and theta'(t) in rad and rad/s.
  AngleDriver(std::function<double(double)> theta, std::function<double(double)> theta_rate)
      : theta_(std::move(theta)), rate_(std::move(theta_rate)) {}
  std::string type() const override { return "speed-driver"; }
  bool is_driver() const override { return true; }
  int size() const override { return 1; }
  std::vector<std::string> equation_names() const override { return {"angle"}; }
  void evaluate(double t, const MarkerMotion& i, const MarkerMotion& j, ConstraintEquations& out) const override;

 private:
  std::function<double(double)> theta_;
  std::function<double(double)> rate_;
};

/// Prescribed lift along the z axis of marker j (a kinematic cam, docs/valvetrain.md): the distance
///   z_j . (p_i - p_j) = offset + s(theta(t)),
/// s the lift of a cam profile against the cam angle theta(t) (rad), theta' its speed; the offset is the
/// initial distance minus the initial lift, so the start is consistent. Use with a prismatic joint (a lifter in
/// its bore) or on any body whose other motions are held.
class LiftDriver final : public Constraint {
 public:
  /// lift(theta) returns {s (m), s' (m/rad)}; theta(t) (rad) and its rate (rad/s).
  LiftDriver(std::function<std::pair<double, double>(double)> lift, std::function<double(double)> theta,
             std::function<double(double)> theta_rate, double offset)
      : lift_(std::move(lift)), theta_(std::move(theta)), rate_(std::move(theta_rate)), offset_(offset) {}
  std::string type() const override { return "lift-driver"; }
  bool is_driver() const override { return true; }
  int size() const override { return 1; }
  std::vector<std::string> equation_names() const override { return {"lift"}; }
  void evaluate(double t, const MarkerMotion& i, const MarkerMotion& j, ConstraintEquations& out) const override;

 private:
  std::function<std::pair<double, double>(double)> lift_;
  std::function<double(double)> theta_;
  std::function<double(double)> rate_;
  double offset_;
};

/// Prescribed displacement of marker i along the z axis of marker j against time (docs/scene-format.md
/// section 3, `type = "displacement"`): a shaker or a prescribed base motion, or a point of a driven body
/// whose position fixes its angle (the tip of a bar on a revolute joint: angle = asin(s / length)),
///   z_j . (p_i - p_j) = offset + s(t),                                                   (D1)
/// the equations of LiftDriver with the cam angle replaced by the time. `motion(t)` returns {s (m), s'
/// (m/s)}; `offset` (m) is the initial distance minus s(t0), so the start is consistent. 1 equation.
std::unique_ptr<Constraint> make_displacement_driver(std::function<std::pair<double, double>(double)> motion,
                                                     double offset);

}  // namespace nvh::solve
