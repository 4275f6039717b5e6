#include "common/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>
#include <sstream>
#include <utility>

namespace nvh {
namespace {

using Clock = std::chrono::steady_clock;

constexpr auto kBarRedraw = std::chrono::milliseconds(100);
constexpr int kBarWidth = 30;

Progress::Style resolve(const Logger& logger, Progress::Style requested) {
  if (logger.verbosity() == Verbosity::kQuiet) return Progress::Style::kNone;  // quiet means quiet
  if (requested != Progress::Style::kAuto) return requested;
  const bool terminal = &logger.stream() == &std::cerr && isatty(fileno(stderr)) == 1;
  return terminal ? Progress::Style::kBar : Progress::Style::kLines;
}

double seconds_since(Clock::time_point start, Clock::time_point now) {
  return std::chrono::duration<double>(now - start).count();
}

/// "0.4 s", "12.3 s", "2 min 05 s", "1 h 02 min".
std::string format_duration(double s, bool tenths = true) {
  char buffer[64];
  if (!(s >= 0.0) || !std::isfinite(s)) s = 0.0;
  if (s < 59.95 && tenths) {
    std::snprintf(buffer, sizeof buffer, "%.1f s", s);
  } else if (s < 59.5) {
    std::snprintf(buffer, sizeof buffer, "%.0f s", s);
  } else if (s < 3600.0) {
    const long total = std::lround(s);
    std::snprintf(buffer, sizeof buffer, "%ld min %02ld s", total / 60, total % 60);
  } else {
    const long minutes = std::lround(s / 60.0);
    std::snprintf(buffer, sizeof buffer, "%ld h %02ld min", minutes / 60, minutes % 60);
  }
  return buffer;
}

}  // namespace

Progress::Progress(const Logger& logger, std::string label, std::int64_t total, Style style,
                   std::chrono::seconds line_interval)
    : logger_(logger),
      label_(std::move(label)),
      total_(total),
      style_(resolve(logger, style)),
      line_interval_(std::max(line_interval, std::chrono::seconds(0))),
      start_(Clock::now()),
      last_line_(start_) {}

Progress::~Progress() {
  try {
    if (finished_) return;
    if (std::uncaught_exceptions() > 0) {
      // Unwinding after a failure: no "done" line; just end a drawn bar so the error starts on its own line.
      finished_ = true;
      if (style_ == Style::kBar && last_percent_ >= 0) logger_.stream() << '\n' << std::flush;
      return;
    }
    finish();
  } catch (...) {
    // never throw from a destructor
  }
}

void Progress::update(std::int64_t done) {
  if (style_ == Style::kNone || finished_) return;
  const auto now = Clock::now();
  const bool known_total = total_ > 0;
  const std::int64_t shown =
      known_total ? std::clamp<std::int64_t>(done, 0, total_) : std::max<std::int64_t>(done, 0);
  const int percent = known_total ? static_cast<int>((shown * 100) / total_) : 0;
  const double elapsed = seconds_since(start_, now);

  if (style_ == Style::kBar) {
    if (last_percent_ >= 0 && now - last_line_ < kBarRedraw) return;
    std::ostringstream line;
    line << "\r[" << label_ << "] ";
    if (known_total) {
      const int filled = static_cast<int>((shown * kBarWidth) / total_);
      line << '[' << std::string(filled, '#') << std::string(kBarWidth - filled, '.') << "] ";
      line << (percent < 10 ? "  " : percent < 100 ? " " : "") << percent << '%';
    } else {
      line << shown << " done";
    }
    line << "  " << format_duration(elapsed) << "  ";
    if (!detail_.empty()) line << detail_ << "  ";
    logger_.stream() << line.str() << std::flush;
    last_line_ = now;
    last_percent_ = percent;
    return;
  }

  // kLines: at most one line per interval; with a zero interval, one per change of the percentage.
  if (last_percent_ >= 0 || line_interval_.count() > 0) {
    if (now - last_line_ < line_interval_) return;
    if (line_interval_.count() == 0 && percent == last_percent_) return;
  }
  std::ostringstream line;
  line << label_ << ": ";
  if (known_total) {
    line << percent << "% (" << shown << '/' << total_ << "), " << format_duration(elapsed) << " elapsed";
    if (shown > 0 && shown < total_) {
      const double left = elapsed * static_cast<double>(total_ - shown) / static_cast<double>(shown);
      line << ", ~" << format_duration(left, false) << " left";
    }
  } else {
    line << shown << " done, " << format_duration(elapsed) << " elapsed";
  }
  if (!detail_.empty()) line << "; " << detail_;
  logger_.info(line.str());
  last_line_ = now;
  last_percent_ = percent;
}

void Progress::update(std::int64_t done, const std::string& detail) {
  detail_ = detail;
  update(done);
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (style_ == Style::kNone) return;
  if (style_ == Style::kBar && last_percent_ >= 0) {
    // Wipe the bar; the final line replaces it.
    logger_.stream() << '\r' << std::string(label_.size() + 3 + kBarWidth + 3 + 24, ' ') << '\r';
  }
  logger_.info(label_ + ": done in " + format_duration(seconds_since(start_, Clock::now())));
}

}  // namespace nvh
