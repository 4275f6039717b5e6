#pragma once
// The analysis window: the part of a signal an analysis sees, so that a simulation's start transient can be
// left out (docs/postproc.md section 2.1).
//
//   --start S, --end E    samples whose time t = t_0 + i / f_s lies in [S, E] (t_0: the signal's first
//                         time; both in the signal's own time axis, s)
//   --skip-cycles N       then the window starts at the N-th shaft-cycle boundary: the first sample with
//                         theta >= theta_c + N cycle_deg, theta_c the first multiple of cycle_deg at or after
//                         the angle at the window's first sample (N whole cycles of the shaft are dropped)
//   --angle-window A0,A1  then only the samples whose shaft angle theta (deg, unwrapped, the dataset
//                         --window-angle, default /crank_angle_deg of the signal's own file) lies in
//                         [A0, A1]; with --angle-period P the window is [A0 + k P, A1 + k P] for the
//                         largest integer k whose window lies wholly inside the signal (its last whole
//                         occurrence: the last cycle of a run, e.g. -30..+90 deg about a cylinder's firing
//                         TDC with P = 720)
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
  std::optional<double> angle_from_deg;    ///< --angle-window: first shaft angle analysed, deg
  std::optional<double> angle_to_deg;      ///< --angle-window: last shaft angle analysed, deg
  std::optional<double> angle_period_deg;  ///< --angle-period: the window repeats with this period, deg
  std::string angle_address = "/crank_angle_deg";  ///< --window-angle: the unwrapped shaft angle, deg
  bool angle_active() const { return angle_from_deg.has_value(); }
  bool active() const { return start_s || end_s || skip_cycles > 0 || angle_active(); }
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

/// A span of shaft angle, deg.
struct AngleSpan {
  double from_deg = 0.0;
  double to_deg = 0.0;
};

/// The shaft-angle span of `window` (--angle-window, --angle-period) on a signal whose (increasing) angle
/// runs from `first_deg` to `last_deg`: [A0, A1], or [A0 + k P, A1 + k P] with the largest k that fits.
/// Errors name the options and `address` (the angle signal): A0 >= A1, a span outside the angle's range, a
/// period not longer than the span.
AngleSpan angle_window_span(const AnalysisWindow& window, double first_deg, double last_deg,
                            const std::string& address);

/// Finds, in a stream of consecutive angle blocks (deg, increasing), the samples whose angle lies in a span
/// (to within 1e-9 of the span's magnitude, so that a sample on a bound is in).
class AngleWindowFinder {
 public:
  explicit AngleWindowFinder(AngleSpan span);
  void push(std::span<const double> angle_deg);
  /// The samples inside the span, counted from the first sample pushed (count 0: none).
  SampleRange range() const { return {first_ < 0 ? 0 : first_, first_ < 0 ? 0 : last_ - first_ + 1}; }

 private:
  AngleSpan span_;
  double tolerance_;
  std::int64_t seen_ = 0, first_ = -1, last_ = -1;
};

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
