#include "common/error.hpp"

#include <sstream>
#include <utility>

namespace nvh {
namespace {

std::string format(const std::string& message, const SourceLocation& where, const std::string& key) {
  std::ostringstream out;
  if (!where.file.empty()) {
    out << where.file;
    if (where.line > 0) out << ':' << where.line;
    if (where.column > 0) out << ':' << where.column;
    out << ": ";
  }
  if (!key.empty()) out << '\'' << key << "': ";
  out << message;
  return out.str();
}

}  // namespace

Error::Error(const std::string& message) : std::runtime_error(message), message_(message) {}

Error::Error(const std::string& message, SourceLocation where, std::string key)
    : std::runtime_error(format(message, where, key)),
      message_(message),
      where_(std::move(where)),
      key_(std::move(key)) {}

}  // namespace nvh
