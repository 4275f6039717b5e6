#include "solve/run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <sstream>

#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "solve/results.hpp"
#include "solve/steady_state.hpp"

namespace nvh::solve {

namespace {

// At most this many samples per run: 10^10 rows of even a few channels are terabytes, so more is an input
// mistake (a sample rate meant in kHz given in Hz), not a run to start.
constexpr double kMaxSamples = 1e10;

std::string number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

/// A non-finite state is never written as a sample or a checkpoint: an error naming the unknown (and so its
/// body, joint or element) and the time instead.
void require_finite(const Model& model, double t, const Eigen::VectorXd& y, const Eigen::VectorXd& yp) {
  if (y.allFinite() && yp.allFinite()) return;
  throw Error("the solution is not finite at t = " + number(t) +
              " s: " + model.non_finite_culprit(t, y.data(), yp.data()));
}

}  // namespace

std::string error_test_holders(const Model& model, const std::vector<long>& steps, int leading) {
  long total = 0;
  for (long n : steps) total += n;
  if (total == 0) return {};
  std::vector<int> order;
  for (int k = 0; k < static_cast<int>(steps.size()); ++k)
    if (steps[k] > 0) order.push_back(k);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return steps[a] > steps[b]; });
  std::ostringstream out;
  for (int i = 0; i < std::min<int>(leading, static_cast<int>(order.size())); ++i) {
    const double share = 100.0 * static_cast<double>(steps[order[i]]) / static_cast<double>(total);
    out << (i ? ", " : "") << model.explain_state(order[i]) << " " << std::lround(share) << " %";
  }
  return out.str();
}

RunSummary run_scene(Scene& scene, const RunOptions& options, const Provenance& provenance, const Logger& log) {
  const auto wall_start = std::chrono::steady_clock::now();
  // From here a signal only sets a flag: the results file, once created, is always left with a status the
  // loop below writes ("interrupted" with a checkpoint), never "running" without one.
  struct GracefulInterrupts {
    GracefulInterrupts() { set_graceful_interrupt(true); }
    ~GracefulInterrupts() { set_graceful_interrupt(false); }
  } graceful;
  Model& model = scene.model;
  // The sample times start_time + k dt must advance: an infinite or absurd rate (dt = 0, or below the
  // resolution of the time) wrote samples at one time without end.
  const double dt = 1.0 / scene.output.sample_rate_hz;
  const bool by_angle = scene.end_angle_deg > 0;
  if (!(std::isfinite(dt) && dt > 0 && scene.start_time + dt > scene.start_time))
    throw Error("output.sample_rate_hz = " + number(scene.output.sample_rate_hz) +
                ": the sample interval is not a positive time step at start_time = " +
                number(scene.start_time) + " s; expected a finite rate in Hz");
  if (!by_angle && (scene.end_time - scene.start_time) / dt > kMaxSamples)
    throw Error("output.sample_rate_hz = " + number(scene.output.sample_rate_hz) + " over " +
                number(scene.end_time - scene.start_time) + " s would write more than " +
                number(kMaxSamples) + " samples; expected a lower rate or a shorter run");
  Eigen::VectorXd y, yp;
  double t0 = scene.start_time;
  long first_sample = 0;
  std::unique_ptr<ResultsWriter> writer;
  double angle_origin = 0;  // end-by-angle: the crank angle at the start of the (original) run

  if (options.restart) {
    // Redundant equations are found again from the start configuration (the same scene gives the same set),
    // before the file is reopened (an interrupt in there leaves the file as it was).
    Eigen::VectorXd y_start, yp_start;
    if (scene.steady_state) refuse_restart_of_steady_state_result(options.output);
    model.consistent_initial_state(scene.start_time, y_start, yp_start, log);
    angle_origin = model.clock_angle(y_start.data());
    Checkpoint cp;
    writer = std::make_unique<ResultsWriter>(ResultsWriter::reopen(options.output, scene, cp));
    y = cp.y;
    yp = cp.yp;
    t0 = cp.time;
    first_sample = cp.samples;
    log.info("restarting from the checkpoint at t = " + std::to_string(t0) + " s (" + std::to_string(first_sample) +
             " samples kept)");
  } else {
    model.consistent_initial_state(t0, y, yp, log);
    angle_origin = model.clock_angle(y.data());
    require_finite(model, t0, y, yp);
    Checkpoint start;
    start.time = t0;
    start.y = y;
    start.yp = yp;
    writer = std::make_unique<ResultsWriter>(ResultsWriter::create(options.output, scene, provenance, start));
  }

  // The periodic steady state: a monitor of the watched channels per cycle (steady_state.hpp); a restart
  // feeds it the samples kept in the file first.
  std::unique_ptr<SteadyStateMonitor> steady;
  auto steady_x = [&](double t, const Eigen::VectorXd& ys) {
    return scene.steady_state->by_angle ? model.clock_angle(ys.data()) * 180.0 / std::numbers::pi : t;
  };
  if (scene.steady_state) {
    steady = std::make_unique<SteadyStateMonitor>(
        *scene.steady_state, *writer,
        scene.steady_state->by_angle ? angle_origin * 180.0 / std::numbers::pi : scene.start_time);
    if (options.restart) steady->replay(writer->root(), first_sample, log);
  }

  auto integrator = make_integrator(model, scene.integrator, t0, y, yp);
  const double t_end = scene.end_time;
  const double end_angle = scene.end_angle_deg * std::numbers::pi / 180.0;
  long k = first_sample;
  auto sample_time = [&](long i) { return scene.start_time + static_cast<double>(i) * dt; };

  const std::int64_t total = by_angle ? static_cast<std::int64_t>(scene.end_angle_deg) : std::int64_t(1000);
  Progress progress(log, "solve", total, options.progress);
  RunSummary summary;
  summary.status = "complete";
  long since_flush = 0;
  // A checkpoint at the integrator's time, or at (t, y, y') given: the last sample's, when a signal stopped
  // the sampling of a step part-way (a restart continues after that sample).
  auto checkpoint_at = [&](double t, const Eigen::VectorXd& cy, const Eigen::VectorXd& cyp) {
    require_finite(model, t, cy, cyp);  // a non-finite state is never a checkpoint
    Checkpoint cp;
    cp.time = t;
    cp.y = cy;
    cp.yp = cyp;
    const auto [dp, dv] = model.constraint_violation(cp.time, cp.y.data());
    summary.max_position_drift = std::max(summary.max_position_drift, dp);
    summary.max_velocity_drift = std::max(summary.max_velocity_drift, dv);
    // Samples up to this time are written; the next run continues after them.
    writer->flush(cp);
    since_flush = 0;
  };
  Eigen::VectorXd yc, ypc;
  auto checkpoint = [&] {
    integrator->state(yc, ypc);
    checkpoint_at(integrator->time(), yc, ypc);
  };
  auto wall_seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };
  Eigen::VectorXd ys, yps;
  double last_detail = -1.0;
  bool stopped_inside_step = false;  // a signal stopped the sampling with samples of the step left
  try {
    bool done = steady && steady->done();  // a restart of a run that had converged before its last checkpoint
    while (!done) {
      const double target = sample_time(k);
      if (target > t_end + 1e-9 * dt) break;
      const double t = integrator->advance(target, t_end);
      while (!done && sample_time(k) <= t + 1e-9 * dt && sample_time(k) <= t_end + 1e-9 * dt) {
        const double ts = sample_time(k);
        if (k > first_sample && !(ts > sample_time(k - 1)))
          throw Error("output.sample_rate_hz = " + number(scene.output.sample_rate_hz) +
                      ": the sample times no longer advance at t = " + number(ts) +
                      " s (the interval is below the resolution of the time); expected a lower rate");
        if (static_cast<double>(k) >= kMaxSamples)
          throw Error("more than " + number(kMaxSamples) + " samples at t = " + number(ts) +
                      " s; expected a lower output.sample_rate_hz or an earlier end");
        integrator->interpolate(std::min(ts, t), ys, yps);
        if (by_angle && model.clock_angle(ys.data()) - angle_origin > end_angle * (1 + 1e-9)) {
          done = true;
          break;
        }
        require_finite(model, ts, ys, yps);  // before it is written
        writer->add_sample(ts, scene, ys, yps);
        ++k;
        if (steady && steady->add(steady_x(ts, ys), k - 1, *writer, log))
          done = true;  // converged or max_cycles
        ++since_flush;
        // Many samples in one step (a high rate): written as they come, memory stays bounded. (At twice the
        // chunk: a normal run reaches one chunk only at the checkpoint after the step, which writes them.)
        if (writer->buffered() >= 2L * scene.output.chunk_samples) writer->flush_samples();
        if (interrupt_requested()) {
          stopped_inside_step = sample_time(k) <= std::min(t, t_end) + 1e-9 * dt;
          break;
        }
      }
      if (stopped_inside_step) {
        checkpoint_at(sample_time(k - 1), ys, yps);
        summary.status = "interrupted";
        break;
      }
      if (since_flush >= scene.output.chunk_samples) checkpoint();
      const double fraction =
          by_angle ? (model.clock_angle(ys.data()) - angle_origin) * 180.0 / std::numbers::pi
                   : 1000.0 * (t - scene.start_time) / std::max(1e-300, t_end - scene.start_time);
      const double wall = wall_seconds();
      if (wall - last_detail >= 0.5) {  // the detail (statistics, formatting) at most twice a second
        last_detail = wall;
        const IntegratorStatistics st = integrator->statistics();
        std::ostringstream detail;
        detail.precision(4);
        detail << "t = " << t << " s";
        if (model.clock) detail << ", " << model.clock_angle(ys.data()) * 180.0 / std::numbers::pi << " deg";
        detail << ", " << static_cast<long>(st.steps / std::max(wall, 1e-9)) << " steps/s";
        progress.update(static_cast<std::int64_t>(fraction), detail.str());
      }
      if (interrupt_requested()) {
        summary.status = "interrupted";
        break;
      }
      if (t >= t_end * (1 - 1e-14)) break;
    }
    if (!stopped_inside_step) checkpoint();
  } catch (const std::exception& e) {
    // The run failed: keep what can be kept and mark the file "failed" with the message. Each step may fail
    // in turn (a full disk fails the flush and maybe the status too); none may replace the run's own error.
    const std::string message = e.what();
    std::string kept;
    try {
      integrator->state(yc, ypc);
      if (yc.allFinite() && ypc.allFinite()) {
        checkpoint_at(integrator->time(), yc, ypc);
        kept = "the " + std::to_string(k) + " samples before are kept in " + options.output.string();
      } else {  // no checkpoint at a non-finite state: a restart goes back to the last good one
        writer->flush_samples();
        kept = "the " + std::to_string(k) + " samples before are kept in " + options.output.string() +
               "; its last checkpoint is the last finite state";
      }
    } catch (const std::exception& save) {
      kept = "saving the last samples failed too (" + std::string(save.what()) + "); " +
             options.output.string() + " keeps the samples up to its last checkpoint";
    }
    try {
      summary.statistics = integrator->statistics();
      writer->finish("failed", message, summary.statistics, wall_seconds());
    } catch (const std::exception& status) {
      kept += "; its status could not be set to \"failed\" (" + std::string(status.what()) + ")";
    }
    throw Error(message + " (" + kept + ")");
  }
  progress.finish();
  summary.end_time = stopped_inside_step ? sample_time(k - 1) : integrator->time();
  summary.samples = k;
  summary.statistics = integrator->statistics();
  summary.wall_seconds = wall_seconds();
  std::string message = summary.status == "complete" ? "" : "stopped by a signal at t = " + std::to_string(summary.end_time) + " s; continue with --restart";
  writer->finish(summary.status, message, summary.statistics, summary.wall_seconds);
  writer->set_drift(summary.max_position_drift, summary.max_velocity_drift);
  if (steady && summary.status == "complete") {  // the kept cycles become the result
    Checkpoint final_state;
    final_state.time = integrator->time();
    integrator->state(final_state.y, final_state.yp);
    summary.steady_state = steady->result();
    write_steady_state_result(options.output, scene, provenance, writer, *summary.steady_state, final_state,
                              summary.statistics, summary.wall_seconds, summary.max_position_drift,
                              summary.max_velocity_drift, log);
  }
  return summary;
}

}  // namespace nvh::solve
