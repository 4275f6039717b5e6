#include "solve/run.hpp"

#include <chrono>
#include <cmath>
#include <numbers>
#include <sstream>

#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "solve/results.hpp"

namespace nvh::solve {

RunSummary run_scene(Scene& scene, const RunOptions& options, const Provenance& provenance, const Logger& log) {
  const auto wall_start = std::chrono::steady_clock::now();
  // From here a signal only sets a flag: the results file, once created, is always left with a status the
  // loop below writes ("interrupted" with a checkpoint), never "running" without one.
  struct GracefulInterrupts {
    GracefulInterrupts() { set_graceful_interrupt(true); }
    ~GracefulInterrupts() { set_graceful_interrupt(false); }
  } graceful;
  Model& model = scene.model;
  Eigen::VectorXd y, yp;
  double t0 = scene.start_time;
  long first_sample = 0;
  std::unique_ptr<ResultsWriter> writer;

  if (options.restart) {
    Checkpoint cp;
    writer = std::make_unique<ResultsWriter>(ResultsWriter::reopen(options.output, scene, cp));
    // Redundant equations are found again from the start configuration (the same scene gives the same set).
    Eigen::VectorXd y_start, yp_start;
    model.consistent_initial_state(scene.start_time, y_start, yp_start, log);
    y = cp.y;
    yp = cp.yp;
    t0 = cp.time;
    first_sample = cp.samples;
    log.info("restarting from the checkpoint at t = " + std::to_string(t0) + " s (" + std::to_string(first_sample) +
             " samples kept)");
  } else {
    model.consistent_initial_state(t0, y, yp, log);
    writer = std::make_unique<ResultsWriter>(ResultsWriter::create(options.output, scene, provenance));
  }
  const double angle_start =
      options.restart ? 0.0 : model.crank_angle(y.data());  // end-by-angle: measured from the start angle
  double angle_origin = angle_start;
  if (options.restart && scene.end_angle_deg > 0) {
    // the start angle of the original run: recomputed from a fresh consistent start
    Eigen::VectorXd y0, yp0;
    model.consistent_initial_state(scene.start_time, y0, yp0, log);
    angle_origin = model.crank_angle(y0.data());
  }

  auto integrator = make_integrator(model, scene.integrator, t0, y, yp);
  const double dt = 1.0 / scene.output.sample_rate_hz;
  const double t_end = scene.end_time;
  const bool by_angle = scene.end_angle_deg > 0;
  const double end_angle = scene.end_angle_deg * std::numbers::pi / 180.0;
  long k = first_sample;
  auto sample_time = [&](long i) { return scene.start_time + static_cast<double>(i) * dt; };

  const std::int64_t total = by_angle ? static_cast<std::int64_t>(scene.end_angle_deg) : std::int64_t(1000);
  Progress progress(log, "solve", total, options.progress);
  RunSummary summary;
  summary.status = "complete";
  long since_flush = 0;
  auto checkpoint = [&] {
    Checkpoint cp;
    cp.time = integrator->time();
    integrator->state(cp.y, cp.yp);
    const auto [dp, dv] = model.constraint_violation(cp.time, cp.y.data());
    summary.max_position_drift = std::max(summary.max_position_drift, dp);
    summary.max_velocity_drift = std::max(summary.max_velocity_drift, dv);
    // Samples up to the integrator's time are written; the next run continues after them.
    writer->flush(cp);
    since_flush = 0;
  };
  Eigen::VectorXd ys, yps;
  double last_detail = -1.0;
  try {
    bool done = false;
    while (!done) {
      const double target = sample_time(k);
      if (target > t_end + 1e-9 * dt) break;
      const double t = integrator->advance(target, t_end);
      while (!done && sample_time(k) <= t + 1e-9 * dt && sample_time(k) <= t_end + 1e-9 * dt) {
        integrator->interpolate(std::min(sample_time(k), t), ys, yps);
        if (by_angle && model.crank_angle(ys.data()) - angle_origin > end_angle * (1 + 1e-9)) {
          done = true;
          break;
        }
        writer->add_sample(sample_time(k), scene, ys, yps);
        ++k;
        ++since_flush;
        if (!ys.allFinite())
          throw Error("the solution is not finite at t = " + std::to_string(sample_time(k - 1)) + " s");
      }
      if (since_flush >= scene.output.chunk_samples) checkpoint();
      const double fraction =
          by_angle ? (model.crank_angle(ys.data()) - angle_origin) * 180.0 / std::numbers::pi
                   : 1000.0 * (t - scene.start_time) / std::max(1e-300, t_end - scene.start_time);
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
      if (wall - last_detail >= 0.5) {  // the detail (statistics, formatting) at most twice a second
        last_detail = wall;
        const IntegratorStatistics st = integrator->statistics();
        std::ostringstream detail;
        detail.precision(4);
        detail << "t = " << t << " s";
        if (model.clock) detail << ", " << model.crank_angle(ys.data()) * 180.0 / std::numbers::pi << " deg";
        detail << ", " << static_cast<long>(st.steps / std::max(wall, 1e-9)) << " steps/s";
        progress.update(static_cast<std::int64_t>(fraction), detail.str());
      }
      if (interrupt_requested()) {
        summary.status = "interrupted";
        break;
      }
      if (t >= t_end * (1 - 1e-14)) break;
    }
  } catch (const Error& e) {
    checkpoint();
    summary.statistics = integrator->statistics();
    writer->finish("failed", e.what(), summary.statistics,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count());
    throw Error(std::string(e.what()) + " (the " + std::to_string(k) + " samples before are kept in " +
                options.output.string() + ")");
  }
  checkpoint();
  progress.finish();
  summary.end_time = integrator->time();
  summary.samples = k;
  summary.statistics = integrator->statistics();
  summary.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  std::string message = summary.status == "complete" ? "" : "stopped by a signal at t = " + std::to_string(summary.end_time) + " s; continue with --restart";
  writer->finish(summary.status, message, summary.statistics, summary.wall_seconds);
  writer->set_drift(summary.max_position_drift, summary.max_velocity_drift);
  return summary;
}

}  // namespace nvh::solve
