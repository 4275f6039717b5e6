#include "common/output_path.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include "common/error.hpp"
#include "common/interrupt.hpp"

namespace nvh {
namespace {

// Same file: by device and inode when both exist (links, "./a" against "a"); else by the normalized
// absolute path (an output that does not exist yet cannot be an existing input, but two outputs can match).
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::error_code error;
  if (std::filesystem::exists(a, error) && std::filesystem::exists(b, error)) {
    const bool same = std::filesystem::equivalent(a, b, error);
    if (!error) return same;
  }
  const auto canonical_a = std::filesystem::weakly_canonical(a, error);
  if (error) return false;
  const auto canonical_b = std::filesystem::weakly_canonical(b, error);
  return !error && canonical_a == canonical_b;
}

std::filesystem::path temporary_for(const std::filesystem::path& path) {
  std::filesystem::path temporary = path;
  temporary += ".tmp-" + std::to_string(::getpid());
  return temporary;
}

}  // namespace

void check_outputs_are_not_inputs(const std::vector<std::filesystem::path>& outputs,
                                  const std::vector<std::filesystem::path>& inputs) {
  for (std::size_t o = 0; o < outputs.size(); ++o) {
    for (const std::filesystem::path& input : inputs) {
      if (!input.empty() && same_file(outputs[o], input)) {
        throw Error("output '" + outputs[o].string() + "' is the input '" + input.string() +
                    "': writing it would destroy the input; choose another output path");
      }
    }
    for (std::size_t p = 0; p < o; ++p) {
      if (same_file(outputs[o], outputs[p])) {
        throw Error("outputs '" + outputs[p].string() + "' and '" + outputs[o].string() +
                    "' are the same file; choose different paths");
      }
    }
  }
}

void check_output_writable(const std::filesystem::path& output) {
  std::error_code error;
  if (std::filesystem::is_directory(output, error)) {
    throw Error(output.string() + ": cannot write the output: it is a directory; expected a file path");
  }
  const std::filesystem::path parent = output.parent_path().empty() ? "." : output.parent_path();
  if (!std::filesystem::is_directory(parent, error)) {
    throw Error(output.string() + ": cannot write the output: directory '" + parent.string() +
                "' does not exist");
  }
  // The temporary the writer will use, created and removed: the one sure test (permissions, read-only
  // mounts, ACLs), made before the work rather than after it.
  const std::filesystem::path probe = temporary_for(output);
  {
    std::ofstream out(probe);
    if (!out) {
      throw Error(output.string() + ": cannot write the output: cannot create files in '" + parent.string() +
                  "' (permissions or a read-only file system?)");
    }
  }
  std::filesystem::remove(probe, error);
}

void check_output_directory(const std::filesystem::path& directory) {
  std::error_code error;
  std::filesystem::create_directories(directory, error);
  if (error || !std::filesystem::is_directory(directory)) {
    throw Error(directory.string() + ": cannot create the output directory" +
                (error ? " (" + error.message() + ")" : std::string(": a file of that name exists")));
  }
  check_output_writable(directory / ".nvh-write-test");
}

TextOutput::TextOutput(std::filesystem::path path)
    : path_(std::move(path)), temporary_(temporary_for(path_)) {
  register_temporary(temporary_);  // removed if a signal stops the run
  out_ = std::make_unique<std::ofstream>(temporary_);
  if (!*out_) {
    unregister_temporary(temporary_);
    throw Error(path_.string() + ": cannot create the file (does its directory exist, is it writable?)");
  }
}

TextOutput::TextOutput(TextOutput&& other) noexcept
    : path_(std::move(other.path_)), temporary_(std::move(other.temporary_)), out_(std::move(other.out_)) {
  other.temporary_.clear();
}

TextOutput::~TextOutput() {
  if (temporary_.empty()) return;
  out_.reset();
  std::error_code ignored;
  std::filesystem::remove(temporary_, ignored);
  unregister_temporary(temporary_);
}

void TextOutput::close() {
  if (!out_ || !out_->is_open()) return;
  errno = 0;
  out_->close();  // flushes: a full disk fails here
  if (out_->fail()) {
    throw Error(path_.string() + ": cannot write the file" +
                (errno != 0 ? std::string(" (") + std::strerror(errno) + ")" : std::string()));
  }
}

void TextOutput::commit() {
  if (temporary_.empty()) throw Error(path_.string() + ": committed twice");
  close();
  std::error_code error;
  std::filesystem::rename(temporary_, path_, error);
  if (error)
    throw Error(path_.string() + ": cannot rename '" + temporary_.string() + "' onto it: " + error.message());
  unregister_temporary(temporary_);
  temporary_.clear();
}

}  // namespace nvh
