// Generalized-alpha for first-order systems (Jansen, Whiting and Hulbert, Comput. Methods Appl. Mech. Engrg.
// 190, 2000, eq. 7-9 and 17-19) applied to the same residual F(t, y, y') = 0 as IDA:
//   y_{n+1}       = y_n + h y'_n + h gamma (y'_{n+1} - y'_n)
//   F(t_n + alpha_f h, y_n + alpha_f (y_{n+1} - y_n), y'_n + alpha_m (y'_{n+1} - y'_n)) = 0
//   alpha_m = (3 - rho_inf) / (2 (1 + rho_inf)),  alpha_f = 1 / (1 + rho_inf),  gamma = 1/2 + alpha_m - alpha_f,
// second order, unconditionally stable for linear problems, with spectral radius rho_inf at h -> infinity
// (rho_inf = 1: no numerical damping; 0: asymptotic annihilation). On the first-order form of the
// equations of motion this is the Chung-Hulbert family (Chung and Hulbert, J. Appl. Mech. 60, 1993); it works
// on the index-2 stabilized constraints of model.hpp like IDA, so both integrators solve the same model.
// Newton on y'_{n+1} uses the same Jacobian with cj = alpha_m / (alpha_f gamma h) and a sparse LU, kept while cj
// stays within jacobian_cj_change of the factorized one's, and IDA's convergence test (newton_tolerance).
// Contact events: after each converged step the gaps of the contact elements (Model::gaps) are evaluated; if
// one changed sign, its crossing is located on the step's Hermite interpolant and the step is redone from its
// start to end there, so that an onset or release is a step boundary (no step straddles the kink of a contact
// force). (Shortening a step beforehand at a crossing predicted by extrapolation was tried and dropped: on the
// piston-slap scene it doubled the Newton failures at 20-100 us steps.)
#include <Eigen/SparseLU>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "solve/integrator.hpp"
#include "solve/jacobian.hpp"

namespace nvh::solve {
namespace {

using Clock = std::chrono::steady_clock;
double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

class GeneralizedAlpha final : public Integrator {
 public:
  GeneralizedAlpha(const Model& model, const IntegratorSettings& s, double t0, const Eigen::VectorXd& y0,
                   const Eigen::VectorXd& yp0)
      : model_(model), s_(s), jacobian_(model, s.jacobian == "dense-fd"), t_(t0), y_(y0), yp_(yp0),
        y_prev_(y0), yp_prev_(yp0), t_prev_(t0), h_(s.step), mask_(model.error_test_mask()) {
    const double rho = s.rho_inf;
    alpha_m_ = (3 - rho) / (2 * (1 + rho));
    alpha_f_ = 1 / (1 + rho);
    gamma_ = 0.5 + alpha_m_ - alpha_f_;
    for (Eigen::VectorXd* v : {&work_.a, &work_.y1, &work_.ya, &work_.ypa, &work_.f, &work_.weights, &dy_})
      v->resize(model.size());
    const auto& p = jacobian_.pattern();
    std::vector<Eigen::Triplet<double>> trip;
    for (int c = 0; c < p.n; ++c)
      for (int k = p.column_start[c]; k < p.column_start[c + 1]; ++k) trip.emplace_back(p.rows[k], c, 1.0);
    matrix_.resize(p.n, p.n);
    matrix_.setFromTriplets(trip.begin(), trip.end());
    matrix_.makeCompressed();
    lu_.analyzePattern(matrix_);
    if (s.events && model.gap_count() > 0) {
      gaps_.resize(model.gap_count());
      model.gaps(t_, y_.data(), yp_.data(), gaps_.data());
      closed_.resize(gaps_.size());
      for (int k = 0; k < gaps_.size(); ++k) closed_[k] = gaps_[k] < 0;
    }
  }

  double advance(double t_target, double t_stop) override {
    const auto start = Clock::now();
    while (t_ < t_target && t_ < t_stop) {
      double h = h_;
      bool landing = t_ + 1.001 * h >= t_stop;  // land on t_stop exactly, no sliver step
      if (landing) h = t_stop - t_;
      int halvings = 0;
      while (!try_step(h)) {
        ++stats_.rejected_steps;
        if (!s_.adaptive || ++halvings > 12) fail(h);
        h *= 0.5;
        h_ = h;
        jacobian_fresh_ = false;
      }
      if (!closed_.empty() && end_at_event(h)) landing = false;
      if (landing) t_ = t_stop;
      ++stats_.steps;
      stats_.last_step = h;
      if (s_.adaptive && h_ < s_.step && ++good_steps_ >= 4) {  // grow back towards the nominal step
        h_ = std::min(s_.step, 2 * h_);
        good_steps_ = 0;
        jacobian_fresh_ = false;
      }
      // A signal: return before the target; the caller samples up to here and writes the checkpoint.
      if (interrupt_requested()) break;
    }
    cpu_total_ += seconds(Clock::now() - start);
    return t_;
  }

  void interpolate(double t, Eigen::VectorXd& y, Eigen::VectorXd& yp) const override {
    // Cubic Hermite between the last two steps.
    const double h = t_ - t_prev_;
    if (h <= 0) {
      y = y_;
      yp = yp_;
      return;
    }
    const double s = (t - t_prev_) / h, s2 = s * s, s3 = s2 * s;
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
    y = h00 * y_prev_ + h10 * h * yp_prev_ + h01 * y_ + h11 * h * yp_;
    const double d00 = (6 * s2 - 6 * s) / h, d10 = 3 * s2 - 4 * s + 1, d01 = (-6 * s2 + 6 * s) / h, d11 = 3 * s2 - 2 * s;
    yp = d00 * y_prev_ + d10 * yp_prev_ + d01 * y_ + d11 * yp_;
  }
  double time() const override { return t_; }
  void state(Eigen::VectorXd& y, Eigen::VectorXd& yp) const override {
    y = y_;
    yp = yp_;
  }
  IntegratorStatistics statistics() const override {
    IntegratorStatistics s = stats_;
    s.last_order = 2;
    s.residual_evaluations += jacobian_.residual_evaluations();
    s.cpu_factorization_s = std::max(0.0, cpu_total_ - s.cpu_residual_s - s.cpu_jacobian_s);
    s.linear_solver = "sparse-lu";
    return s;
  }

 private:
  /// The time in [a, b] where gap k, given by gap(t), crosses zero from the side closed_[k] (Illinois, a
  /// modified regula falsi); fb = gap(b) is on the other side. gap(a) is evaluated, and replaced by the
  /// side's sign if it is not on that side.
  template <class Gap>
  double crossing(int k, double a, double b, double fb, const Gap& gap) const {
    const double tolerance = 1e-9 * (b - a);
    double fa = gap(a);
    if ((fa < 0) != static_cast<bool>(closed_[k])) fa = closed_[k] ? -1e-300 : 1e-300;
    int side = 0;
    for (int it = 0; it < 100 && b - a > tolerance; ++it) {
      double t = (a * fb - b * fa) / (fb - fa);
      if (!(t > a && t < b)) t = 0.5 * (a + b);
      const double ft = gap(t);
      if ((ft < 0) == (fb < 0)) {  // the crossing is in [a, t]
        b = t, fb = ft;
        if (side == -1) fa *= 0.5;
        side = -1;
      } else {
        a = t, fa = ft;
        if (side == 1) fb *= 0.5;
        side = 1;
      }
    }
    return b;
  }

  /// After a converged step of length h: if gaps changed sign, redo the step to end at the earliest
  /// crossing (on the Hermite interpolant of the step); the step's length is then h. Returns whether it did.
  bool end_at_event(double& h) {
    model_.gaps(t_, y_.data(), yp_.data(), gaps_.data());
    const double t0 = t_prev_, t1 = t_;
    const double tolerance = 1e-9 * (t1 - t0);  // of the crossing's time, and how close to an end is "at" it
    double t_event = t1;
    std::vector<int> crossed;
    Eigen::VectorXd y, yp, g(gaps_.size());
    for (int k = 0; k < gaps_.size(); ++k) {
      if ((gaps_[k] < 0) == static_cast<bool>(closed_[k])) continue;
      const double b = crossing(k, t0, t1, gaps_[k], [&](double t) {
        interpolate(t, y, yp);
        model_.gaps(t, y.data(), yp.data(), g.data());
        return g[k];
      });
      if (b < t_event - tolerance) {
        t_event = b;
        crossed.assign(1, k);
      } else if (b <= t_event + tolerance) {
        crossed.push_back(k);
      }
    }
    if (crossed.empty()) return false;
    bool shortened = false;
    // Redo the step to end at the crossing; not for a sliver at its start (a step of a few ns makes Newton's
    // matrix, conditioned as 1/h^2 on the constraints, fail): there the event is the step's start.
    if (t_event - t0 > 1e-3 * (t1 - t0) && t1 - t_event > tolerance) {
      const Eigen::VectorXd y1 = y_, yp1 = yp_;
      t_ = t_prev_, y_ = y_prev_, yp_ = yp_prev_;
      const double hc = t_event - t0;
      if (try_step(hc)) {
        h = hc;
        shortened = true;
      } else {  // keep the converged step (its end is after the crossing)
        t_prev_ = t0, y_prev_ = y_, yp_prev_ = yp_;
        t_ = t1, y_ = y1, yp_ = yp1;
      }
    }
    for (int k : crossed) {  // a gap that the redone step alone crosses is found at the next step's start
      closed_[k] = !closed_[k];
      ++stats_.events;
      log_event({t_event, k, static_cast<bool>(closed_[k])});
    }
    return shortened;
  }

  bool try_step(double h) {
    const int n = model_.size();
    const double cj = alpha_m_ / (alpha_f_ * gamma_ * h);
    const double ta = t_ + alpha_f_ * h;
    // The step's vectors live in the integrator (sized once), named here as in the equations at the top.
    Eigen::VectorXd &a = work_.a, &y1 = work_.y1, &ya = work_.ya, &ypa = work_.ypa, &f = work_.f,
                    &weights = work_.weights;
    for (int k = 0; k < n; ++k) weights[k] = 1.0 / (s_.rtol * std::abs(y_[k]) + s_.atol);
    auto stage = [&] {
      y1 = y_ + h * yp_ + h * gamma_ * (a - yp_);
      ya = y_ + alpha_f_ * (y1 - y_);
      ypa = yp_ + alpha_m_ * (a - yp_);
      const auto start = Clock::now();
      model_.residual(ta, ya.data(), ypa.data(), f.data());
      ++stats_.residual_evaluations;
      stats_.cpu_residual_s += seconds(Clock::now() - start);
    };
    for (int attempt = 0; attempt < 2; ++attempt) {
      jacobian_fresh_now_ = false;
      predict(h, a);
      stage();
      // A new iteration matrix when the last one is stale (a failure) or its cj is more than
      // jacobian_cj_change away (as IDA, IDASetDeltaCjLSetup); in between the correction is scaled by
      // 2 / (1 + cj / cj_), IDA's compensation of the dominant cj dF/dy' part.
      if ((!jacobian_fresh_ || std::abs(cj / cj_ - 1) > s_.jacobian_cj_change) &&
          !factor(ta, ya, ypa, f, cj, h, weights)) {
        ++stats_.nonlinear_failures;  // a non-finite Jacobian: a shorter step, as for a non-finite residual
        return false;
      }
      const double scale = 2 / (1 + cj / cj_);
      bool converged = false;
      double first = 0;
      for (int it = 0; it < kMaxIterations; ++it) {
        if (!f.allFinite()) {  // kept for the message if the step cannot be shortened enough (fail())
          note_non_finite(ta, ya, ypa);
          break;
        }
        dy_ = lu_.solve(-f);  // correction of y_alpha
        if (scale != 1) dy_ *= scale;
        ++stats_.linear_solves;
        ++stats_.newton_iterations;
        a += dy_ / (alpha_f_ * gamma_ * h);
        stage();
        // Convergence (Hairer & Wanner, Solving ODEs II, 2nd ed., sec. IV.8, eq. 8.10-8.11; IDA's test): the
        // error left after iteration m is estimated as rate / (1 - rate) |dy_m| from the contraction rate
        // (|dy_m| / |dy_0|)^(1/m); before this step has a rate, the last one's (rate_ratio_) is used.
        const double norm = (dy_.cwiseProduct(weights).cwiseProduct(mask_)).norm() / std::sqrt(double(n));
        if (it == 0) {
          first = norm;
        } else {
          const double rate = std::pow(norm / first, 1.0 / it);
          if (rate > 0.9) break;  // not contracting
          rate_ratio_ = rate / (1 - rate);
        }
        // Without an error test behind it (IDA has one), a rate carried from another step is trusted no lower
        // than kCarriedRateRatio: a fresh matrix's quadratic convergence (rates of 1e-6) would otherwise accept
        // a stale matrix's first correction of any size.
        const double ratio = it == 0 ? std::max(rate_ratio_, kCarriedRateRatio) : rate_ratio_;
        if (ratio * norm <= s_.newton_tolerance) {
          converged = f.allFinite();
          if (!converged) note_non_finite(ta, ya, ypa);
          break;
        }
      }
      if (converged) {
        non_finite_.clear();
        t_prev_ = t_;
        y_prev_ = y_;
        yp_prev_ = yp_;
        t_ += h;
        y_ = y1;
        yp_ = a;
        return true;
      }
      ++stats_.nonlinear_failures;
      if (jacobian_fresh_now_) break;
      jacobian_fresh_ = false;  // retry once with a fresh Jacobian
    }
    return false;
  }

  /// The predictor of y'_{n+1}: linear extrapolation through the last two steps' y' (constant y' at the
  /// start). Measured on the valvetrain with the flexible rocker (20 us): 10 % fewer Newton iterations than
  /// constant y'.
  void predict(double h, Eigen::VectorXd& a) const {
    const double hp = t_ - t_prev_;
    if (hp > 0)
      a = yp_ + (h / hp) * (yp_ - yp_prev_);
    else
      a = yp_;
  }

  /// False (and the cause noted for fail()) if the Jacobian is not finite.
  bool factor(double ta, const Eigen::VectorXd& ya, const Eigen::VectorXd& ypa, const Eigen::VectorXd& f,
              double cj, double h, const Eigen::VectorXd& weights) {
    const auto start = Clock::now();
    if (s_.jacobian == "analytic")
      model_.jacobian(ta, ya.data(), ypa.data(), cj, values_);
    else
      jacobian_.evaluate(ta, ya, ypa, f, cj, h, weights, values_);
    ++stats_.jacobian_evaluations;
    stats_.cpu_jacobian_s += seconds(Clock::now() - start);
    for (double v : values_)
      if (!std::isfinite(v)) {
        jacobian_fresh_ = false;
        note_non_finite(ta, ya, ypa, "the Jacobian");
        return false;
      }
    std::copy(values_.begin(), values_.end(), matrix_.valuePtr());
    lu_.factorize(matrix_);
    if (lu_.info() != Eigen::Success)
      throw Error("generalized-alpha: the iteration matrix is singular at t = " + std::to_string(t_) + " s");
    cj_ = cj;
    rate_ratio_ = 20;  // no rate known for the new matrix (IDA's start value)
    jacobian_fresh_ = true;
    jacobian_fresh_now_ = true;
    return true;
  }

  [[noreturn]] void fail(double h) const {
    std::ostringstream msg;
    msg << "generalized-alpha: Newton did not converge at t = " << t_ << " s with step " << h << " s";
    if (!non_finite_.empty()) msg << "; " << non_finite_;
    msg << "; try a smaller step, adaptive = true, or check the scene's parameters";
    throw Error(msg.str());
  }

  void note_non_finite(double t, const Eigen::VectorXd& y, const Eigen::VectorXd& yp,
                       const char* what = "the residual") {
    std::ostringstream msg;
    msg << what << " is not finite at t = " << t << " s";
    const std::string culprit = model_.non_finite_culprit(t, y.data(), yp.data());
    if (!culprit.empty()) msg << ": " << culprit;
    non_finite_ = msg.str();
  }

  const Model& model_;
  IntegratorSettings s_;
  ColoredJacobian jacobian_;
  double t_;
  Eigen::VectorXd y_, yp_, y_prev_, yp_prev_;
  double t_prev_;
  double h_;
  // Newton's norm: the error test's unknowns (1). The multipliers stay out (IDA's Newton test has them, at
  // multiplier_atol): tried, a flexible valvetrain then failed to converge at contact events, where the
  // shortened steps leave the index-2 multipliers known to round-off / h^2 only.
  Eigen::VectorXd mask_;
  double alpha_m_ = 0, alpha_f_ = 0, gamma_ = 0, cj_ = 0;
  static constexpr int kMaxIterations = 8;
  static constexpr double kCarriedRateRatio = 1.0;  // the least rate / (1 - rate) trusted from another step
  double rate_ratio_ = 20;  // rate / (1 - rate) of Newton's last contraction (the convergence test)
  Eigen::VectorXd dy_;      // Newton's correction
  struct StepVectors {      // try_step's: y'_{n+1} (a), y_{n+1}, the stage's y and y', F, the error weights
    Eigen::VectorXd a, y1, ya, ypa, f, weights;
  } work_;
  Eigen::SparseMatrix<double> matrix_;
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu_;
  std::vector<double> values_;
  bool jacobian_fresh_ = false;
  bool jacobian_fresh_now_ = false;
  int good_steps_ = 0;
  Eigen::VectorXd gaps_;       // at the last step's end
  std::vector<char> closed_;   // per gap: on the closed side (< 0) after the last located event
  IntegratorStatistics stats_;
  double cpu_total_ = 0;
  std::string non_finite_;  // the last non-finite residual since the last converged step (fail())
};

}  // namespace

std::unique_ptr<Integrator> make_generalized_alpha(const Model& model, const IntegratorSettings& s, double t0,
                                                   const Eigen::VectorXd& y0, const Eigen::VectorXd& yp0) {
  return std::make_unique<GeneralizedAlpha>(model, s, t0, y0, yp0);
}

}  // namespace nvh::solve
