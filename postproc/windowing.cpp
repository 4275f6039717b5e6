#include "postproc/windowing.hpp"

#include <cmath>
#include <optional>
#include <sstream>
#include <vector>

#include "common/error.hpp"
#include "postproc/output.hpp"
#include "postproc/shaft_angle.hpp"
#include "postproc/signal_input.hpp"

namespace nvh::postproc {

namespace {

/// --angle-window on a signal already restricted to the time window `range`: the samples whose shaft angle
/// (the dataset --window-angle, sampled with the signal) lies in the span of angle_window_span().
void apply_angle_window(SignalSource& signal, const SampleRange& range, const AnalysisWindow& window,
                        std::int64_t block, const Logger& log) {
  if (window.skip_cycles > 0)
    throw Error("--angle-window and --skip-cycles exclude each other; expected one of them");
  const SignalInfo& info = signal.info();
  SignalSource angle = SignalSource::open(window_angle_address(info, window));
  if (angle.size() != signal.file_size() ||
      std::abs(angle.info().sample_rate_hz - info.sample_rate_hz) > 1e-9 * info.sample_rate_hz) {
    std::ostringstream msg;
    msg << "--angle-window: the shaft angle '" << angle.info().address << "' (" << angle.size()
        << " samples at " << angle.info().sample_rate_hz << " Hz) does not match signal '" << info.address
        << "' (" << signal.file_size() << " samples at " << info.sample_rate_hz
        << " Hz); expected an angle sampled with the signal (--window-angle)";
    throw Error(msg.str());
  }
  angle.restrict_to(range.first, range.count);
  std::vector<double> first(1), last(1);
  angle.read(0, first);
  angle.read(angle.size() - 1, last);
  if (!(last[0] > first[0])) {
    std::ostringstream msg;
    msg << "--angle-window: the shaft angle '" << angle.info().address
        << "' does not increase over the window (" << first[0] << " to " << last[0]
        << " deg); expected an unwrapped, increasing angle in deg";
    throw Error(msg.str());
  }
  AngleWindowFinder finder(angle_window_span(window, first[0], last[0], angle.info().address));
  for_each_block(angle, block, log, "angle window",
                 [&](std::int64_t, std::span<const double> a) { finder.push(a); });
  const SampleRange inside = finder.range();
  if (inside.count < 2) {
    std::ostringstream msg;
    msg << window.describe() << ": the angle window holds " << inside.count << " sample(s) of '"
        << info.address << "'; expected at least 2";
    throw Error(msg.str());
  }
  signal.restrict_to(range.first + inside.first, inside.count);
}

}  // namespace

Eigen::VectorXd shaft_angle_at_samples(const SignalSource& signal, const AnalysisWindow& window) {
  const SignalInfo& info = signal.info();
  if (!window.angle_address.empty() && window.angle_address[0] == '/' && info.file.empty()) return {};
  std::optional<SignalSource> angle;
  try {
    angle.emplace(SignalSource::open(window_angle_address(info, window)));
  } catch (const Error&) {
    if (window.angle_active()) throw;
    return {};  // a signal without a shaft angle: time only
  }
  if (angle->size() != signal.file_size()) return {};
  angle->restrict_to(signal.first_sample(), signal.size());
  const std::vector<double> a = angle->read_all();
  return Eigen::Map<const Eigen::VectorXd>(a.data(), static_cast<Eigen::Index>(a.size()));
}

std::string window_angle_address(const SignalInfo& signal, const AnalysisWindow& window) {
  const std::string& address = window.angle_address;
  return !address.empty() && address[0] == '/' ? signal.file.string() + ":" + address : address;
}

/// Restrict `signal` to the analysis window: --start/--end, then --skip-cycles with the shaft angle
/// (`angle` may be null when the subcommand has none) or --angle-window. No-op without a window.
void apply_window(SignalSource& signal, const AnalysisWindow& window, const AngleSource* angle,
                  double cycle_deg, std::int64_t block, const Logger& log) {
  if (!window.active()) return;
  const SampleRange range =
      time_window_samples(signal.info(), signal.file_start_time_s(), signal.file_size(), window);
  signal.restrict_to(range.first, range.count);
  if (window.angle_active()) {
    apply_angle_window(signal, range, window, block, log);
    return;
  }
  if (window.skip_cycles <= 0) return;
  if (!angle) throw Error("--skip-cycles needs a shaft angle; this subcommand has none");
  AngleProvider provider(*angle, signal, block, log);
  CycleSkipper skipper(cycle_deg, window.skip_cycles);
  std::vector<double> a;
  for (std::int64_t offset = 0; offset < signal.size() && !skipper.found(); offset += block) {
    a.resize(static_cast<std::size_t>(std::min(block, signal.size() - offset)));
    provider.read(offset, a);
    skipper.push(a);
  }
  if (!skipper.found() || signal.size() - skipper.sample() < 2) {
    std::ostringstream msg;
    msg << "--skip-cycles " << window.skip_cycles << ": signal '" << signal.info().address
        << "' does not reach the shaft angle " << skipper.target_deg() << " deg (" << window.skip_cycles
        << " whole cycles of " << cycle_deg << " deg) inside the window; expected fewer cycles to skip";
    throw Error(msg.str());
  }
  signal.restrict_to(range.first + skipper.sample(), range.count - skipper.sample());
  log.detail(signal.info().name + ": --skip-cycles " + std::to_string(window.skip_cycles) +
             ": analysis starts at " + std::to_string(signal.info().start_time_s) + " s");
}

/// The cycles of `all` (tracked over the samples of `read`, a window with margins) lying wholly inside the
/// samples `window` of `read`; start times shifted to count from the file's first sample.
OrderSpectra cycles_in_window(const OrderSpectra& all, const SampleRange& window, const SignalSource& read) {
  const double fs = read.info().sample_rate_hz;
  const double from = static_cast<double>(window.first) / fs,
               to = static_cast<double>(window.first + window.count - 1) / fs;
  // To within a sample: the first sample of a window set by --skip-cycles is the one at or just after the
  // boundary, so the boundary itself may lie up to one sample before it.
  const double slack = 1.0 / fs;
  std::vector<Eigen::Index> keep;
  for (Eigen::Index c = 0; c < all.rpm.size(); ++c) {
    const double end = all.start_time_s[c] + 60.0 * (all.cycle_deg / 360.0) / all.rpm[c];  // next boundary
    if (all.start_time_s[c] >= from - slack && end <= to + slack) keep.push_back(c);
  }
  OrderSpectra s = all;
  const auto n = static_cast<Eigen::Index>(keep.size());
  s.amplitude.resize(n, all.amplitude.cols());
  s.phase_deg.resize(n, all.phase_deg.cols());
  s.rpm.resize(n);
  s.start_time_s.resize(n);
  for (Eigen::Index r = 0; r < n; ++r) {
    s.amplitude.row(r) = all.amplitude.row(keep[r]);
    s.phase_deg.row(r) = all.phase_deg.row(keep[r]);
    s.rpm[r] = all.rpm[keep[r]];
    s.start_time_s[r] = all.start_time_s[keep[r]] + static_cast<double>(read.first_sample()) / fs;
  }
  return s;
}

/// Adds the window to an error of an analysis that the window made too short: the message names the options.
[[noreturn]] void rethrow_in_window(const Error& e, const AnalysisWindow& window, const SignalSource& s) {
  if (!window.active()) throw e;
  std::ostringstream msg;
  msg << e.what() << " (analysis window " << window.describe() << ": " << s.size() << " samples, "
      << s.info().start_time_s << " to " << window_end_s(s.info()) << " s; widen the window)";
  throw Error(msg.str());
}

}  // namespace nvh::postproc
