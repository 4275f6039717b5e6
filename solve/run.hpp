#pragma once
// Running a scene: consistent start, the time loop with sampled output, checkpoints, progress, and clean
// ends on failure or on SIGTERM/SIGINT.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/log.hpp"
#include "common/progress.hpp"
#include "common/provenance.hpp"
#include "solve/scene.hpp"
#include "solve/steady_state.hpp"

namespace nvh::solve {

struct RunOptions {
  std::filesystem::path output;
  bool restart = false;
  Progress::Style progress = Progress::Style::kAuto;
};

struct RunSummary {
  std::string status;  // "complete", "interrupted"
  double end_time = 0;
  long samples = 0;
  IntegratorStatistics statistics;
  double wall_seconds = 0;
  double max_position_drift = 0;  // largest |Phi| over the checkpoints (m or rad)
  double max_velocity_drift = 0;  // largest |C w + Phi_t| over the checkpoints
  std::optional<SteadyStateResult> steady_state;  // with [steady_state]: cycles, convergence, kept rows
};

/// The unknowns that held the integrator's error test in most accepted steps (IntegratorStatistics::
/// error_test_steps), the `leading` first, each with its share of the steps: "body 'valve' w[0] (speed
/// s') 73 %, ...". Empty if nothing was counted.
std::string error_test_holders(const Model& model, const std::vector<long>& steps, int leading = 3);

/// Integrate `scene` and write the results file. Throws nvh::Error on a failed run after marking the file
/// "failed" with the message (the samples so far are kept).
RunSummary run_scene(Scene& scene, const RunOptions& options, const Provenance& provenance, const Logger& log);

}  // namespace nvh::solve
