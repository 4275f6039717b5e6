#include "postproc/analysis_window.hpp"

#include <cmath>
#include <sstream>

#include "common/error.hpp"

namespace nvh::postproc {

std::string AnalysisWindow::describe() const {
  std::ostringstream s;
  s.precision(10);
  if (start_s) s << " --start " << *start_s;
  if (end_s) s << " --end " << *end_s;
  if (skip_cycles > 0) s << " --skip-cycles " << skip_cycles;
  if (angle_from_deg) s << " --angle-window " << *angle_from_deg << "," << angle_to_deg.value_or(0.0);
  if (angle_period_deg) s << " --angle-period " << *angle_period_deg;
  return s.str().empty() ? std::string() : s.str().substr(1);
}

SampleRange time_window_samples(const SignalInfo& info, double file_start_s, std::int64_t file_size,
                                const AnalysisWindow& window) {
  const double fs = info.sample_rate_hz;
  const double t_last = file_start_s + static_cast<double>(file_size - 1) / fs;
  const double tolerance = 1e-6 / fs;  // a time given to within a micro-sample is on the sample
  std::ostringstream span;
  span.precision(10);
  span << "signal '" << info.address << "' spans " << file_start_s << " to " << t_last << " s";
  auto check_inside = [&](const char* option, double t) {
    if (!std::isfinite(t) || t < file_start_s - tolerance || t > t_last + tolerance) {
      std::ostringstream msg;
      msg.precision(10);
      msg << option << " " << t << " s is outside the signal: " << span.str();
      throw Error(msg.str());
    }
  };
  if (window.start_s) check_inside("--start", *window.start_s);
  if (window.end_s) check_inside("--end", *window.end_s);
  const double start = window.start_s.value_or(file_start_s);
  const double end = window.end_s.value_or(t_last);
  if (start >= end) {
    std::ostringstream msg;
    msg.precision(10);
    msg << "--start " << start << " s is not before --end " << end << " s; expected start < end";
    throw Error(msg.str());
  }
  SampleRange r;
  r.first = static_cast<std::int64_t>(std::ceil((start - file_start_s) * fs - 1e-6));
  const auto last = static_cast<std::int64_t>(std::floor((end - file_start_s) * fs + 1e-6));
  r.first = std::max<std::int64_t>(r.first, 0);
  r.count = std::min(last, file_size - 1) - r.first + 1;
  if (r.count < 2) {
    std::ostringstream msg;
    msg.precision(10);
    msg << window.describe() << ": the window holds " << std::max<std::int64_t>(r.count, 0)
        << " sample(s) of '" << info.address << "'; expected at least 2";
    throw Error(msg.str());
  }
  return r;
}

AngleSpan angle_window_span(const AnalysisWindow& window, double first_deg, double last_deg,
                            const std::string& address) {
  std::ostringstream msg;
  msg.precision(10);
  const double a0 = window.angle_from_deg.value_or(0.0), a1 = window.angle_to_deg.value_or(0.0);
  if (!window.angle_from_deg || !window.angle_to_deg || !std::isfinite(a0) || !std::isfinite(a1) ||
      a0 >= a1) {
    msg << "--angle-window " << a0 << "," << a1
        << ": expected two finite angles FROM,TO in deg with FROM < TO";
    throw Error(msg.str());
  }
  const double tolerance = 1e-9 * (std::abs(a0) + std::abs(a1) + std::abs(last_deg) + 1.0);
  AngleSpan span{a0, a1};
  if (window.angle_period_deg) {
    const double p = *window.angle_period_deg;
    if (!std::isfinite(p) || p < a1 - a0) {
      msg << "--angle-period " << p << ": expected at least the window's length " << a1 - a0 << " deg";
      throw Error(msg.str());
    }
    // The largest integer k with a1 + k p <= last: the last whole occurrence.
    const double k = std::floor((last_deg - a1 + tolerance) / p);
    span = {a0 + k * p, a1 + k * p};
  }
  if (span.from_deg < first_deg - tolerance || span.to_deg > last_deg + tolerance) {
    msg << window.describe() << ": the shaft angle '" << address << "' runs from " << first_deg << " to "
        << last_deg << " deg in the signal's window; expected the angle window [" << span.from_deg << ", "
        << span.to_deg << "] deg inside it";
    throw Error(msg.str());
  }
  return span;
}

AngleWindowFinder::AngleWindowFinder(AngleSpan span)
    : span_(span), tolerance_(1e-9 * (std::abs(span.from_deg) + std::abs(span.to_deg) + 1.0)) {}

void AngleWindowFinder::push(std::span<const double> angle_deg) {
  for (std::size_t i = 0; i < angle_deg.size(); ++i) {
    const double a = angle_deg[i];
    if (a >= span_.from_deg - tolerance_ && a <= span_.to_deg + tolerance_) {
      const std::int64_t index = seen_ + static_cast<std::int64_t>(i);
      if (first_ < 0) first_ = index;
      last_ = index;
    }
  }
  seen_ += static_cast<std::int64_t>(angle_deg.size());
}

bool CycleSkipper::push(std::span<const double> angle_deg) {
  if (found_) return true;
  for (std::size_t i = 0; i < angle_deg.size(); ++i) {
    if (!started_) {
      // The first boundary at or after the window's first angle, then N cycles on.
      target_ = (std::ceil(angle_deg[i] / cycle_deg_ - 1e-9) + cycles_) * cycle_deg_;
      started_ = true;
    }
    if (angle_deg[i] >= target_ - 1e-9 * cycle_deg_) {
      found_ = true;
      sample_ = seen_ + static_cast<std::int64_t>(i);
      return true;
    }
  }
  seen_ += static_cast<std::int64_t>(angle_deg.size());
  return false;
}

}  // namespace nvh::postproc
