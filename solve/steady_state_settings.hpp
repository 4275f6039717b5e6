#pragma once
// The [steady_state] table of a scene (docs/scene-format.md section 9): run cycles until the watched result
// channels repeat from one cycle to the next within a tolerance, then keep the last cycles as the result.
#include <string>
#include <vector>

namespace nvh::solve {

struct SteadyStateSettings {
  /// Result datasets as in the results file ("forces/spring/tension", "markers/block.top/acceleration"),
  /// without the leading '/'; a trailing "[k]" watches column k only (0-based, as postproc's signal paths).
  std::vector<std::string> channels;
  std::vector<double> floors;  // per channel, in its unit: the least RMS it is measured against (0: none)
  double tolerance = 1e-3;     // relative change from one cycle to the next
  int max_cycles = 50;
  int keep_cycles = 1;        // the last cycles written as the result
  bool keep_history = false;  // true: every sample stays in the file, the kept cycles are marked
  bool by_angle = true;       // cycles of the clock's crank angle (cycle in deg), else of time (cycle in s)
  double cycle = 720;         // deg or s
};

}  // namespace nvh::solve
