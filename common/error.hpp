#pragma once
// The one error type of the toolchain. Every failure a user can cause (bad input, a missing file,
// a model that cannot be solved) is thrown as nvh::Error with a message that says what was expected;
// when it comes from an input file it also carries the file, line, column and key.
// The CLIs catch it in main(), print it, and exit with a non-zero code (see ExitCode).
#include <cstdio>
#include <stdexcept>
#include <string>

namespace nvh {

/// Where in an input file something was found (1-based line and column; 0 when unknown).
struct SourceLocation {
  std::string file;
  int line = 0;
  int column = 0;
};

/// Exit codes that scripts can rely on (documented in docs/cli.md).
enum class ExitCode : int {
  kSuccess = 0,
  kFailure = 1,     ///< the run failed: bad input, a model that cannot be solved, an I/O error
  kUsage = 2,       ///< bad command line (unknown option, missing argument)
  kInterrupted = 3  ///< stopped by a signal; what was complete is kept
};

class Error : public std::runtime_error {
 public:
  /// An error without a source location (I/O, numerics).
  explicit Error(const std::string& message);
  /// An error in an input file: "file:line:column: key: message".
  Error(const std::string& message, SourceLocation where, std::string key);

  const std::string& message() const { return message_; }
  const SourceLocation& where() const { return where_; }
  const std::string& key() const { return key_; }

 private:
  std::string message_;
  SourceLocation where_;
  std::string key_;
};

/// A number for a message, in scientific notation with three significant digits ("1.23e-07").
inline std::string scientific(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2e", value);
  return text;
}

}  // namespace nvh
