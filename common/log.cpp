#include "common/log.hpp"

#include <utility>

namespace nvh {
namespace {

void write(std::ostream& out, const std::string& tool, const char* kind, const std::string& message) {
  if (!tool.empty()) out << '[' << tool << "] ";
  out << kind << message << '\n';
  out.flush();  // batch logs (Slurm, make) should show each line when it happens
}

}  // namespace

Logger::Logger(std::ostream& out, std::string tool, Verbosity verbosity)
    : out_(out), tool_(std::move(tool)), verbosity_(verbosity) {}

void Logger::info(const std::string& message) const {
  if (verbosity_ >= Verbosity::kNormal) write(out_, tool_, "", message);
}

void Logger::detail(const std::string& message) const {
  if (verbosity_ >= Verbosity::kVerbose) write(out_, tool_, "", message);
}

void Logger::warning(const std::string& message) const {
  write(out_, tool_, "warning: ", message);
}

void Logger::error(const std::string& message) const {
  write(out_, tool_, "error: ", message);
}

}  // namespace nvh
