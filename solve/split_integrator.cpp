// The body-wise partitioned integrator (split_integrator.hpp); the scheme and its equations are in
// docs/theory/split-integrator.md, numbered (S1)-(S6) there and referred to below.
//
// Over a macro step [T, T + H] each group g solves its own rows of the model's residual (model.hpp)
//   F_g(t, y_g, y_g', y_o(t), y_o'(t)) = 0                                                        (S1)
// for its own unknowns y_g, the other groups' unknowns y_o taken as known functions of time:
//   extrapolated from T, y_o(T + s) = y_o(T) + s y_o'(T) + s^2/2 a_o  (degree 0, 1 or 2)           (S2)
//   a_o = (y_o'(T) - y_o'(T - H_prev)) / H_prev,
// or, once group o has been advanced (Gauss-Seidel; every corrector pass), the piecewise cubic Hermite
// interpolant of (y_o, y_o') on the steps its IDA took (S3). Corrector passes stop when the end state changes
// by less than the tolerances (S4). With the coupling correction, the partners' unknowns in g's equations are
// yhat_o(t) + delta_o(t), integrated with g from delta_o(T) = 0 on the partners' rows linearized at the
// start:
//   R_o(s) + A_oo delta_o + B_oo delta_o' + A_og (y_g - yhat_g) + B_og (y_g' - yhat_g') = 0,        (S5)
//   A = dF/dy, B = dF/dy' at (T, y(T), y'(T)) (Model::jacobian at cj = 0 and 1),
//   R_o(s) = F_o(T) + s dF_o/dt along yhat (the predictor pass; 0 in corrector passes),
// yhat the linear extrapolation (predictor) or the previous pass (corrector): the partners respond, linearly,
// to g's motion - the interface Jacobian that keeps stiff couplings stable. Each group is its own SUNDIALS
// IDA instance, restarted (IDAReInit) at each macro step and pass from a consistent state (S6). With
// macro_tolerance the macro step is chosen by the exchange's error estimate (S7): the other groups' end
// states as each group saw them (extrapolated, linearized) against the states they reached.
#include "solve/split_integrator.hpp"

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_sparse.h>
#include <Eigen/SparseLU>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <limits>
#include <numeric>
#include <sstream>
#include <utility>

#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "solve/newton_matrix_solver.hpp"
#include "solve/sundials_kernels.hpp"

namespace nvh::solve {

// ------------------------------------------------------------------ partition

SplitPartition partition_model(const Model& model, const std::vector<std::vector<std::string>>& merge) {
  const int nb = static_cast<int>(model.bodies.size());
  auto moving = [&](int b) { return b >= 0 && b < nb && model.bodies[b]->state_count() > 0; };
  std::vector<int> parent(nb);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int b) {
    while (parent[b] != b) b = parent[b] = parent[parent[b]];
    return b;
  };
  auto unite = [&](int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  };
  for (const auto& c : model.constraints)
    if (moving(c.i.body) && moving(c.j.body)) unite(c.i.body, c.j.body);
  for (const auto& list : merge) {
    int first = -1;
    for (const auto& name : list) {
      int b = 0;
      while (b < nb && model.bodies[b]->name() != name) ++b;
      if (!moving(b)) throw Error("split group: no moving body '" + name + "'");
      if (first < 0) first = b;
      unite(first, b);
    }
  }
  SplitPartition p;
  std::vector<int> group_of_root(nb, -1), group_of_body(nb, -1);
  for (int b = 0; b < nb; ++b) {
    if (!moving(b)) continue;
    const int r = find(b);
    if (group_of_root[r] < 0) {
      group_of_root[r] = p.groups++;
      p.bodies.emplace_back();
    }
    group_of_body[b] = group_of_root[r];
    p.bodies[group_of_body[b]].push_back(model.bodies[b]->name());
  }
  if (p.groups == 0) {  // nothing moves: one group holds the rest (clock, elements)
    p.groups = 1;
    p.bodies.emplace_back();
  }
  auto group_of = [&](const MarkerRef& i, const MarkerRef& j) {
    if (moving(i.body)) return group_of_body[i.body];
    if (moving(j.body)) return group_of_body[j.body];
    return 0;
  };
  p.group_of_state.assign(model.size(), p.groups - 1);  // the energy integrals: the last group
  for (int b = 0; b < nb; ++b)
    for (int k = 0; k < model.bodies[b]->state_count(); ++k)
      p.group_of_state[model.body_offset(b) + k] = group_of_body[b];
  if (model.clock) p.group_of_state[model.clock_index()] = group_of(model.clock->i, model.clock->j);
  for (const auto& f : model.forces) {
    int g = 0;
    for (const auto& m : f.markers)
      if (moving(m.body)) {
        g = group_of_body[m.body];
        break;
      }
    for (int k = 0; k < f.state_count; ++k) p.group_of_state[f.state_offset + k] = g;
  }
  for (const auto& c : model.constraints) {
    const int g = group_of(c.i, c.j);
    for (int e = 0; e < c.constraint->size(); ++e) {
      p.group_of_state[model.lambda_offset() + c.first_row + e] = g;
      p.group_of_state[model.mu_offset() + c.first_row + e] = g;
    }
  }
  p.states.assign(p.groups, {});
  for (int k = 0; k < model.size(); ++k) p.states[p.group_of_state[k]].push_back(k);
  return p;
}

namespace {

using Clock = std::chrono::steady_clock;
double seconds(Clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

Eigen::Map<Eigen::VectorXd> view(N_Vector v) {
  return {N_VGetArrayPointer(v), static_cast<Eigen::Index>(N_VGetLength(v))};
}

void check(int flag, const char* what) {
  if (flag < 0)
    throw Error(std::string("split integrator: IDA ") + what + " failed (flag " + std::to_string(flag) + ")");
}

/// The motion of every unknown over the macro step, y(T + s) = c0 + s c1 + s^2 c2 + s^3 c3: (S2) or (S3).
struct Motion {
  Eigen::VectorXd c0, c1, c2, c3;
  void resize(int n) {
    for (auto* c : {&c0, &c1, &c2, &c3}) c->setZero(n);
  }
  void evaluate(double s, Eigen::VectorXd& y, Eigen::VectorXd& yp) const {
    y = c0 + s * (c1 + s * (c2 + s * c3));
    yp = c1 + s * (2 * c2 + 3 * s * c3);
  }
};

/// Piecewise cubic Hermite on the points a group's IDA stepped through in the last macro step (dense output).
struct Record {
  std::vector<double> t;
  std::vector<Eigen::VectorXd> y, yp;
  void clear() { t.clear(), y.clear(), yp.clear(); }
  void add(double time, const Eigen::Ref<const Eigen::VectorXd>& v,
           const Eigen::Ref<const Eigen::VectorXd>& vp) {
    t.push_back(time), y.emplace_back(v), yp.emplace_back(vp);
  }
  void interpolate(double time, Eigen::VectorXd& v, Eigen::VectorXd& vp) const {
    std::size_t k = std::upper_bound(t.begin(), t.end(), time) - t.begin();
    k = std::clamp<std::size_t>(k, 1, t.size() - 1);
    const double h = t[k] - t[k - 1], x = std::clamp((time - t[k - 1]) / h, 0.0, 1.0);
    const double h00 = (1 + 2 * x) * (1 - x) * (1 - x), h10 = x * (1 - x) * (1 - x),
                 h01 = x * x * (3 - 2 * x), h11 = x * x * (x - 1);
    v = h00 * y[k - 1] + h * h10 * yp[k - 1] + h01 * y[k] + h * h11 * yp[k];
    const double d00 = 6 * x * (x - 1) / h, d10 = (1 - x) * (1 - 3 * x), d01 = -d00, d11 = x * (3 * x - 2);
    vp = d00 * y[k - 1] + d10 * yp[k - 1] + d01 * y[k] + d11 * yp[k];
  }
};

class SplitIntegrator;

/// One group's IDA over its own unknowns (and, with the correction, its partners' deltas (S5)).
struct Group {
  SplitIntegrator* owner = nullptr;
  int id = 0;
  std::vector<int> own, partners;  // global unknowns: its own, and its partners' (the deltas)
  int m = 0;                       // own.size() + partners.size()
  // The sub-problem's Jacobian in CSC: each entry takes full-pattern entry `source`; `frozen`: a delta row
  // (A + cj B of the macro step's start) rather than the current dF/dy + cj dF/dy'.
  std::vector<sunindextype> column_start, rows;
  std::vector<int> source;
  std::vector<char> frozen;
  std::vector<int> local_row_of;  // global unknown -> local row (-1: not in the sub-problem)
  Eigen::VectorXd ref, refp, x, xp;
  SUNContext ctx = nullptr;
  void* mem = nullptr;
  N_Vector u = nullptr, up = nullptr, work = nullptr, work2 = nullptr;
  SUNMatrix matrix = nullptr;
  SUNLinearSolver solver = nullptr;
  double next_step = 0;   // the step IDA would have taken next at the last macro step's end
  Record record;          // this pass's steps (after the step: the last pass's, the dense output)
  Record previous;        // the previous pass's (corrector passes)
  Eigen::VectorXd seen;   // the whole state as this group saw it at the macro step's end (S7)
  Eigen::VectorXd reads;  // 1 for the other groups' differential unknowns its own equations read (S7)
  std::exception_ptr pending;
  std::string message, non_finite;
  ~Group() {
    if (mem) IDAFree(&mem);
    if (solver) SUNLinSolFree(solver);
    if (matrix) SUNMatDestroy(matrix);
    for (N_Vector v : {u, up, work, work2})
      if (v) N_VDestroy(v);
    if (ctx) SUNContext_Free(&ctx);
  }
};

/// A signal (SIGINT, SIGTERM) inside a macro step: it is abandoned (SplitIntegrator::advance).
struct Interrupted {};

/// A group's IDA failed or stalled inside a macro step: advance() retries it shorter (down to the macro
/// step / kMaxMacroStepCut), and reports the error only when the shortest fails too.
struct MacroStepFailure : Error {
  using Error::Error;
};
constexpr double kMaxMacroStepCut = 256;
/// A group's IDA is stalled when, after this many steps in one macro step, its step is below
/// kStalledStep x the macro step: measured on the valvetrain with a bridge (a group's linearized partners
/// across the lash's closing), 42,000 steps of 2e-11 s at t = 4.137 ms, a Jacobian and a Newton failure at
/// nearly every step, for 60 s without progress at a macro step of 0.5 ms.
constexpr long kStallSteps = 2000;
constexpr double kStalledStep = 1e-6;

class SplitIntegrator final : public Integrator {
 public:
  SplitIntegrator(const Model& model, const IntegratorSettings& s, double t0, const Eigen::VectorXd& y0,
                  const Eigen::VectorXd& yp0)
      : model_(model),
        s_(s),
        partition_(partition_model(model, s.split_groups)),
        pattern_(model.jacobian_pattern()),
        t_(t0),
        y_(y0),
        yp_(yp0),
        yp_before_(yp0) {
    if (!(s.macro_step > 0)) throw Error("split integrator: macro_step must be > 0 s");
    const int n = model.size();
    motion_.resize(n);
    source_.assign(partition_.groups, kExtrapolated);
    f_.setZero(n), f0_.setZero(n), g0_.setZero(n);
    mask_ = model.error_test_mask();
    stats_.error_test_steps.assign(static_cast<std::size_t>(model.size()), 0);
    atol_ =
        (mask_.array() > 0)
            .select(Eigen::VectorXd::Constant(n, s.atol), Eigen::VectorXd::Constant(n, s.multiplier_atol));
    if (s.velocity_atol > 0)
      atol_ = (model.velocity_tolerance_mask().array() > 0)
                  .select(Eigen::VectorXd::Constant(n, s.velocity_atol), atol_);
    gauss_seidel_ = s.exchange == "gauss-seidel";
    groups_.reserve(partition_.groups);
    for (int g = 0; g < partition_.groups; ++g) groups_.push_back(std::make_unique<Group>());
    for (int g = 0; g < partition_.groups; ++g) setup(*groups_[g], g);
  }

  // The macro step: s_.macro_step, cut by 4 when a group's IDA fails or stalls in it (the step is redone
  // from its start), grown back by 2 after each success. With macro_tolerance (S7) it follows the exchange's
  // error estimate instead: a step whose estimate exceeds the tolerance is redone shorter, and the next one
  // is scaled by 0.8 (tolerance / estimate)^(1/2), within a quarter and twice the last, at most macro_step,
  // at least macro_step / kMaxMacroStepCut (where the estimate no longer shrinks with H - at an impact - the
  // step at that floor is taken as it is). The state at the start is untouched until a macro step completes
  // (macro_step() writes y_, yp_, t_ last), so a retry needs no restore.
  double advance(double t_target, double t_stop) override {
    const auto start = Clock::now();
    const double h_min = s_.macro_step / kMaxMacroStepCut * 1.0001;
    while (t_ < t_target && t_ < t_stop) {
      double h = std::min(h_next_, s_.macro_step);
      if (t_ + 1.001 * h >= t_stop) h = t_stop - t_;  // land on t_stop, no sliver step
      try {
        const bool accept_any = h <= h_min;
        const bool accepted = macro_step(h, accept_any);
        if (s_.macro_tolerance > 0) {
          const double ratio = exchange_error_ / s_.macro_tolerance;
          const double factor = ratio > 0 ? 0.8 / std::sqrt(ratio) : 2.0;
          h_next_ = std::clamp(h * std::clamp(factor, 0.25, accepted ? 2.0 : 0.8), h_min, s_.macro_step);
          if (!accepted) ++stats_.rejected_steps;
        } else {
          h_next_ = std::min(2 * h_next_, s_.macro_step);
        }
      } catch (const Interrupted&) {
        break;  // the macro step abandoned: the state stays at its start, which run.cpp checkpoints
      } catch (const MacroStepFailure& e) {
        if (h <= s_.macro_step / kMaxMacroStepCut * 1.0001) throw Error(e.what());
        h_next_ = h / 4;
        ++stats_.rejected_steps;
      }
      if (interrupt_requested()) break;
    }
    cpu_total_ += seconds(Clock::now() - start);
    return t_;
  }

  void interpolate(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) const override {
    y = y_, yp = yp_;
    if (!stepped_) return;
    for (const auto& gp : groups_) {
      const Group& g = *gp;
      g.record.interpolate(t, v_, vp_);
      for (std::size_t i = 0; i < g.own.size(); ++i) y[g.own[i]] = v_[i], yp[g.own[i]] = vp_[i];
    }
  }
  double time() const override { return t_; }
  void state(Eigen::VectorXd& y, Eigen::VectorXd& yp) const override { y = y_, yp = yp_; }
  IntegratorStatistics statistics() const override {
    IntegratorStatistics st = stats_;
    st.linear_solves = st.newton_iterations;
    st.last_step = last_macro_step_;
    st.cpu_residual_s = cpu_residual_;
    st.cpu_jacobian_s = cpu_jacobian_;
    st.cpu_factorization_s = std::max(0.0, cpu_total_ - cpu_residual_ - cpu_jacobian_);
    st.linear_solver = linear_solvers_;
    return st;
  }

  // ---------------------------------------------------------------- the callbacks of a group's IDA
  static int residual(double t, N_Vector u, N_Vector up, N_Vector r, void* data) {
    Group& g = *static_cast<Group*>(data);
    SplitIntegrator& self = *g.owner;
    const auto start = Clock::now();
    try {
      self.full_state(g, t, N_VGetArrayPointer(u), N_VGetArrayPointer(up));
      self.model_.residual(t, self.yf_.data(), self.ypf_.data(), self.f_.data());
      double* rr = N_VGetArrayPointer(r);
      const int no = static_cast<int>(g.own.size());
      for (int i = 0; i < no; ++i) rr[i] = self.f_[g.own[i]];
      if (!g.partners.empty()) {  // (S5): the delta rows, linear, frozen at the macro step's start
        const double sr = self.predictor_ ? t - self.t_ : 0.0;
        for (int i = no; i < g.m; ++i) {
          const int k = g.partners[i - no];
          rr[i] = self.predictor_ ? self.f0_[k] + sr * self.g0_[k] : 0.0;
        }
        for (int c = 0; c < g.m; ++c)
          for (sunindextype e = g.column_start[c]; e < g.column_start[c + 1]; ++e)
            if (g.frozen[e]) rr[g.rows[e]] += self.a_[g.source[e]] * g.x[c] + self.b_[g.source[e]] * g.xp[c];
      }
      for (int i = 0; i < g.m; ++i)
        if (!std::isfinite(rr[i])) {
          std::ostringstream msg;
          msg << "the residual is not finite at t = " << t << " s";
          const std::string culprit = self.model_.non_finite_culprit(t, self.yf_.data(), self.ypf_.data());
          if (!culprit.empty()) msg << ": " << culprit;
          g.non_finite = msg.str();
          self.cpu_residual_ += seconds(Clock::now() - start);
          return 1;
        }
    } catch (...) {
      g.pending = std::current_exception();
      return -1;
    }
    self.cpu_residual_ += seconds(Clock::now() - start);
    return 0;
  }

  static int jacobian(double t, double cj, N_Vector u, N_Vector up, N_Vector, SUNMatrix j, void* data,
                      N_Vector, N_Vector, N_Vector) {
    Group& g = *static_cast<Group*>(data);
    SplitIntegrator& self = *g.owner;
    const auto start = Clock::now();
    try {
      self.full_state(g, t, N_VGetArrayPointer(u), N_VGetArrayPointer(up));
      self.model_.jacobian(t, self.yf_.data(), self.ypf_.data(), cj, self.values_);
      sunindextype* colptr = SUNSparseMatrix_IndexPointers(j);
      sunindextype* rowval = SUNSparseMatrix_IndexValues(j);
      double* val = SUNSparseMatrix_Data(j);
      std::copy(g.column_start.begin(), g.column_start.end(), colptr);
      std::copy(g.rows.begin(), g.rows.end(), rowval);
      for (std::size_t e = 0; e < g.rows.size(); ++e) {
        const int k = g.source[e];
        val[e] = g.frozen[e] ? self.a_[k] + cj * self.b_[k] : self.values_[k];
        if (!std::isfinite(val[e])) {
          g.non_finite = "the Jacobian is not finite at t = " + std::to_string(t) + " s";
          return 1;
        }
      }
    } catch (...) {
      g.pending = std::current_exception();
      return -1;
    }
    self.cpu_jacobian_ += seconds(Clock::now() - start);
    return 0;
  }

  static void quiet(int, const char*, const char*, char* msg, void* data) {
    static_cast<Group*>(data)->message = msg;
  }

 private:
  // kRecord: Group::record (this pass's steps once solved, the last pass's before), kPreviousRecord:
  // Group::previous (the last pass's, once the group is being or has been solved in this pass)
  enum Source { kExtrapolated, kRecord, kPreviousRecord };

  /// The whole state at t for group g's sub-problem: the others' motion (S2)/(S3), g's own unknowns, the
  /// partners' deltas added (S5); g.x, g.xp the deviations the delta rows are driven by.
  void full_state(Group& g, double t, const double* u, const double* up) {
    motion_.evaluate(t - t_, yf_, ypf_);
    for (int o = 0; o < partition_.groups; ++o) {  // (S3): the groups given by their steps
      if (source_[o] == kExtrapolated) continue;
      const Group& go = *groups_[o];
      (source_[o] == kRecord ? go.record : go.previous).interpolate(t, v_, vp_);
      for (std::size_t i = 0; i < go.own.size(); ++i) yf_[go.own[i]] = v_[i], ypf_[go.own[i]] = vp_[i];
    }
    const int no = static_cast<int>(g.own.size());
    for (int i = 0; i < no; ++i) {
      const int k = g.own[i];
      g.x[i] = u[i] - yf_[k], g.xp[i] = up[i] - ypf_[k];
      yf_[k] = u[i], ypf_[k] = up[i];
    }
    for (std::size_t i = 0; i < g.partners.size(); ++i) {
      const int k = g.partners[i];
      g.x[no + i] = u[no + i], g.xp[no + i] = up[no + i];
      yf_[k] += u[no + i], ypf_[k] += up[no + i];
    }
  }

  void setup(Group& g, int id) {
    g.owner = this;
    g.id = id;
    g.own = partition_.states[id];
    if (s_.coupling_correction)  // Jacobi: every other group; Gauss-Seidel: the ones after it (not yet
                                 // advanced)
      for (int k = 0; k < model_.size(); ++k) {
        const int o = partition_.group_of_state[k];
        if (o != id && (!gauss_seidel_ || o > id)) g.partners.push_back(k);
      }
    g.m = static_cast<int>(g.own.size() + g.partners.size());
    g.reads = Eigen::VectorXd::Zero(model_.size());  // (S7): the others' unknowns g's own equations read
    for (int c = 0; c < pattern_.n; ++c)
      if (partition_.group_of_state[c] != id)
        for (int e = pattern_.column_start[c]; e < pattern_.column_start[c + 1]; ++e)
          if (partition_.group_of_state[pattern_.rows[e]] == id) g.reads[c] = mask_[c];
    g.local_row_of.assign(model_.size(), -1);
    std::vector<int> sub(g.own);
    sub.insert(sub.end(), g.partners.begin(), g.partners.end());
    for (int i = 0; i < g.m; ++i) g.local_row_of[sub[i]] = i;
    g.column_start.assign(1, 0);
    for (int c = 0; c < g.m; ++c) {
      std::vector<std::pair<int, int>> entries;  // local row, full-pattern entry
      for (int e = pattern_.column_start[sub[c]]; e < pattern_.column_start[sub[c] + 1]; ++e)
        if (const int r = g.local_row_of[pattern_.rows[e]]; r >= 0) entries.emplace_back(r, e);
      std::sort(entries.begin(), entries.end());
      for (const auto& [r, e] : entries) {
        g.rows.push_back(r);
        g.source.push_back(e);
        g.frozen.push_back(r >= static_cast<int>(g.own.size()));
      }
      g.column_start.push_back(static_cast<sunindextype>(g.rows.size()));
    }
    g.x.setZero(g.m), g.xp.setZero(g.m);
    check(SUNContext_Create(nullptr, &g.ctx), "SUNContext_Create");
    g.u = N_VNew_Serial(g.m, g.ctx);
    g.up = N_VNew_Serial(g.m, g.ctx);
    g.work = N_VNew_Serial(g.m, g.ctx);
    g.work2 = N_VNew_Serial(g.m, g.ctx);
    for (N_Vector v : {g.u, g.up, g.work, g.work2}) use_fast_serial_kernels(v);  // ida_integrator.cpp says why
    fill_start(g);
    g.mem = IDACreate(g.ctx);
    check(IDAInit(g.mem, &SplitIntegrator::residual, t_, g.u, g.up), "IDAInit");
    check(IDASetUserData(g.mem, &g), "IDASetUserData");
    N_Vector id_vec = N_VNew_Serial(g.m, g.ctx), atol = N_VNew_Serial(g.m, g.ctx);
    for (int i = 0; i < g.m; ++i) view(id_vec)[i] = mask_[sub[i]], view(atol)[i] = atol_[sub[i]];
    check(IDASVtolerances(g.mem, s_.rtol, atol), "IDASVtolerances");
    check(IDASetId(g.mem, id_vec), "IDASetId");
    N_VDestroy(atol);
    N_VDestroy(id_vec);
    check(IDASetSuppressAlg(g.mem, SUNTRUE), "IDASetSuppressAlg");
    if (s_.max_step > 0) check(IDASetMaxStep(g.mem, s_.max_step), "IDASetMaxStep");
    check(IDASetMaxOrd(g.mem, s_.max_order), "IDASetMaxOrd");
    check(IDASetDeltaCjLSetup(g.mem, s_.jacobian_cj_change), "IDASetDeltaCjLSetup");
    check(IDASetMaxNumSteps(g.mem, 100000000L), "IDASetMaxNumSteps");
    g.matrix = SUNSparseMatrix(g.m, g.m, std::max<sunindextype>(1, g.rows.size()), CSC_MAT, g.ctx);
    use_fast_sparse_kernels(g.matrix);
    const std::vector<int> start(g.column_start.begin(), g.column_start.end()),
        rows(g.rows.begin(), g.rows.end());
    const NewtonSolver kind = choose_newton_solver(s_.linear_solver, g.m, start, rows).kind;
    g.solver = make_newton_solver(kind, g.matrix, g.ctx);
    linear_solvers_ += (linear_solvers_.empty() ? "" : "+") + std::string(to_string(kind));
    check(IDASetLinearSolver(g.mem, g.solver, g.matrix), "IDASetLinearSolver");
    check(IDASetJacFn(g.mem, &SplitIntegrator::jacobian), "IDASetJacFn");
    check(IDASetErrHandlerFn(g.mem, &SplitIntegrator::quiet, &g), "IDASetErrHandlerFn");
    // The first step as IDA's (1 us with joints, as ida_integrator.cpp); later ones continue from the step
    // IDA would have taken next at the last macro step's end.
    g.next_step = s_.initial_step > 0 ? s_.initial_step : 1e-6;
  }

  void fill_start(Group& g) {
    auto u = view(g.u), up = view(g.up);
    u.setZero(), up.setZero();
    for (std::size_t i = 0; i < g.own.size(); ++i) u[i] = y_[g.own[i]], up[i] = yp_[g.own[i]];
  }

  /// Group `o`'s motion over the step: extrapolated (S2) of degree p, or the dense output of its steps (S3).
  void set_motion(int o, Source source, int p = 1) {
    source_[o] = source;
    for (int k : partition_.states[o]) {
      const double d0 = yp_[k];
      motion_.c0[k] = y_[k];
      motion_.c1[k] = p >= 1 ? d0 : 0.0;
      motion_.c2[k] = p >= 2 && h_before_ > 0 ? 0.5 * (d0 - yp_before_[k]) / h_before_ : 0.0;
    }
  }

  /// Integrate group g over [t_, t_ + h] (one pass); its end state into (y_end, yp_end), its record kept.
  void solve_group(Group& g, double h, int pass) {
    fill_start(g);
    check(IDAReInit(g.mem, t_, g.u, g.up), "IDAReInit");
    if (!g.partners.empty()) {  // a delta is judged as the partner's unknown it corrects, not by its own size
      N_Vector atol = N_VClone(g.u);
      const int no = static_cast<int>(g.own.size());
      for (int i = 0; i < g.m; ++i) {
        const int k = i < no ? g.own[i] : g.partners[i - no];
        view(atol)[i] = atol_[k] + (i < no ? 0.0 : s_.rtol * (std::abs(y_[k]) + h * std::abs(yp_[k])));
      }
      check(IDASVtolerances(g.mem, s_.rtol, atol), "IDASVtolerances");
      N_VDestroy(atol);
    }
    check(IDASetInitStep(g.mem, std::min(g.next_step, h)), "IDASetInitStep");
    check(IDASetStopTime(g.mem, t_ + h), "IDASetStopTime");
    const int no = static_cast<int>(g.own.size());
    std::swap(g.previous, g.record);
    g.record.clear();
    g.record.add(t_, view(g.u).head(no), view(g.up).head(no));
    g.non_finite.clear();
    long steps_seen = 0;
    double tret = t_;
    while (true) {
      const int flag = IDASolve(g.mem, t_ + h, &tret, g.u, g.up, IDA_ONE_STEP);
      if (g.pending) std::rethrow_exception(std::exchange(g.pending, nullptr));
      if (flag < 0) fail(g, flag, h, pass);
      long n = 0;
      int order = 0;
      IDAGetNumSteps(g.mem, &n);
      IDAGetLastOrder(g.mem, &order);
      if (order >= 1 && order <= 5) stats_.steps_at_order[order - 1] += n - steps_seen;
      if (n > steps_seen) count_error_test_holder(g);
      steps_seen = n;
      g.non_finite.clear();
      g.record.add(tret, view(g.u).head(no), view(g.up).head(no));
      if (flag == IDA_TSTOP_RETURN || tret >= t_ + h) break;
      if (interrupt_requested()) throw Interrupted{};  // a signal inside a long macro step
      if (n > kStallSteps) {
        double last = 0;
        IDAGetLastStep(g.mem, &last);
        if (last < kStalledStep * h) {
          std::ostringstream msg;
          msg << where(g.id, h, pass) << ": IDA stalled at t = " << tret << " s (" << n
              << " steps, the last of " << last << " s). Try a smaller macro_step or fewer groups.";
          throw MacroStepFailure(msg.str());
        }
      }
    }
    IDAGetCurrentStep(g.mem, &g.next_step);
    long v = 0;
    IDAGetNumSteps(g.mem, &v), stats_.steps += v;
    IDAGetNumErrTestFails(g.mem, &v), stats_.rejected_steps += v;
    IDAGetNumNonlinSolvIters(g.mem, &v), stats_.newton_iterations += v;
    IDAGetNumNonlinSolvConvFails(g.mem, &v), stats_.nonlinear_failures += v;
    IDAGetNumJacEvals(g.mem, &v), stats_.jacobian_evaluations += v;
    IDAGetNumResEvals(g.mem, &v), stats_.residual_evaluations += v;
    int order = 0;
    IDAGetLastOrder(g.mem, &order);
    stats_.last_order = std::max(stats_.last_order, order);
    for (int i = 0; i < no; ++i) y_end_[g.own[i]] = view(g.u)[i], yp_end_[g.own[i]] = view(g.up)[i];
    if (s_.macro_tolerance > 0) {  // (S7): the others' states as g saw them at the end
      full_state(g, tret, N_VGetArrayPointer(g.u), N_VGetArrayPointer(g.up));
      g.seen = yf_;
    }
  }

  /// The inner error test's weights 1 / (rtol |y| + atol) at this pass's end state.
  Eigen::VectorXd end_weights() const { return (s_.rtol * y_end_.cwiseAbs() + atol_).cwiseInverse(); }

  /// (S7): the largest difference between another group's end state as a group saw it (extrapolated (S2),
  /// with its linearized response (S5), or its previous pass (S3)) and the state it reached, over the
  /// differential unknowns the group's own equations read (Group::reads), in units of the error weights
  /// rtol |y| + atol. A group's own states and those of groups it saw by their steps (Gauss-Seidel)
  /// contribute nothing.
  double exchange_error() const {
    const Eigen::VectorXd w = end_weights();
    double e = 0;
    for (const auto& gp : groups_)
      e = std::max(e, ((gp->seen - y_end_).cwiseProduct(w).cwiseProduct(gp->reads)).cwiseAbs().maxCoeff());
    return e;
  }

  /// One macro step [t_, t_ + h]: a predictor pass and up to `iterations` corrector passes. With
  /// macro_tolerance, false (and nothing changed) when the exchange's error estimate (S7) exceeds it, unless
  /// `accept_any`.
  bool macro_step(double h, bool accept_any) {
    {  // A = dF/dy, B = dF/dy' at the start: (S5) and the consistent derivatives (S6)
      const auto start = Clock::now();
      model_.jacobian(t_, y_.data(), yp_.data(), 0.0, a_);
      model_.jacobian(t_, y_.data(), yp_.data(), 1.0, b_);
      for (std::size_t k = 0; k < b_.size(); ++k) b_[k] -= a_[k];
      cpu_jacobian_ += seconds(Clock::now() - start);
      stats_.jacobian_evaluations += 2;
    }
    consistent_derivatives();  // also at the first step: a --restart starts from a checkpoint taken before it
    if (s_.coupling_correction) {  // (S5): R(s) = F(T) + s dF/dt along the linear extrapolation
      model_.residual(t_, y_.data(), yp_.data(), f0_.data());
      const double eps = 1e-6 * h;
      const Eigen::VectorXd y1 = y_ + eps * yp_;
      model_.residual(t_ + eps, y1.data(), yp_.data(), g0_.data());
      g0_ = (g0_ - f0_) / eps;
    }
    const int groups = partition_.groups;
    bool have_previous = false;
    for (int pass = 0; pass <= s_.iterations; ++pass) {
      predictor_ = !have_previous;
      y_end_ = y_, yp_end_ = yp_;
      for (int g = 0; g < groups; ++g) {
        for (int o = 0; o < groups; ++o) {
          if (gauss_seidel_ && o < g)
            set_motion(o, kRecord);  // advanced in this pass: its steps (S3)
          else if (have_previous)    // the last pass's steps (S3): the ones solved in this pass (and g) moved
                                     // it
            set_motion(o, o <= g ? kPreviousRecord : kRecord);
          else
            set_motion(o, kExtrapolated, s_.coupling_correction ? 1 : s_.extrapolation);  // (S2)
        }
        solve_group(*groups_[g], h, pass);
      }
      if (!y_end_.allFinite() || !yp_end_.allFinite()) {
        Eigen::Index k = 0;
        for (; k < y_end_.size(); ++k)
          if (!std::isfinite(y_end_[k]) || !std::isfinite(yp_end_[k])) break;
        throw Error(where(partition_.group_of_state[k], h, pass) + ": the state " + model_.describe_state(k) +
                    " is not finite: the exchange diverged");
      }
      if (s_.macro_tolerance > 0) exchange_error_ = exchange_error();
      if (have_previous) {  // converged: the change of the end state within the tolerances
        const Eigen::VectorXd w = end_weights().cwiseProduct(mask_);
        if (((y_end_ - y_pass_).cwiseProduct(w)).cwiseAbs().maxCoeff() <= 1) break;
      }
      y_pass_ = y_end_, yp_pass_ = yp_end_;
      have_previous = true;
    }
    if (s_.macro_tolerance > 0 && exchange_error_ > s_.macro_tolerance && !accept_any) return false;
    yp_before_ = yp_;
    h_before_ = h;
    t_ += h;
    y_ = y_end_, yp_ = yp_end_;
    last_macro_step_ = h;
    stepped_ = true;
    return true;
  }

  /// (S6): at an exchange the groups' ends were computed against the others' assumed motion, so their
  /// derivatives do not satisfy F(T, y, y') = 0 with the others' actual states (an acceleration jumps by the
  /// coupling force's error over the mass), and a joint's multipliers lambda no longer hold its bodies on the
  /// acceleration-level constraint. IDA restarted on such y' needs steps of tol / jump. So the derivatives of
  /// the differential unknowns D and the multipliers lambda (L) are made consistent (positions, velocities
  /// left as they are), one linear solve as for the accelerations of a consistent start:
  ///   B_DD dy'_D + A_DL dlambda = -F_D                       (the rows of D, linear in y' and lambda)
  ///   A_LD (y'_D + dy'_D) + dF_L/dt = 0                      (d/dt of the velocity equations C w + Phi_t)
  /// a redundant (inactive) equation's row keeping lambda_k = 0.
  void consistent_derivatives() {
    const int n = model_.size();
    if (index_.empty()) {
      const Eigen::VectorXd dm = model_.differential_mask();
      index_.assign(n, -1);
      for (int k = 0; k < n; ++k)
        if (dm[k] > 0) index_[k] = static_cast<int>(unknown_.size()), unknown_.push_back(k);
      differential_ = static_cast<int>(unknown_.size());
      for (int k = model_.lambda_offset(); k < model_.mu_offset(); ++k)
        index_[k] = static_cast<int>(unknown_.size()), unknown_.push_back(k);
    }
    const int nu = static_cast<int>(unknown_.size()), nd = differential_;
    auto is_d = [&](int k) { return index_[k] >= 0 && index_[k] < nd; };
    auto is_l = [&](int k) { return index_[k] >= nd; };
    std::vector<char> active(nu, 0);  // a velocity equation that involves a differential unknown
    for (int c = 0; c < pattern_.n; ++c)
      for (int e = pattern_.column_start[c]; e < pattern_.column_start[c + 1]; ++e)
        if (is_l(pattern_.rows[e]) && is_d(c) && a_[e] != 0) active[index_[pattern_.rows[e]]] = 1;
    project(model_.mu_offset(), model_.size(), false);          // positions onto Phi = 0
    project(model_.lambda_offset(), model_.mu_offset(), true);  // velocities onto C w + Phi_t = 0
    model_.residual(t_, y_.data(), yp_.data(), f_.data());
    const double eps = 1e-7 * std::max(1.0, std::abs(t_));
    model_.residual(t_ + eps, y_.data(), yp_.data(), g0_.data());  // dF_L/dt at fixed (y, y')
    Eigen::VectorXd rhs(nu);
    for (int i = 0; i < nu; ++i) {
      const int k = unknown_[i];
      rhs[i] = i < nd || !active[i] ? -f_[k] : -(g0_[k] - f_[k]) / eps;
    }
    std::vector<Eigen::Triplet<double>> trip;
    for (int c = 0; c < pattern_.n; ++c)
      for (int e = pattern_.column_start[c]; e < pattern_.column_start[c + 1]; ++e) {
        const int r = pattern_.rows[e];
        if (index_[r] < 0 || index_[c] < 0) continue;
        const int i = index_[r], j = index_[c];
        if (is_d(r) && is_d(c)) {
          trip.emplace_back(i, j, b_[e]);
        } else if (is_d(r) && is_l(c)) {
          trip.emplace_back(i, j, a_[e]);
        } else if (is_l(r) && active[i] && is_d(c)) {
          trip.emplace_back(i, j, a_[e]);
          rhs[i] -= a_[e] * yp_[c];
        } else if (is_l(r) && !active[i] && is_l(c)) {
          trip.emplace_back(i, j, a_[e]);
        }
      }
    Eigen::SparseMatrix<double> m(nu, nu);
    m.setFromTriplets(trip.begin(), trip.end());
    m.makeCompressed();
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
    lu.compute(m);
    if (lu.info() != Eigen::Success)
      throw Error(
          "split integrator: at t = " + std::to_string(t_) +
          " s the system for consistent accelerations and multipliers ([M C^T; C 0]) is singular; the "
          "exchange cannot restart the groups");
    const Eigen::VectorXd d = lu.solve(rhs);
    for (int i = 0; i < nu; ++i) (i < nd ? yp_ : y_)[unknown_[i]] += d[i];
  }

  /// (S6, first) The groups' ends satisfy their joints' equations only to Newton's tolerance; a restart
  /// would enforce them exactly in its first step, a jump of the velocities (positions) independent of the
  /// step that the error test then rejects at every step size (seen on a slider-crank at 90 deg crank, where
  /// the conrod's angular velocity, weighted by atol alone, crosses zero). So the violations r of the rows
  /// [first, last) (the position or the velocity equations) are removed by the least-norm change of the
  /// positions (velocities) x: dx = -J^T (J J^T)^-1 r, J = dr/dx from A.
  void project(int first, int last, bool velocities) {
    const Eigen::VectorXd vmask = model_.velocity_mask(), dmask = model_.differential_mask();
    std::vector<int> row_of(model_.size(), -1), col_of(model_.size(), -1), rows, cols;
    for (int k = 0; k < model_.size(); ++k)
      if (dmask[k] > 0 && (vmask[k] > 0) == velocities)
        col_of[k] = static_cast<int>(cols.size()), cols.push_back(k);
    std::vector<Eigen::Triplet<double>> trip;
    for (int c = 0; c < pattern_.n; ++c)
      for (int e = pattern_.column_start[c]; e < pattern_.column_start[c + 1]; ++e) {
        const int r = pattern_.rows[e];
        if (r < first || r >= last || col_of[c] < 0 || a_[e] == 0) continue;
        if (row_of[r] < 0) row_of[r] = static_cast<int>(rows.size()), rows.push_back(r);
        trip.emplace_back(row_of[r], col_of[c], a_[e]);
      }
    if (rows.empty()) return;
    Eigen::SparseMatrix<double> j(static_cast<Eigen::Index>(rows.size()),
                                  static_cast<Eigen::Index>(cols.size()));
    j.setFromTriplets(trip.begin(), trip.end());
    model_.residual(t_, y_.data(), yp_.data(), f_.data());
    Eigen::VectorXd r(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) r[i] = f_[rows[i]];
    const Eigen::SparseMatrix<double> jjt = j * j.transpose();
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(jjt);
    if (lu.info() != Eigen::Success)
      throw Error("split integrator: at t = " + std::to_string(t_) + " s the joints' " +
                  (velocities ? "velocity" : "position") +
                  " equations are dependent; cannot project onto them");
    const Eigen::VectorXd dx = -(j.transpose() * lu.solve(r));
    for (std::size_t i = 0; i < cols.size(); ++i) y_[cols[i]] += dx[i];
  }

  std::string where(int group, double h, int pass) const {
    std::ostringstream msg;
    msg << "split integrator: group " << group + 1 << " (bodies";
    for (const auto& b : partition_.bodies[group]) msg << " '" << b << "'";
    msg << ") in the macro step [" << t_ << ", " << t_ + h << "] s";
    if (pass > 0) msg << ", corrector pass " << pass;
    return msg.str();
  }

  /// The group's unknown (of the full state; its own, not its partners' linearized responses) with the
  /// largest weighted local error estimate in the step just taken (IntegratorStatistics::error_test_steps).
  void count_error_test_holder(Group& g) {
    if (IDAGetErrWeights(g.mem, g.work) < 0 || IDAGetEstLocalErrors(g.mem, g.work2) < 0) return;
    const double* weight = N_VGetArrayPointer(g.work);
    const double* error = N_VGetArrayPointer(g.work2);
    int best = -1;
    double largest = -1.0;
    for (int i = 0; i < static_cast<int>(g.own.size()); ++i)
      if (mask_[g.own[i]] > 0)
        if (const double e = std::abs(error[i] * weight[i]); e > largest) largest = e, best = g.own[i];
    if (best >= 0) ++stats_.error_test_steps[best];
  }

  [[noreturn]] void fail(Group& g, int flag, double h, int pass) {
    double t_now = t_;
    IDAGetCurrentTime(g.mem, &t_now);
    std::ostringstream msg;
    char* name = IDAGetReturnFlagName(flag);
    msg << where(g.id, h, pass) << ": IDA failed at t = " << t_now << " s (flag " << flag << ": "
        << (name ? name : "?") << ")";
    std::free(name);
    if (!g.non_finite.empty()) msg << "; " << g.non_finite;
    if (IDAGetErrWeights(g.mem, g.work) >= 0 && IDAGetEstLocalErrors(g.mem, g.work2) >= 0) {
      Eigen::Index k = 0;
      const int no = static_cast<int>(g.own.size());
      Eigen::VectorXd e = view(g.work2).cwiseProduct(view(g.work)).cwiseAbs();
      for (int i = 0; i < g.m; ++i)  // only the unknowns in the error test (not the multipliers)
        if (mask_[i < no ? g.own[i] : g.partners[i - no]] == 0) e[i] = 0;
      e.maxCoeff(&k);
      msg << "; the largest weighted error is in "
          << (k < no ? model_.explain_state(g.own[k])
                     : "the linearized response of " + model_.describe_state(g.partners[k - no]));
    }
    if (!g.message.empty()) msg << "; IDA says: " << g.message;
    msg << ". Try a smaller macro_step, coupling_correction = true, or tighter tolerances.";
    throw MacroStepFailure(msg.str());
  }

  const Model& model_;
  IntegratorSettings s_;
  SplitPartition partition_;
  SparsityPattern pattern_;
  bool gauss_seidel_ = false;
  double t_;
  Eigen::VectorXd y_, yp_;     // at t_ (the macro step's start)
  Eigen::VectorXd yp_before_;  // y' at t_ - h_before_ (quadratic extrapolation)
  double h_before_ = 0;
  double h_next_ = std::numeric_limits<double>::infinity();  // the next macro step (advance)
  double exchange_error_ = 0;                                // (S7) of the last pass
  Eigen::VectorXd y_end_, yp_end_;                           // this pass's end
  Eigen::VectorXd y_pass_, yp_pass_;                         // the previous pass's end
  Eigen::VectorXd mask_, atol_;
  Motion motion_;
  std::vector<Source> source_;          // per group, in the current group's pass
  Eigen::VectorXd yf_, ypf_, f_;        // the whole state a group's residual sees
  Eigen::VectorXd f0_, g0_;             // (S5): F and dF/dt along the extrapolation at the step's start
  bool predictor_ = true;               // the predictor pass (S5 with R), or a corrector pass
  std::vector<double> values_, a_, b_;  // dF/dy + cj dF/dy' now; A, B at the macro step's start
  std::vector<std::unique_ptr<Group>> groups_;
  std::vector<int> unknown_, index_;  // (S6): the differential unknowns, then the multipliers lambda
  int differential_ = 0;
  mutable Eigen::VectorXd v_, vp_;
  bool stepped_ = false;
  double last_macro_step_ = 0;
  IntegratorStatistics stats_;
  double cpu_residual_ = 0, cpu_jacobian_ = 0, cpu_total_ = 0;
  std::string linear_solvers_;  // each group's Newton solver, "+"-joined (statistics)
};

}  // namespace

std::unique_ptr<Integrator> make_split_integrator(const Model& model, const IntegratorSettings& s, double t0,
                                                  const Eigen::VectorXd& y0, const Eigen::VectorXd& yp0) {
  return std::make_unique<SplitIntegrator>(model, s, t0, y0, yp0);
}

}  // namespace nvh::solve
