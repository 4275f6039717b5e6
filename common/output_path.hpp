#pragma once
// Checks a tool makes on its output paths before any work, and text outputs (CSV) written like the HDF5
// ones: to a temporary beside the final path, renamed by commit(), removed if the run fails first.
// With them an output never replaces an input, an unwritable output is known before the computation,
// and a failed run leaves none of its outputs (the tools commit every output only once all are written).
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace nvh {

/// Error naming both paths if `output` is one of `inputs` (the same file by any path: "./a.h5", "a.h5", a
/// symbolic or hard link) or if two outputs are the same file. `outputs` are the files the tool will write.
void check_outputs_are_not_inputs(const std::vector<std::filesystem::path>& outputs,
                                  const std::vector<std::filesystem::path>& inputs);

/// Error naming the path unless a file can be created at `output`: its directory exists and is writable
/// (checked by creating and removing a file beside it) and the path is not a directory.
void check_output_writable(const std::filesystem::path& output);

/// Create `directory` if missing and check that files can be created in it (error naming it otherwise).
void check_output_directory(const std::filesystem::path& directory);

/// A text file written to "<path>.tmp-<pid>" and renamed onto `path` by commit(); removed unless committed.
class TextOutput {
 public:
  explicit TextOutput(std::filesystem::path path);
  TextOutput(TextOutput&& other) noexcept;
  TextOutput& operator=(TextOutput&&) = delete;
  TextOutput(const TextOutput&) = delete;
  TextOutput& operator=(const TextOutput&) = delete;
  ~TextOutput();

  std::ostream& stream() { return *out_; }
  /// Close the temporary, checking that everything was written (a full disk shows up here), but keep it
  /// under its temporary name: commit() renames it. Call before committing the other outputs of the run.
  void close();
  /// close() if not done, then rename onto the final path.
  void commit();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_, temporary_;
  std::unique_ptr<std::ofstream> out_;
};

}  // namespace nvh
