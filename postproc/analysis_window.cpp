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
