#pragma once
// Time integrators behind one interface: both solve the model's residual F(t, y, y') = 0 (model.hpp).
#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "solve/model.hpp"

namespace nvh::solve {

struct IntegratorSettings {
  std::string method = "ida";  // "ida" (BDF, SUNDIALS), "generalized-alpha" or "split" (split_integrator.hpp)
  double rtol = 1e-6;
  double atol = 1e-8;
  double multiplier_atol = 1e-3;  // absolute tolerance of the multipliers (N, N m; index-2 variables)
  double velocity_atol = 0;       // of every velocity, bodies' and elements' (m/s, rad/s); 0: atol
  double max_step = 0;            // s, 0 = no limit
  double initial_step = 0;        // s, 0 = automatic
  int max_order = 5;              // IDA
  // IDA: a new Jacobian (and factorization) when cj = alpha/h has changed by more than this fraction since
  // the last one (IDASetDeltaCjLSetup; 0.25 is SUNDIALS' default). Between updates IDA scales the Newton
  // correction by 2/(1 + cj/cj_old); a larger value trades Jacobians for Newton iterations.
  double jacobian_cj_change = 0.25;
  double rho_inf = 0.8;  // generalized-alpha spectral radius at infinity
  double step = 1e-4;    // generalized-alpha step (s); adapted if `adaptive`
  bool adaptive = true;  // generalized-alpha: halve the step when Newton fails, grow it back
  // generalized-alpha: Newton stops when its estimated remaining error, in the weighted RMS norm of rtol |y| +
  // atol, is below this. IDA uses 0.33 behind its error test; generalized-alpha has none, and its joints
  // hold only to Newton's error, so a hundredth of the tolerance.
  double newton_tolerance = 0.01;
  // "analytic" (model.hpp), "colored-fd" (sparse differences) or "dense-fd"
  std::string jacobian = "analytic";
  // IDA's Newton matrix: "auto" (dense LU where the matrix is dense enough, else KLU), "klu" or "dense"
  // (newton_matrix_solver.hpp)
  std::string linear_solver = "auto";
  bool events = true;  // locate the sign changes of the contact gaps (Model::gaps) as step boundaries
  // method = "split" (split_integrator.hpp, docs/theory/split-integrator.md)
  double macro_step = 0;            // s: H, the exchange interval between the groups
  std::string exchange = "jacobi";  // "jacobi" or "gauss-seidel"
  int extrapolation = 1;            // degree (0, 1, 2) of the other groups' extrapolated motion
  bool coupling_correction = true;  // linearized partner response (the interface Jacobian)
  int iterations = 0;               // corrector passes of each macro step (waveform relaxation)
  // > 0: the macro step is chosen by the exchange's error estimate (S7), at most macro_step; the largest
  // exchange error allowed, in units of the inner error weights rtol |y| + atol. 0: H = macro_step fixed.
  double macro_tolerance = 0;
  std::vector<std::vector<std::string>> split_groups;  // body names to integrate in one group
};

/// A located sign change of a contact gap (Model::gaps): onset (open -> closed, the gap falls below 0) or
/// release. IDA finds it by its root finding on the gaps and restarts at it (order 1); generalized-alpha
/// finds it on its Hermite interpolant and redoes the step to end there.
struct ContactEvent {
  double time = 0;  // s
  int gap = 0;      // index among Model::gaps
  bool onset = true;
};

/// What the results file reports under /solver/statistics.
struct IntegratorStatistics {
  long steps = 0, rejected_steps = 0, newton_iterations = 0, jacobian_evaluations = 0, linear_solves = 0,
       residual_evaluations = 0, nonlinear_failures = 0;
  long events = 0;  // contact onsets and releases located (IntegratorSettings::events)
  int last_order = 0;
  double last_step = 0;
  // IDA: accepted steps taken at BDF order 1..5 (IDA picks the order itself, up to max_order); zeros for
  // generalized-alpha. Results: steps_at_order_1 .. steps_at_order_5.
  std::array<long, 5> steps_at_order{};
  // IDA and the split integrator's groups: per unknown of y, the accepted steps in which it had the largest
  // weighted local error estimate of the error test - the unknown that set the step size there. Empty where
  // not counted (generalized-alpha). Results: /solver/statistics/error_test_steps; the log names the leading
  // ones.
  std::vector<long> error_test_steps;
  // wall-clock seconds (steady_clock) in the residual, the Jacobian and the rest (results: wall_*_s)
  double cpu_residual_s = 0, cpu_jacobian_s = 0, cpu_factorization_s = 0;
  // the Newton matrix's factorization: "klu" or "dense" (IDA, newton_matrix_solver.hpp), "sparse-lu"
  // (generalized-alpha: Eigen's SparseLU); the split integrator lists its groups' ("klu+dense")
  std::string linear_solver;
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  /// Take internal steps until the time reaches at least t_target (never beyond t_stop); returns the time.
  /// Throws nvh::Error naming the time and the dominating residual's owner when a step cannot converge.
  virtual double advance(double t_target, double t_stop) = 0;
  /// y and y' at any time inside the last step (dense output).
  virtual void interpolate(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) const = 0;
  /// The current state (checkpoints).
  virtual double time() const = 0;
  virtual void state(Eigen::VectorXd& y, Eigen::VectorXd& yp) const = 0;
  virtual IntegratorStatistics statistics() const = 0;
  /// The located contact events in time order (the first kEventLogSize; statistics().events counts all).
  const std::vector<ContactEvent>& events() const { return event_log_; }
  static constexpr std::size_t kEventLogSize = 100000;

 protected:
  void log_event(const ContactEvent& e) {
    if (event_log_.size() < kEventLogSize) event_log_.push_back(e);
  }

 private:
  std::vector<ContactEvent> event_log_;
};

std::unique_ptr<Integrator> make_integrator(const Model& model, const IntegratorSettings& s, double t0,
                                            const Eigen::VectorXd& y0, const Eigen::VectorXd& yp0);

}  // namespace nvh::solve
