#include "common/resources.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

namespace nvh {

long long peak_memory_bytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) {
      std::istringstream s(line.substr(6));
      long long kib = 0;
      s >> kib;
      return kib * 1024;
    }
  }
  return 0;
}

void StageTimer::lap(const std::string& name) {
  const auto now = std::chrono::steady_clock::now();
  stages_.push_back({name, std::chrono::duration<double>(now - last_).count(), peak_memory_bytes()});
  last_ = now;
}

double StageTimer::total_seconds() const {
  double total = 0.0;
  for (const Stage& s : stages_) total += s.seconds;
  return total;
}

std::string StageTimer::table() const {
  std::ostringstream out;
  char line[160];
  std::snprintf(line, sizeof line, "  %-22s %10s %14s\n", "stage", "wall [s]", "peak RSS [MiB]");
  out << line;
  for (const Stage& s : stages_) {
    std::snprintf(line, sizeof line, "  %-22s %10.3f %14.1f\n", s.name.c_str(), s.seconds,
                  static_cast<double>(s.peak_bytes) / (1024.0 * 1024.0));
    out << line;
  }
  std::snprintf(line, sizeof line, "  %-22s %10.3f\n", "total", total_seconds());
  out << line;
  return out.str();
}

}  // namespace nvh
