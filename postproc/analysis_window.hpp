#pragma once
// The analysis window: the part of a signal an analysis sees, so that a simulation's start transient can be
// left out (docs/postproc.md section 2.1).
//
//   --start S, --end E    samples whose time t = t_0 + i / f_s lies in [S, E] (t_0: the signal's first
//                         time; both in the signal's own time axis, s)
//   --skip-cycles N       then the window starts at the N-th shaft-cycle boundary: the first sample with
//                         theta >= theta_c + N cycle_deg, theta_c the first multiple of cycle_deg at or after
//                         the angle at the window's first sample (N whole cycles of the shaft are dropped)
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "postproc/signal.hpp"

namespace nvh::postproc {

struct AnalysisWindow {
  std::optional<double> start_s;  ///< --start: first time analysed, s (default: the signal's first sample)
  std::optional<double> end_s;    ///< --end: last time analysed, s (default: the signal's last sample)
  int skip_cycles = 0;            ///< --skip-cycles: whole shaft cycles dropped after start_s
  bool active() const { return start_s || end_s || skip_cycles > 0; }
  /// "--start 0.5 --end 2" etc., for messages.
  std::string describe() const;
};

struct SampleRange {
  std::int64_t first = 0;  ///< first sample, counted in the file
  std::int64_t count = 0;
};

/// The samples of the time window of `window` (start_s / end_s; skip_cycles is applied later with the shaft
/// angle, CycleSkipper). `file_start_s`, `file_size` describe the unrestricted signal. Errors name the
/// option: a time outside the signal, start >= end, fewer than 2 samples.
SampleRange time_window_samples(const SignalInfo& info, double file_start_s, std::int64_t file_size,
                                const AnalysisWindow& window);

/// Finds, in a stream of consecutive angle blocks (deg, increasing), the first sample at or past the N-th
/// cycle boundary (see the header comment).
class CycleSkipper {
 public:
  CycleSkipper(double cycle_deg, int cycles) : cycle_deg_(cycle_deg), cycles_(cycles) {}
  /// Feed the next block; true once the boundary is reached (later calls change nothing).
  bool push(std::span<const double> angle_deg);
  bool found() const { return found_; }
  /// Index (from the first sample pushed) of the first sample with angle >= target_deg().
  std::int64_t sample() const { return sample_; }
  double target_deg() const { return target_; }

 private:
  double cycle_deg_;
  int cycles_;
  bool started_ = false, found_ = false;
  double target_ = 0.0;
  std::int64_t seen_ = 0, sample_ = -1;
};

}  // namespace nvh::postproc
