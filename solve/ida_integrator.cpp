// SUNDIALS IDA: variable-order, variable-step BDF on the residual form F(t, y, y') = 0, with the KLU sparse
// direct solver and the colored finite-difference Jacobian (jacobian.hpp). Algebraic variables (multipliers)
// are excluded from the error test, as for index-2 systems (Brenan, Campbell and Petzold, Numerical Solution
// of Initial-Value Problems in DAEs, SIAM 1996, section 6.2).
// Contact events: IDA's root finding on the gaps of the contact elements (Model::gaps) locates each onset and
// release on the step's interpolant; the integration then restarts there (IDAReInit with the interpolated y,
// y': order 1, a fresh history), so the next steps do not extrapolate the smooth history across the kink of the
// contact force - the alternative, continuing on the old polynomial, is what made the error test reject
// thousands of steps at the impacts (bench/README.md, piston slap).
#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "solve/integrator.hpp"
#include "solve/jacobian.hpp"
#include "solve/newton_matrix_solver.hpp"
#include "solve/sundials_kernels.hpp"
#include "solve/split_integrator.hpp"

namespace nvh::solve {

std::unique_ptr<Integrator> make_generalized_alpha(const Model& model, const IntegratorSettings& s, double t0,
                                                   const Eigen::VectorXd& y0, const Eigen::VectorXd& yp0);

namespace {

using Clock = std::chrono::steady_clock;
double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

Eigen::Map<Eigen::VectorXd> view(N_Vector v) {
  return {N_VGetArrayPointer(v), static_cast<Eigen::Index>(N_VGetLength(v))};
}

class IdaIntegrator final : public Integrator {
 public:
  IdaIntegrator(const Model& model, const IntegratorSettings& s, double t0, const Eigen::VectorXd& y0,
                const Eigen::VectorXd& yp0)
      : model_(model), jacobian_(model, s.jacobian == "dense-fd"), analytic_(s.jacobian == "analytic"), t_(t0) {
    const sunindextype n = model.size();
    check(SUNContext_Create(nullptr, &ctx_), "SUNContext_Create");
    y_ = N_VNew_Serial(n, ctx_);
    yp_ = N_VNew_Serial(n, ctx_);
    work_ = N_VNew_Serial(n, ctx_);
    work2_ = N_VNew_Serial(n, ctx_);
    // Debian's SUNDIALS is built without optimization: IDA's vector arithmetic (every vector it clones from
    // y_) runs on this build's kernels instead (sundials_kernels.hpp).
    for (N_Vector v : {y_, yp_, work_, work2_}) use_fast_serial_kernels(v);
    view(y_) = y0;
    view(yp_) = yp0;
    mem_ = IDACreate(ctx_);
    check(IDAInit(mem_, &IdaIntegrator::residual, t0, y_, yp_), "IDAInit");
    check(IDASetUserData(mem_, this), "IDASetUserData");
    // Absolute tolerances: atol for coordinates and velocities; multiplier_atol for the multipliers, which
    // an index-2 system determines only to round-off / h (a tight atol on them stalls Newton's test).
    N_Vector id = N_VNew_Serial(n, ctx_);
    view(id) = model.error_test_mask();  // the energy integrals stay out of the error test
    error_test_mask_ = view(id);
    error_test_steps_.assign(static_cast<std::size_t>(n), 0);
    N_Vector atol = N_VNew_Serial(n, ctx_);
    view(atol) = (view(id).array() > 0).select(Eigen::VectorXd::Constant(n, s.atol),
                                               Eigen::VectorXd::Constant(n, s.multiplier_atol));
    // The velocities may have their own (velocity_atol): a lightly damped stiff contact (a valve on its seat)
    // rings with amplitudes of nanometres but velocities above a position-sized atol, and the error test
    // would follow that ringing with microsecond steps (docs/scene-format.md, [integrator]). All velocity
    // unknowns alike: the bodies' and the elements' (a pushrod chain's masses ring the same way).
    if (s.velocity_atol > 0)
      view(atol) = (model.velocity_tolerance_mask().array() > 0)
                       .select(Eigen::VectorXd::Constant(n, s.velocity_atol), view(atol));
    check(IDASVtolerances(mem_, s.rtol, atol), "IDASVtolerances");
    N_VDestroy(atol);
    check(IDASetId(mem_, id), "IDASetId");
    N_VDestroy(id);
    check(IDASetSuppressAlg(mem_, SUNTRUE), "IDASetSuppressAlg");
    if (s.max_step > 0) check(IDASetMaxStep(mem_, s.max_step), "IDASetMaxStep");
    // IDA's own first-step estimate can be tiny on index-2 constraints, where Newton's matrix is conditioned
    // as 1/h^2: start at 1 us unless told otherwise (the error test shortens it if needed).
    const double h0 = s.initial_step > 0 ? s.initial_step : (model.constraint_equations() > 0 ? 1e-6 : 0.0);
    if (h0 > 0) check(IDASetInitStep(mem_, h0), "IDASetInitStep");
    check(IDASetMaxOrd(mem_, s.max_order), "IDASetMaxOrd");
    check(IDASetDeltaCjLSetup(mem_, s.jacobian_cj_change), "IDASetDeltaCjLSetup");
    check(IDASetMaxNumSteps(mem_, 100000000L), "IDASetMaxNumSteps");
    const auto& p = jacobian_.pattern();
    matrix_ = SUNSparseMatrix(n, n, std::max(1, p.nonzeros()), CSC_MAT, ctx_);
    use_fast_sparse_kernels(matrix_);
    sunindextype* colptr = SUNSparseMatrix_IndexPointers(matrix_);
    sunindextype* rowval = SUNSparseMatrix_IndexValues(matrix_);
    for (int c = 0; c <= n; ++c) colptr[c] = p.column_start[c];
    for (int k = 0; k < p.nonzeros(); ++k) rowval[k] = p.rows[k];
    newton_solver_ = choose_newton_solver(s.linear_solver, p.n, p.column_start, p.rows).kind;
    solver_ = make_newton_solver(newton_solver_, matrix_, ctx_);
    check(IDASetLinearSolver(mem_, solver_, matrix_), "IDASetLinearSolver");
    check(IDASetJacFn(mem_, &IdaIntegrator::jacobian), "IDASetJacFn");
    check(IDASetErrHandlerFn(mem_, &IdaIntegrator::quiet, this), "IDASetErrHandlerFn");
    if (s.events && model.gap_count() > 0) {
      gaps_ = model.gap_count();
      check(IDARootInit(mem_, gaps_, &IdaIntegrator::roots), "IDARootInit");
      check(IDASetNoInactiveRootWarn(mem_), "IDASetNoInactiveRootWarn");
      roots_found_.resize(gaps_);
    }
    h0_ = h0;
  }
  ~IdaIntegrator() override {
    IDAFree(&mem_);
    SUNLinSolFree(solver_);
    SUNMatDestroy(matrix_);
    for (N_Vector v : {y_, yp_, work_, work2_}) N_VDestroy(v);
    SUNContext_Free(&ctx_);
  }

  double advance(double t_target, double t_stop) override {
    check(IDASetStopTime(mem_, t_stop), "IDASetStopTime");
    const auto start = Clock::now();
    while (t_ < t_target) {
      // The restart at the last event waits until here: the samples before the event are interpolated on the
      // step that found it.
      if (restart_pending_) restart(t_stop);
      double tret = t_;
      const int flag = IDASolve(mem_, t_stop, &tret, y_, yp_, IDA_ONE_STEP);
      if (pending_) std::rethrow_exception(std::exchange(pending_, nullptr));
      if (flag < 0) fail(flag);
      t_ = tret;
      stepped_ = true;
      count_order();
      non_finite_.clear();  // a non-finite trial that IDA recovered from by a shorter step is no failure
      if (flag == IDA_ROOT_RETURN) {
        IDAGetRootInfo(mem_, roots_found_.data());
        for (int k = 0; k < gaps_; ++k)
          if (roots_found_[k] != 0) {
            ++events_;
            log_event({t_, k, roots_found_[k] < 0});
          }
        restart_pending_ = kRestartAtEvents;
      }
      if (flag == IDA_TSTOP_RETURN) break;
      // A signal: return before the target; the caller samples up to here and writes the checkpoint.
      if (interrupt_requested()) break;
    }
    cpu_total_ += seconds(Clock::now() - start);
    return t_;
  }

  void interpolate(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) const override {
    if (!stepped_) {  // before the first step: the initial state
      y = view(y_);
      yp = view(yp_);
      return;
    }
    if (IDAGetDky(mem_, t, 0, work_) < 0 || IDAGetDky(mem_, t, 1, work2_) < 0)
      throw Error("IDA: cannot interpolate at t = " + std::to_string(t));
    y = view(work_);
    yp = view(work2_);
  }
  double time() const override { return t_; }
  void state(Eigen::VectorXd& y, Eigen::VectorXd& yp) const override {
    y = view(y_);
    yp = view(yp_);
  }

  IntegratorStatistics statistics() const override {
    IntegratorStatistics s = counters();  // since the last restart
    s.steps += before_.steps;
    s.rejected_steps += before_.rejected_steps;
    s.newton_iterations += before_.newton_iterations;
    s.nonlinear_failures += before_.nonlinear_failures;
    s.jacobian_evaluations += before_.jacobian_evaluations;
    s.linear_solves = s.newton_iterations;
    s.residual_evaluations += before_.residual_evaluations + jacobian_.residual_evaluations();
    s.events = events_;
    s.steps_at_order = steps_at_order_;
    s.error_test_steps = error_test_steps_;
    int order = 0;
    IDAGetLastOrder(mem_, &order), s.last_order = order;
    IDAGetLastStep(mem_, &s.last_step);
    s.cpu_residual_s = cpu_residual_;
    s.cpu_jacobian_s = cpu_jacobian_;
    s.cpu_factorization_s = std::max(0.0, cpu_total_ - cpu_residual_ - cpu_jacobian_);
    s.linear_solver = to_string(newton_solver_);
    return s;
  }

 private:
  // Restart (IDAReInit) at each event. Measured against continuing on the old history (which takes exactly
  // the steps of a run without events): on the dropped ball of tests/solve/test_contact_events.cpp it halves the
  // rejected steps (12 against 24); on piston slap it changes them little (bench/README.md).
  static constexpr bool kRestartAtEvents = true;

  /// After IDASolve in one-step mode: if it took a step (a root found in the last step returns without a new
  /// one), count it at the order it was taken with.
  void count_order() {
    long n = 0;
    IDAGetNumSteps(mem_, &n);
    if (n <= steps_seen_) return;
    int order = 0;
    IDAGetLastOrder(mem_, &order);
    if (order >= 1 && order <= 5) steps_at_order_[order - 1] += n - steps_seen_;
    steps_seen_ = n;
    count_error_test_holder();
  }

  /// The unknown of the error test with the largest weighted local error estimate of the last step (or the
  /// failed attempt), -1 if IDA has none: 3 n operations.
  int largest_weighted_error() {
    if (IDAGetErrWeights(mem_, work_) < 0 || IDAGetEstLocalErrors(mem_, work2_) < 0) return -1;
    const double* weight = N_VGetArrayPointer(work_);
    const double* error = N_VGetArrayPointer(work2_);
    int best = -1;
    double largest = -1.0;
    for (int k = 0; k < static_cast<int>(error_test_steps_.size()); ++k)
      if (error_test_mask_[k] > 0)
        if (const double e = std::abs(error[k] * weight[k]); e > largest) largest = e, best = k;
    return best;
  }
  /// IntegratorStatistics::error_test_steps: the step just taken counts for its largest weighted error.
  void count_error_test_holder() {
    if (const int k = largest_weighted_error(); k >= 0) ++error_test_steps_[k];
  }

  /// IDA's counters, which IDAReInit resets.
  IntegratorStatistics counters() const {
    IntegratorStatistics s;
    long v = 0;
    IDAGetNumSteps(mem_, &v), s.steps = v;
    IDAGetNumErrTestFails(mem_, &v), s.rejected_steps = v;
    IDAGetNumNonlinSolvIters(mem_, &v), s.newton_iterations = v;
    IDAGetNumNonlinSolvConvFails(mem_, &v), s.nonlinear_failures = v;
    IDAGetNumJacEvals(mem_, &v), s.jacobian_evaluations = v;
    IDAGetNumResEvals(mem_, &v), s.residual_evaluations = v;
    return s;
  }

  /// Start afresh at the event (t_, y_, y'_): BDF order 1, the initial step of the start.
  void restart(double t_stop) {
    const IntegratorStatistics c = counters();
    before_.steps += c.steps;
    before_.rejected_steps += c.rejected_steps;
    before_.newton_iterations += c.newton_iterations;
    before_.nonlinear_failures += c.nonlinear_failures;
    before_.jacobian_evaluations += c.jacobian_evaluations;
    before_.residual_evaluations += c.residual_evaluations;
    check(IDAReInit(mem_, t_, y_, yp_), "IDAReInit");
    steps_seen_ = 0;
    if (h0_ > 0) check(IDASetInitStep(mem_, h0_), "IDASetInitStep");
    check(IDASetStopTime(mem_, t_stop), "IDASetStopTime");
    restart_pending_ = false;
    stepped_ = false;
  }

  static int roots(double t, N_Vector y, N_Vector yp, double* g, void* data) {
    auto* self = static_cast<IdaIntegrator*>(data);
    try {
      self->model_.gaps(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp), g);
    } catch (...) {
      self->pending_ = std::current_exception();
      return -1;
    }
    return 0;
  }

  static void check(int flag, const char* what) {
    if (flag < 0) throw Error(std::string("IDA: ") + what + " failed (flag " + std::to_string(flag) + ")");
  }
  static void quiet(int, const char*, const char*, char* msg, void* self) {
    static_cast<IdaIntegrator*>(self)->last_message_ = msg;
  }

  [[noreturn]] void fail(int flag) {
    // Which unknown dominates the weighted local error: name its owner (body, element state). Only the
    // unknowns of the error test count: IDA leaves the multipliers out (IDASetSuppressAlg), and their
    // estimates, known to round-off / h only, would otherwise name a joint in most steps (as the split
    // integrator's fail() already did).
    double t_now = t_;
    IDAGetCurrentTime(mem_, &t_now);
    std::string culprit;
    if (const int k = largest_weighted_error(); k >= 0) culprit = model_.explain_state(k);
    std::ostringstream msg;
    // The name is malloc'd by SUNDIALS (IDAGetReturnFlagName): freed here, it leaked on every failure.
    char* name = IDAGetReturnFlagName(flag);
    msg << "the integrator failed at t = " << t_now << " s (IDA flag " << flag << ": " << (name ? name : "?")
        << ")";
    std::free(name);
    // Non-finite forces or states are the cause whatever IDA reports (it cuts the step until it gives up).
    if (!non_finite_.empty()) msg << "; " << non_finite_;
    if (!culprit.empty()) msg << "; the largest weighted error is in " << culprit;
    if (!last_message_.empty()) msg << "; IDA says: " << last_message_;
    msg << ". Try a smaller max_step or tolerances, or check that element's parameters.";
    throw Error(msg.str());
  }

  /// Which element or state makes `what` non-finite at (t, y, y') (Model::non_finite_culprit), for fail().
  void note_non_finite(double t, N_Vector y, N_Vector yp, const char* what) {
    std::ostringstream msg;
    msg << what << " is not finite at t = " << t << " s";
    const std::string culprit = model_.non_finite_culprit(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp));
    if (!culprit.empty()) msg << ": " << culprit;
    non_finite_ = msg.str();
  }

  static int residual(double t, N_Vector y, N_Vector yp, N_Vector r, void* data) {
    auto* self = static_cast<IdaIntegrator*>(data);
    const auto start = Clock::now();
    try {
      self->model_.residual(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp), N_VGetArrayPointer(r));
    } catch (...) {
      self->pending_ = std::current_exception();
      return -1;
    }
    self->cpu_residual_ += seconds(Clock::now() - start);
    for (double v : view(r))
      if (!std::isfinite(v)) {  // recoverable: IDA cuts the step; kept for the message if it gives up
        self->note_non_finite(t, y, yp, "the residual");
        return 1;
      }
    return 0;
  }

  static int jacobian(double t, double cj, N_Vector y, N_Vector yp, N_Vector r, SUNMatrix j, void* data, N_Vector,
                      N_Vector, N_Vector) {
    auto* self = static_cast<IdaIntegrator*>(data);
    const auto start = Clock::now();
    try {
      if (self->analytic_) {
        self->model_.jacobian(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp), cj, self->values_);
      } else {
        double h = 0;
        IDAGetCurrentStep(self->mem_, &h);
        N_Vector ewt = N_VClone(y);
        IDAGetErrWeights(self->mem_, ewt);
        const Eigen::VectorXd weights = view(ewt);
        N_VDestroy(ewt);
        self->jacobian_.evaluate(t, view(y), view(yp), view(r), cj, h, weights, self->values_);
      }
      // IDA zeroes the matrix (SUNMatZero empties the column pointers too) before each call: rewrite the
      // pattern, then the values.
      const auto& p = self->jacobian_.pattern();
      sunindextype* colptr = SUNSparseMatrix_IndexPointers(j);
      sunindextype* rowval = SUNSparseMatrix_IndexValues(j);
      for (int c = 0; c <= p.n; ++c) colptr[c] = p.column_start[c];
      for (int k = 0; k < p.nonzeros(); ++k) rowval[k] = p.rows[k];
      std::copy(self->values_.begin(), self->values_.end(), SUNSparseMatrix_Data(j));
      for (int c = 0; c < p.n; ++c)
        for (int k = p.column_start[c]; k < p.column_start[c + 1]; ++k)
          if (!std::isfinite(self->values_[k])) {  // the LU would fail on it unrecoverably: a shorter step
            // The entry names the element's bodies even where the residual there is finite (a film that
            // converged from one start and not from another).
            const std::string what = "the Jacobian (first non-finite entry: the equation of " +
                                     self->model_.describe_state(p.rows[k]) + ", by " +
                                     self->model_.describe_state(c) + ")";
            self->note_non_finite(t, y, yp, what.c_str());
            return 1;
          }
    } catch (...) {
      self->pending_ = std::current_exception();
      return -1;
    }
    self->cpu_jacobian_ += seconds(Clock::now() - start);
    return 0;
  }

  const Model& model_;
  ColoredJacobian jacobian_;
  bool analytic_;
  NewtonSolver newton_solver_ = NewtonSolver::kKlu;
  SUNContext ctx_ = nullptr;
  void* mem_ = nullptr;
  N_Vector y_ = nullptr, yp_ = nullptr, work_ = nullptr, work2_ = nullptr;
  SUNMatrix matrix_ = nullptr;
  SUNLinearSolver solver_ = nullptr;
  std::vector<double> values_;
  double t_;
  bool stepped_ = false;
  int gaps_ = 0;                  // root functions (0: events off or no contacts)
  std::vector<int> roots_found_;
  bool restart_pending_ = false;
  long events_ = 0;
  double h0_ = 0;
  IntegratorStatistics before_;   // IDA's counters summed over the restarts
  std::array<long, 5> steps_at_order_{};  // accepted steps per BDF order, over the restarts
  Eigen::VectorXd error_test_mask_;       // Model::error_test_mask(): 1 where the error test looks
  std::vector<long> error_test_steps_;    // per unknown: the steps it held the error test (over the restarts)
  long steps_seen_ = 0;                   // IDAGetNumSteps at the last count (since the last restart)
  double cpu_residual_ = 0, cpu_jacobian_ = 0, cpu_total_ = 0;
  std::exception_ptr pending_;
  std::string last_message_;
  std::string non_finite_;  // the last non-finite residual or Jacobian since the last step (fail())
};

}  // namespace

std::unique_ptr<Integrator> make_integrator(const Model& model, const IntegratorSettings& s, double t0,
                                            const Eigen::VectorXd& y0, const Eigen::VectorXd& yp0) {
  if (s.method == "generalized-alpha") return make_generalized_alpha(model, s, t0, y0, yp0);
  if (s.method == "split") return make_split_integrator(model, s, t0, y0, yp0);
  return std::make_unique<IdaIntegrator>(model, s, t0, y0, yp0);
}

}  // namespace nvh::solve
