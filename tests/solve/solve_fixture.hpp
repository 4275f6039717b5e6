#pragma once
// Run a scene given as text through solve's library and read its results back.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

#include "common/error.hpp"
#include "common/hdf5.hpp"
#include "common/log.hpp"
#include "solve/run.hpp"
#include "solve/scene.hpp"

namespace nvh::solve::testing {

/// This test process's scratch folder under the system's temporary folder, removed with everything in it when
/// the process exits (ctest runs each test in a process of its own; a forked child leaves it to its parent).
class ProcessTempDir {
 public:
  ProcessTempDir()
      : owner_(::getpid()),
        path_(std::filesystem::temp_directory_path() / ("nvh_solve_tests_" + std::to_string(owner_))) {
    std::filesystem::create_directories(path_);
  }
  ~ProcessTempDir() {
    std::error_code ignored;
    if (::getpid() == owner_) std::filesystem::remove_all(path_, ignored);
  }
  ProcessTempDir(const ProcessTempDir&) = delete;
  ProcessTempDir& operator=(const ProcessTempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  pid_t owner_;
  std::filesystem::path path_;
};

inline std::filesystem::path temp_path(const std::string& name) {
  static const ProcessTempDir dir;
  std::filesystem::create_directories(dir.path());  // a test may have removed it
  return dir.path() / name;
}

/// Parse the scene `text` as if it were the file `name`.toml in folder `base` (where the files it names -
/// tables, superelements - are looked for), run it quietly into `output`, and return that path.
inline std::filesystem::path run_text_at(const std::string& text, const std::string& name,
                                         const std::filesystem::path& base,
                                         const std::filesystem::path& output, RunSummary* summary = nullptr) {
  Scene scene = parse_scene(text, name + ".toml", base);
  std::ostringstream sink;
  const Logger log(sink, "solve", Verbosity::kQuiet);
  RunOptions options;
  options.output = output;
  options.progress = Progress::Style::kNone;
  const Provenance p = make_provenance("solve-test", 0, nullptr, {});
  const RunSummary s = run_scene(scene, options, p, log);
  if (summary) *summary = s;
  return options.output;
}

/// Parse, run, and return the results file path. Files the scene names (tables, superelements) are looked for
/// in `folder` under testdata/ (a shipped scene's own folder).
inline std::filesystem::path run_text(const std::string& text, const std::string& name,
                                      RunSummary* summary = nullptr, const std::string& folder = "scenes") {
  return run_text_at(text, name, std::filesystem::path(NVH_SOURCE_DIR) / "testdata" / folder,
                     temp_path(name + ".h5"), summary);
}

/// A scene shipped in testdata (path relative to testdata/) with edits: each `from` is replaced by `to` at
/// its first occurrence; an edit that finds nothing fails the test (the shipped file changed under it).
inline std::string shipped_scene(const std::string& path,
                                 std::initializer_list<std::pair<std::string, std::string>> edits = {}) {
  std::ifstream in(std::filesystem::path(NVH_SOURCE_DIR) / "testdata" / path);
  EXPECT_TRUE(in.good()) << "cannot read testdata/" << path;
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const auto& [from, to] : edits) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << "testdata/" << path << " has no '" << from << "'";
    if (at != std::string::npos) text.replace(at, from.size(), to);
  }
  return text;
}

/// Column `c` of an (n, 3) dataset, or a 1-D dataset (c ignored).
inline Eigen::VectorXd signal(const std::filesystem::path& file, const std::string& path, int c = -1) {
  const h5::File f = h5::File::open_read(file);
  if (c < 0) return f.root().read_vector(path);
  return f.root().read_matrix(path).col(c);
}

/// signal() as a std::vector (for loops over samples).
inline std::vector<double> column(const std::filesystem::path& file, const std::string& path, int c = -1) {
  const Eigen::VectorXd v = signal(file, path, c);
  return std::vector<double>(v.data(), v.data() + v.size());
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

// ------------------------------------------------------------------ a ball bouncing on a floor
// A 0.5 kg point mass 1 mm above a floor at -1.5 m/s, Hunt-Crossley contact (k = 1e8 N/m^1.5, e = 0.7 at
// 1 m/s): append [integrator] keys (test_dynamics.cpp, test_contact_events.cpp).
inline const std::string kBallOnFloor = R"(
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "floor"
[[body]]
name = "ball"
type = "point-mass"
mass = 0.5
position = [0, 0, 0.001]
velocity = [0, 0, -1.5]
  [[body.marker]]
  name = "c"
[[force]]
name = "impact"
type = "contact"
i = "ball.c"
j = "ground.floor"
stiffness = 1e8
exponent = 1.5
restitution = 0.7
reference_speed = 1.0
[clock]
end_time = 0.004
[output]
sample_rate_hz = 100000
)";

// f = k d^n (1 + alpha d'): m v dv/(1 + alpha v) = -k d^n dd over an impact gives
// G(v_out) = G(v_in), G(v) = v / alpha - ln(1 + alpha v) / alpha^2 (Hunt & Crossley 1975; Gilardi & Sharf,
// Mech. Mach. Theory 37, 2002, eq. 17), solved by bisection for the rebound speed.
inline double hunt_crossley_rebound(double alpha, double v_in) {
  auto g = [&](double v) { return v / alpha - std::log1p(alpha * v) / (alpha * alpha); };
  double lo = -1 / alpha + 1e-12, hi = -1e-12;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (g(mid) > g(v_in) ? lo : hi) = mid;
  }
  return -0.5 * (lo + hi);
}

}  // namespace nvh::solve::testing
