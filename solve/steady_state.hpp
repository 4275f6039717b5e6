#pragma once
// The periodic steady state (docs/scene-format.md section 9, docs/results-format.md "/solver/steady_state").
//
// The run is cut into cycles of the clock's crank angle (or of time) counted from its start. At the end of
// cycle k every watched channel is sampled at N equally spaced phases of the cycle (N = the samples of the
// first cycle; linear interpolation between samples), and set against cycle k - 1 at the same phases:
//
//   change_c = RMS_phases,columns(x_k - x_{k-1}) / max(RMS(x_k), 1e-3 max_j<=k RMS(x_j), floor_c)
//
// (RMS, not the standard deviation; the second term guards a channel that has decayed to ~0, the floor is
// the user's, in the channel's unit; 0 / 0 counts as 0). The change does not bound how far cycle k is from
// the periodic solution: a transient that shrinks by a factor q per cycle is still change q / (1 - q) away
// (the geometric series of the changes to come). So each channel's ratio q = change_k / change_{k-1} is
// estimated, held to [0.5, 0.95] (0.95 at the first comparison, with no ratio yet), and the estimated
// distance to the periodic solution
//
//   distance_c = change_c q / (1 - q)          (>= change_c, at most 19 change_c)
//
// is what the tolerance bounds. A channel whose change grew in one of its last two cycles no longer decays
// geometrically - it sits at its noise floor (the integrator's tolerance, a chaotic contact, a component
// incommensurate with the cycle) - and its distance is its change (q = 0.5). The run has converged when every distance is below the tolerance; it stops
// then, or after max_cycles cycles with a warning.
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "common/hdf5.hpp"
#include "common/input.hpp"
#include "common/log.hpp"
#include "common/provenance.hpp"
#include "solve/steady_state_settings.hpp"

namespace nvh::solve {

struct Scene;
struct Checkpoint;
struct IntegratorStatistics;
class ResultsWriter;

/// Read a [steady_state] table. `clock_markers`: the scene's clock defines a crank angle; `clock_cycle_deg`:
/// the [clock]'s cycle_deg if given (else 0). Errors name the file, line and key.
SteadyStateSettings read_steady_state(const input::Table& t, bool clock_markers, double clock_cycle_deg);

/// Error at `channels` of `t` unless every watched channel names a dataset the scene writes (and a column
/// it has); `paths` and `columns`: the scene's result datasets (results.hpp, result_datasets).
void check_steady_state_channels(const input::Table& t, const SteadyStateSettings& s,
                                 const std::vector<std::string>& paths, const std::vector<int>& columns);

struct SteadyStateResult {
  bool converged = false;
  int cycles = 0;                     // complete cycles run
  std::vector<double> final_change;   // per channel, at the last compared cycle (NaN: none compared)
  std::vector<double> final_distance;  // per channel, the estimated distance to the periodic solution then
  Eigen::MatrixXd change;             // (cycles - 1, channels): the change at the end of each cycle >= 2
  std::vector<long> cycle_first_row;  // the first sample of each cycle (and of the one after the last)
  std::vector<double> cycle_start;    // each cycle's start, in deg or s of the clock (absolute)
  long kept_first = 0, kept_end = 0;  // the rows [first, end) of the kept cycles
  int kept_cycles = 0;
};

class SteadyStateMonitor {
 public:
  /// The watched channels are found among the writer's datasets. `origin`: the crank angle (deg) or the
  /// time (s) of the run's start; cycle k covers [origin + k cycle, origin + (k + 1) cycle).
  SteadyStateMonitor(const SteadyStateSettings& settings, const ResultsWriter& writer, double origin);

  /// One sample, just added to the writer as row `row`, at crank angle (deg) or time (s) `x`. Logs a line
  /// per completed cycle. Returns true when the run is done (converged, or max_cycles cycles complete).
  bool add(double x, long row, const ResultsWriter& writer, const Logger& log);
  /// --restart: the rows [0, rows) already in the file, fed through `add` again (the same cycles result).
  void replay(const h5::Group& root, long rows, const Logger& log);
  bool done() const { return done_; }
  /// The outcome (kept rows decided here); call once the run has ended.
  SteadyStateResult result() const;
  const SteadyStateSettings& settings() const { return s_; }

 private:
  bool add_values(double x, long row, std::span<const double> values, const Logger& log);
  void close_cycle(const Logger& log);

  SteadyStateSettings s_;
  double origin_;
  std::vector<int> dataset_, first_column_, columns_;  // per channel
  std::vector<int> offset_;                            // per channel: its first value in a sample row
  int width_ = 0;                                      // watched values per sample
  std::vector<double> xs_;                             // samples of the open cycle (and the one before)
  std::vector<double> values_;                         // row-major, width_ per sample
  int phases_ = 0;                                     // N, from the first cycle
  Eigen::MatrixXd previous_;                           // (phases, width) of the last cycle
  std::vector<double> largest_rms_;                    // per channel, over the cycles so far
  SteadyStateResult r_;
  std::vector<std::vector<double>> changes_;  // per compared cycle, per channel
  long last_row_ = -1;
  bool done_ = false;
  std::vector<double> scratch_;
};

/// --restart: error if `path` already holds a finished steady-state result (nothing to continue).
void refuse_restart_of_steady_state_result(const std::filesystem::path& path);

/// After the run: write /solver/steady_state into the results file (the writer's), and unless keep_history
/// replace the file by one holding only the kept cycles (written under a temporary name, renamed into place;
/// the history file stays complete until then). `writer` is closed on return.
void write_steady_state_result(const std::filesystem::path& path, const Scene& scene,
                               const Provenance& provenance, std::unique_ptr<ResultsWriter>& writer,
                               const SteadyStateResult& result, const Checkpoint& final_state,
                               const IntegratorStatistics& statistics, double wall_seconds,
                               double max_position_drift, double max_velocity_drift, const Logger& log);

}  // namespace nvh::solve
