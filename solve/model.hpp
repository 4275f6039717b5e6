#pragma once
// The multibody model: bodies, constraints (joints, drivers), force elements, a clock; the layout of the state
// vector y, the residual F(t, y, y') = 0 that both integrators solve, and its analytic Jacobian.
//
// State layout (the "stabilized index-2" form of Gear, Gupta and Leimkuhler, J. Comput. Appl. Math. 12, 1985):
//   y = [ body 1: q, w | body 2: ... | clock angle | element states z | energy: dissipated, input |
//         lambda (one per constraint equation) | mu (same) ]
// Residual rows:
//   kinematics    q' - H(q) (w - C^T mu)                      = 0   (per body)
//   dynamics      M(q) w' + h(q, w) - Q(t, q, w, z) + C^T lambda = 0   (per body)
//   clock         phi' - (omega_i - omega_j) . z_j             = 0
//   elements      r_e(t, markers, z, z')                       = 0   (their own rows)
//   energy        E_d' - P_dissipated,  W_in' - P_input         = 0   (integrals for the energy balance)
//   velocity      C(q) w + Phi_t                               = 0   (multiplier lambda)
//   position      Phi(q, t)                                    = 0   (multiplier mu)
// so that positions and velocities both satisfy the constraints, mu = 0 on the exact solution, and lambda are
// the reaction multipliers. Redundant equations (a planar linkage of revolute joints in 3D) are found at the
// start by a rank-revealing QR of C and removed: their rows become lambda_k = 0 and mu_k = 0.
//
// Jacobian (jacobian(): dF/dy + cj dF/dy', in the pattern of jacobian_pattern()): assembled from the bodies'
// own blocks and marker sensitivities (body.hpp) and each element's Jacobian by its markers' motion
// (force_element.hpp) through the chain rule; constraints' first derivatives are exact (their D matrices), the
// change of D with the markers' pose (d(C w)/dq, d(C^T lambda)/dq) is differentiated locally per constraint,
// and the radial direction of each floating body's Euler parameters (which scales A(p), rotation.hpp) by a
// forward difference of the residual, bodies sharing no row moved together.
// Two terms are left out by design: d(C^T mu)/dq in the kinematic rows (mu = 0 on the solution) and the energy
// rows' dependence on the state (the integrals feed nothing back). Not thread-safe: the residual and Jacobian
// use preallocated workspaces (no heap allocation per call for rigid bodies and point masses).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/log.hpp"
#include "solve/body.hpp"
#include "solve/constraint.hpp"
#include "solve/force_element.hpp"

namespace nvh::solve {

struct MarkerRef {
  int body = -1;
  int marker = -1;
};

struct ConstraintEntry {
  std::string name;
  std::unique_ptr<Constraint> constraint;
  MarkerRef i, j;
  int first_row = 0;          // index of its first equation among all constraint equations
  std::vector<char> active;   // per equation; redundant ones are 0
};

struct ForceEntry {
  std::string name;
  std::unique_ptr<ForceElement> element;
  std::vector<MarkerRef> markers;  // in the element's order (i, j for two-marker elements)
  int state_offset = 0;            // of its internal states in y (set by finalize)
  int state_count = 0;
  int gap_offset = 0;              // of its gaps among all gaps
};

struct ClockDefinition {
  MarkerRef i, j;            // crank angle = rotation of i about z_j
  double zero_angle = 0;     // rad: the crank angle at t = 0 is angle(i, j) - zero_angle
};

/// The sparsity pattern of dF/dy (and dF/dy'), compressed by columns.
struct SparsityPattern {
  int n = 0;
  std::vector<int> column_start;  // n + 1
  std::vector<int> rows;          // row indices, sorted within each column
  int nonzeros() const { return static_cast<int>(rows.size()); }
};

/// The terms of the energy balance (J): kinetic + potential + dissipated - input = its initial value.
struct EnergyBalance {
  double kinetic = 0;     // bodies
  double potential = 0;   // gravity, elastic strain of flexible bodies, energy stored in elements
  double dissipated = 0;  // integral of the dissipated power (elements, structural damping)
  double input = 0;       // integral of the power of sources (loads, motors) and of driven joints
};

class Model {
 public:
  Model();
  ~Model();
  Model(Model&&) noexcept;
  Model& operator=(Model&&) noexcept;

  Vec3 gravity = Vec3::Zero();
  std::vector<std::unique_ptr<Body>> bodies;
  std::vector<ConstraintEntry> constraints;
  std::vector<ForceEntry> forces;
  std::optional<ClockDefinition> clock;

  /// Assign the state layout. Call once after all bodies, constraints and forces are added.
  void finalize();

  int size() const { return size_; }
  int constraint_equations() const { return n_eq_; }
  int body_offset(int b) const { return body_offset_[b]; }
  int clock_index() const { return clock_index_; }
  int energy_offset() const { return energy_offset_; }
  int lambda_offset() const { return lambda_offset_; }
  int mu_offset() const { return mu_offset_; }
  int gap_count() const { return n_gaps_; }
  /// 1 for differential variables, 0 for algebraic ones (lambda, mu, algebraic element states).
  Eigen::VectorXd differential_mask() const;
  /// 1 for the variables in the integrators' error test: the differential ones less the energy integrals.
  Eigen::VectorXd error_test_mask() const;
  /// 1 on the bodies' velocity coordinates w, 0 elsewhere.
  Eigen::VectorXd velocity_mask() const;
  /// 1 on every velocity unknown - the bodies' w and the elements' velocity states (a mass chain's masses) -
  /// 0 elsewhere: where the integrators apply `velocity_atol`.
  Eigen::VectorXd velocity_tolerance_mask() const;
  /// Per state, a human-readable owner ("body crank: w[3]", "joint pin: lambda point-x") for messages.
  std::string describe_state(int k) const;
  /// describe_state with the state's meaning where its body gives one (Body::state_meaning):
  /// "body 'rocker' w[20] (modal velocity 15, 40.00 kHz)". For the run's summary and failure messages.
  std::string explain_state(int k) const;

  /// F(t, y, y').
  void residual(double t, const double* y, const double* yp, double* f) const;
  /// dF/dy + cj dF/dy' at (t, y, y'), in the order of jacobian_pattern()'s entries.
  void jacobian(double t, const double* y, const double* yp, double cj, std::vector<double>& values) const;
  /// When F(t, y, y') or the state is not finite: what makes it so, for the error message ("the state body
  /// 'crank' w[2] is inf", "force element 'mount' (maxwell) gives a non-finite force at marker 0"); empty if
  /// all is finite. Re-evaluates the contributions one by one, so it is called only once a residual was
  /// found non-finite (the integrators check the assembled residual, which costs nothing extra).
  std::string non_finite_culprit(double t, const double* y, const double* yp) const;
  /// The gaps of all contact elements (> 0 open): the integrators locate their sign changes.
  void gaps(double t, const double* y, const double* yp, double* out) const;

  /// Consistent initial y, y' at t0: positions projected onto Phi = 0, redundant equations found and
  /// deactivated (reported to `log`), velocities projected onto C w + Phi_t = 0, accelerations and lambda
  /// from the augmented system [M C^T; C 0], element states at their initial values.
  void consistent_initial_state(double t0, Eigen::VectorXd& y, Eigen::VectorXd& yp, const Logger& log);

  SparsityPattern jacobian_pattern() const;

  // --- kinematics and element values for output ---
  MarkerMotion marker_motion(const MarkerRef& m, const double* y) const;
  /// Marker acceleration (global) from y, y': Jv w' + d(Jv)/dt w (the latter by a directional difference).
  Vec3 marker_acceleration(const MarkerRef& m, const double* y, const double* yp) const;
  /// The input an element sees at (t, y, y'); `markers` is filled (sized by the caller or here).
  ElementInput element_input(const ForceEntry& f, double t, const double* y, const double* yp,
                             std::vector<MarkerMotion>& markers) const;
  /// Reaction force and torque (global) on body i of a constraint, at marker i, at time t (a driver's
  /// equation depends on it).
  void reaction(int c, double t, const double* y, Vec3& force, Vec3& torque) const;
  /// The clock's integrated angle state (rad): what crank-angle loads see (its column is in their Jacobian).
  /// Being an integral of the markers' relative angular velocity, it drifts by the integration error (a
  /// speed-driven flexible crank: 2e-3 deg after 10 cycles at rtol 1e-5).
  double crank_angle(const double* y) const { return clock_index_ >= 0 ? y[clock_index_] : 0.0; }
  /// The clock's angle as measured (rad): the markers' relative angle about z_j, less zero_deg, unwrapped to
  /// the revolution of the integrated state. Exact where the constraints hold (a speed driver's theta(t));
  /// what the results' crank_angle_deg, the end by angle and the steady state's cycles use.
  double clock_angle(const double* y) const;
  double total_kinetic_energy(const double* y) const;
  EnergyBalance energy(double t, const double* y, const double* yp) const;
  /// The resultant of every force element's and constraint's wrench on body b at (t, y, y'): a force and its
  /// torque about `point` (global axes, N and N m). Gravity is not included. Output only (it evaluates the
  /// elements acting on b again): the support reaction of a slider or rotor (fixed_axis_body.hpp).
  void applied_wrench(int b, double t, const double* y, const double* yp, const Vec3& point, Vec3& force,
                      Vec3& torque) const;
  /// Largest violation of the active position equations |Phi| (m or rad) and of the velocity equations
  /// |C w + Phi_t| (m/s or rad/s): the constraint drift.
  std::pair<double, double> constraint_violation(double t, const double* y) const;

  std::span<const double> positions(int b, const double* y) const;
  std::span<const double> velocities(int b, const double* y) const;

 private:
  struct Workspace;
  void constraint_matrix(double t, const double* y, Eigen::MatrixXd& c, Eigen::VectorXd& phi,
                         Eigen::VectorXd& phi_t) const;  // all equations, dense (start-up only)
  int velocity_offset(int b) const { return body_offset_[b] + bodies[b]->position_count(); }
  /// The body whose states hold unknown k (its q, w or multipliers), -1 if none.
  int body_of_state(int k) const;
  /// Wrenches (and state rows) of element f at (t, y, y'), into the workspace.
  void evaluate_element(std::size_t f, double t, const double* y, const double* yp, double* state_rows) const;
  /// Powers (W) of the element wrenches: dissipated, and the input of sources.
  void element_powers(double t, const double* y, const double* yp, double& dissipated, double& input) const;
  double driver_power(double t, const double* y) const;

  int size_ = 0;
  int n_eq_ = 0;
  int clock_index_ = -1;
  int energy_offset_ = 0;
  int lambda_offset_ = 0;
  int mu_offset_ = 0;
  int n_gaps_ = 0;
  std::vector<int> body_offset_;
  std::vector<int> w_global_offset_;  // offset of each body's w in the stacked velocity vector
  int n_w_ = 0;
  std::vector<std::vector<int>> radial_groups_;  // floating bodies whose Euler parameter columns share no row
  std::unique_ptr<Workspace> ws_;
};

}  // namespace nvh::solve
