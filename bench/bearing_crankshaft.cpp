// A rigid 4-cylinder crankshaft on 5 main bearings under rotating and gas loads, run by solve three times:
// with finite Reynolds bearings (JFO, 60 x 20 cells), with short (Ocvirk) bearings, and with linear
// spring-dampers (isotropic: the mean direct stiffness and damping of the short bearing at eps = 0.6 under
// the scene's mean main-bearing load direction). It prints the CPU time per revolution of each, and how far
// the journal orbits of the cheaper models are from the finite bearing's over the second 720 deg cycle.
//
// Scene: testdata/scenes/bearing_crankshaft.toml (the finite variant; the others are rewritten from it).
//   build-bearing/bench/bench_bearing_crankshaft [scene.toml] [cycles, default 2]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "common/hdf5.hpp"
#include "common/log.hpp"
#include "solve/bearing/short_bearing.hpp"
#include "solve/run.hpp"
#include "solve/scene.hpp"

using namespace nvh;

namespace {

constexpr double kClearance = 30e-6;  // m, as in the scene
constexpr int kBearings = 5;

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void replace_all(std::string& s, const std::string& from, const std::string& to) {
  for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
}

/// Each journal-bearing block (from its type line to the blank line after it) replaced by `keys`.
std::string with_bearings_replaced(std::string s, const std::string& keys) {
  const std::string start = "type = \"journal-bearing\"";
  for (std::size_t at = s.find(start); at != std::string::npos; at = s.find(start, at)) {
    const std::size_t end = s.find("\n\n", at);
    s.replace(at, end - at, keys);
  }
  return s;
}

/// The short bearing's mean direct coefficients at eps = 0.6 (load along -y; the scene's bearing).
std::pair<double, double> spring_damper_coefficients() {
  bearing::BearingSpec s;
  s.model = bearing::Model::kShort;
  s.diameter = 0.055;
  s.width = 0.024;
  s.radial_clearance = kClearance;
  s.viscosity = 0.008;
  const double eps = 0.6, phi = std::atan(std::numbers::pi * std::sqrt(1 - eps * eps) / (4 * eps));
  bearing::Kinematics k;
  k.e = eps * kClearance * Eigen::Vector2d(std::sin(phi), -std::cos(phi));  // load along -y
  k.omega_journal = 3000 * 2 * std::numbers::pi / 60;
  const bearing::FilmResult r = bearing::evaluate_short(s, k);
  return {-0.5 * (r.jacobian(0, 0) + r.jacobian(1, 1)), -0.5 * (r.jacobian(0, 2) + r.jacobian(1, 3))};
}

struct Run {
  std::string name;
  double cpu_s = 0, wall_s = 0, revolutions = 0;
  solve::IntegratorStatistics stats;
  std::vector<Eigen::MatrixXd> orbit;  // per bearing: samples x 2 (ex, ey), m
  Eigen::VectorXd time;
};

Run run(const std::string& name, const std::string& text, const std::filesystem::path& base) {
  Run r;
  r.name = name;
  solve::Scene scene = solve::parse_scene(text, name + ".toml", base);
  std::ostringstream sink;
  const Logger log(sink, "bench", Verbosity::kQuiet);
  solve::RunOptions options;
  options.output = std::filesystem::temp_directory_path() / ("bench_bearing_crankshaft_" + name + ".h5");
  options.progress = Progress::Style::kNone;
  const Provenance p = make_provenance("bench_bearing_crankshaft", 0, nullptr, {});
  const std::clock_t c0 = std::clock();
  const auto t0 = std::chrono::steady_clock::now();
  const solve::RunSummary s = solve::run_scene(scene, options, p, log);
  r.cpu_s = double(std::clock() - c0) / CLOCKS_PER_SEC;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.stats = s.statistics;
  r.revolutions = scene.end_angle_deg / 360.0;
  const h5::File f = h5::File::open_read(options.output);
  r.time = f.root().read_vector("time");
  for (int b = 1; b <= kBearings; ++b)
    r.orbit.push_back(
        f.root().read_matrix("markers/crank.main" + std::to_string(b) + "/position").leftCols(2));
  std::filesystem::remove(options.output);
  return r;
}

/// Largest and RMS distance (in units of c) between two runs' journal centres over the samples from `first`.
std::pair<double, double> orbit_difference(const Run& a, const Run& b, Eigen::Index first) {
  double worst = 0, sum = 0;
  long n = 0;
  const Eigen::Index last = std::min(a.time.size(), b.time.size());
  for (int k = 0; k < kBearings; ++k)
    for (Eigen::Index i = first; i < last; ++i) {
      const double d = (a.orbit[k].row(i) - b.orbit[k].row(i)).norm() / kClearance;
      worst = std::max(worst, d);
      sum += d * d;
      ++n;
    }
  return {worst, std::sqrt(sum / std::max(n, 1L))};
}

double peak_eccentricity(const Run& r, Eigen::Index first) {
  double peak = 0;
  for (const auto& o : r.orbit)
    for (Eigen::Index i = first; i < o.rows(); ++i) peak = std::max(peak, o.row(i).norm() / kClearance);
  return peak;
}

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path scene_path =
      argc > 1 ? argv[1] : std::filesystem::path(NVH_SOURCE_DIR) / "testdata/scenes/bearing_crankshaft.toml";
  std::string finite = read_text(scene_path);
  if (argc > 2) replace_all(finite, "end_cycles = 2", "end_cycles = " + std::string(argv[2]));
  std::string short_text = finite;
  replace_all(short_text, "model = \"finite\"", "model = \"short\"");
  const auto [k, d] = spring_damper_coefficients();
  std::ostringstream keys;
  keys << "type = \"bushing\"\nstiffness = [" << k << ", " << k << ", 0, 0, 0, 0]\ndamping = [" << d << ", "
       << d << ", 0, 0, 0, 0]";
  const std::string spring_text = with_bearings_replaced(finite, keys.str());
  std::printf("spring-damper: k = %.4g N/m, d = %.4g N s/m (short bearing at eps 0.6)\n\n", k, d);
  std::fflush(stdout);

  const auto base = scene_path.parent_path();
  std::vector<Run> runs;
  for (const auto& [name, text] :
       {std::pair{"spring-damper", spring_text}, {"short", short_text}, {"finite", finite}}) {
    runs.push_back(run(name, text, base));
    std::printf("%-14s done: %.2f s CPU, %ld steps\n", name, runs.back().cpu_s, runs.back().stats.steps);
    std::fflush(stdout);
  }
  std::printf("\n");
  const Run& ref = runs.back();
  // The second half of the run (from 720 deg on with the default 2 cycles): past the start transient.
  const Eigen::Index first = ref.time.size() / 2;

  std::printf("%-14s %10s %10s %12s %8s %10s %10s %10s %12s %12s\n", "bearings", "CPU s/rev", "wall s/rev",
              "CPU/spring", "steps", "residuals", "jacobians", "peak eps", "max |de|/c", "rms |de|/c");
  const double spring_cpu = runs.front().cpu_s;
  for (const Run& r : runs) {
    const auto [worst, rms] = orbit_difference(r, ref, first);
    std::printf("%-14s %10.3f %10.3f %12.1f %8ld %10ld %10ld %10.3f %12.4f %12.4f\n", r.name.c_str(),
                r.cpu_s / r.revolutions, r.wall_s / r.revolutions, r.cpu_s / spring_cpu, r.stats.steps,
                r.stats.residual_evaluations, r.stats.jacobian_evaluations, peak_eccentricity(r, first),
                worst, rms);
  }
  std::printf(
      "\n|de|/c: distance of each journal centre from the finite-bearing run's, over the second half of "
      "the run, all 5 bearings.\n");
  return 0;
}
