#pragma once
// Logging for the CLIs. No global logger: main() makes one and hands it down; libraries take a
// `Logger&` only where they report progress, and never print otherwise.
#include <ostream>
#include <string>

namespace nvh {

enum class Verbosity { kQuiet = 0, kNormal = 1, kVerbose = 2 };

class Logger {
 public:
  /// Writes to `out` (std::cerr in the tools). Messages are prefixed "[tool] " and, for warnings and
  /// errors, "warning: " / "error: ".
  Logger(std::ostream& out, std::string tool, Verbosity verbosity = Verbosity::kNormal);

  void info(const std::string& message) const;     ///< shown unless quiet
  void detail(const std::string& message) const;   ///< shown when verbose
  void warning(const std::string& message) const;  ///< always shown
  void error(const std::string& message) const;    ///< always shown

  Verbosity verbosity() const { return verbosity_; }
  std::ostream& stream() const { return out_; }
  const std::string& tool() const { return tool_; }

 private:
  std::ostream& out_;
  std::string tool_;
  Verbosity verbosity_;
};

}  // namespace nvh
