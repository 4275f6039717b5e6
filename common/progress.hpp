#pragma once
// Progress of long work: a redrawn bar on a terminal, plain periodic lines in batch logs (Slurm, make).
//
//   nvh::Progress bar(logger, "eigen-solve", total_steps);
//   for (...) bar.update(done);
//   bar.finish();
#include <chrono>
#include <cstdint>
#include <string>

#include "common/log.hpp"

namespace nvh {

class Progress {
 public:
  enum class Style { kAuto, kBar, kLines, kNone };

  /// kAuto: a bar if the logger's stream is a terminal (isatty on stderr), else lines;
  /// nothing when the logger is quiet. Lines are written at most every `line_interval`.
  Progress(const Logger& logger, std::string label, std::int64_t total, Style style = Style::kAuto,
           std::chrono::seconds line_interval = std::chrono::seconds(10));
  ~Progress();  // finishes if not finished
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void update(std::int64_t done);
  /// A better estimate of the total (an iteration that needs more steps than first thought).
  void set_total(std::int64_t total) { total_ = total; }
  /// The same with a detail appended to the bar or line (e.g. "t = 0.12 s, 1440 deg, 850 steps/s").
  void update(std::int64_t done, const std::string& detail);
  /// Final line with the elapsed time ("label: done in 3.2 s").
  void finish();

  Style style() const { return style_; }

 private:
  const Logger& logger_;
  std::string label_;
  std::int64_t total_;
  Style style_;
  std::chrono::seconds line_interval_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_line_;
  int last_percent_ = -1;
  bool finished_ = false;
  std::string detail_;
};

}  // namespace nvh
