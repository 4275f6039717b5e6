#include "common/provenance.hpp"

#include <unistd.h>

#include <chrono>
#include <climits>
#include <ctime>
#include <string_view>
#include <utility>

#include "common/error.hpp"
#include "common/sha256.hpp"
#include "common/version.hpp"

namespace nvh {
namespace {

// "2026-11-21T06:10:00Z": now, in UTC, to the second.
std::string utc_timestamp() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

std::string host_name() {
  char name[HOST_NAME_MAX + 1] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}

// True if the shell would read `argument` as one word unchanged: only characters with no meaning to it.
bool shell_safe(std::string_view argument) {
  if (argument.empty()) return false;
  for (char c : argument) {
    const bool safe = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      std::string_view("_-+=/.,:@%").find(c) != std::string_view::npos;
    if (!safe) return false;
  }
  return true;
}

// POSIX single quotes; a single quote inside becomes '\'' (close, escaped quote, reopen).
std::string shell_quote(std::string_view argument) {
  if (shell_safe(argument)) return std::string(argument);
  std::string quoted = "'";
  for (char c : argument) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace

std::string join_command_line(int argc, const char* const* argv) {
  std::string line;
  for (int i = 0; i < argc && argv[i] != nullptr; ++i) {
    if (i > 0) line += ' ';
    line += shell_quote(argv[i]);
  }
  return line;
}

Provenance make_provenance(std::string tool, int argc, const char* const* argv,
                           const std::vector<std::filesystem::path>& inputs) {
  Provenance provenance;
  provenance.tool = std::move(tool);
  provenance.tool_version = kVersion;
  provenance.command_line = join_command_line(argc, argv);
  provenance.inputs = inputs;
  provenance.input_sha256.reserve(inputs.size());
  for (const std::filesystem::path& input : inputs) provenance.input_sha256.push_back(sha256_file(input));
  provenance.created_utc = utc_timestamp();
  provenance.host = host_name();
  return provenance;
}

void write_provenance(h5::Group& root, const Provenance& provenance) {
  if (provenance.inputs.size() != provenance.input_sha256.size()) {
    throw Error("provenance: " + std::to_string(provenance.inputs.size()) + " input files but " +
                std::to_string(provenance.input_sha256.size()) + " SHA-256 hashes");
  }
  std::vector<std::string> input_files;
  input_files.reserve(provenance.inputs.size());
  for (const std::filesystem::path& input : provenance.inputs) input_files.push_back(input.string());

  root.set_attribute("tool", provenance.tool);
  root.set_attribute("tool_version", provenance.tool_version);
  root.set_attribute("command_line", provenance.command_line);
  root.set_attribute("created_utc", provenance.created_utc);
  root.set_attribute("host", provenance.host);
  root.set_attribute("input_files", input_files);
  root.set_attribute("input_sha256", provenance.input_sha256);
}

}  // namespace nvh
