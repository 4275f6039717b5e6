#pragma once
// Run a scene given as text through solve's library and read its results back.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>

#include "common/error.hpp"
#include "common/hdf5.hpp"
#include "common/log.hpp"
#include "solve/run.hpp"
#include "solve/scene.hpp"

namespace nvh::solve::testing {

inline std::filesystem::path temp_path(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("nvh_solve_tests_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir / name;
}

/// Parse, run, and return the results file path.
inline std::filesystem::path run_text(const std::string& text, const std::string& name,
                                      RunSummary* summary = nullptr) {
  Scene scene = parse_scene(text, name + ".toml", std::filesystem::path(NVH_SOURCE_DIR) / "testdata/scenes");
  std::ostringstream sink;
  const Logger log(sink, "solve", Verbosity::kQuiet);
  RunOptions options;
  options.output = temp_path(name + ".h5");
  options.progress = Progress::Style::kNone;
  const Provenance p = make_provenance("solve-test", 0, nullptr, {});
  const RunSummary s = run_scene(scene, options, p, log);
  if (summary) *summary = s;
  return options.output;
}

/// Column `c` of an (n, 3) dataset, or a 1-D dataset (c ignored).
inline Eigen::VectorXd signal(const std::filesystem::path& file, const std::string& path, int c = -1) {
  const h5::File f = h5::File::open_read(file);
  if (c < 0) return f.root().read_vector(path);
  return f.root().read_matrix(path).col(c);
}

/// The message of the error that parsing a bad scene throws (the scene's file name: bad.toml), or "no error".
inline std::string scene_error(const std::string& text) {
  try {
    parse_scene(text, "bad.toml", ".");
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

/// An (n, 3) or (n, m) dataset.
inline Eigen::MatrixXd matrix(const std::filesystem::path& file, const std::string& path) {
  return h5::File::open_read(file).root().read_matrix(path);
}

/// A number written with all its digits into a scene.
inline std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

}  // namespace nvh::solve::testing
