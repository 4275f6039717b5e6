#pragma once
// Wall time and memory of the stages of a run, for the user's log and for bench/.
#include <chrono>
#include <string>
#include <vector>

namespace nvh {

/// Peak resident set size of this process so far (VmHWM from /proc/self/status), bytes; 0 if unknown.
long long peak_memory_bytes();

/// Records the wall time and the peak memory at the end of each named stage.
class StageTimer {
 public:
  struct Stage {
    std::string name;
    double seconds = 0.0;
    long long peak_bytes = 0;
  };

  StageTimer() : last_(std::chrono::steady_clock::now()) {}
  /// Close the current stage under `name` (time since the previous call or construction).
  void lap(const std::string& name);
  const std::vector<Stage>& stages() const { return stages_; }
  double total_seconds() const;
  /// A small table: stage, seconds, peak memory in MiB.
  std::string table() const;

 private:
  std::chrono::steady_clock::time_point last_;
  std::vector<Stage> stages_;
};

}  // namespace nvh
