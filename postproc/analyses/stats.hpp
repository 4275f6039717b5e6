#pragma once
// postproc stats: RMS, peak, crest factor, band RMS and harmonics of the running speed (docs/postproc.md
// sections 3.4, 4.4, 5).
#include <optional>
#include <utility>
#include <vector>

#include "common/log.hpp"
#include "postproc/options.hpp"

namespace nvh::postproc {

struct StatsCommand {
  CommonOptions common;
  std::optional<std::pair<double, double>> band_hz;  ///< band-limited RMS over [lo, hi]
  double band_resolution_hz = 1.0;
  std::vector<double> harmonics;  ///< orders of the running speed (needs the angle)
  AngleSource angle;
  double cycle_deg = 360.0;
};

/// Runs the analysis on every signal and writes `common.output`; an error leaves no output.
void run_stats(const StatsCommand& command, const Logger& log, int argc, const char* const* argv);

}  // namespace nvh::postproc
