// Work-precision of solve's integrators: error against a reference run (IDA at rtol 1e-11) versus CPU time,
// for IDA over tolerances, generalized-alpha over steps and the body-wise split (Gauss-Seidel exchange with
// the coupling correction, its groups' IDA at rtol 1e-6) over macro steps, on one scene. Prints a table and
// writes CSV.
//
//   bench_solve_work_precision SCENE SIGNAL COLUMN OUT.csv [REFERENCE_RTOL [FINEST_RTOL [events-off]]]
// With `events-off` both sweeps run again without contact events ([integrator] events = false), as methods
// "ida no-events" and "generalized-alpha no-events"; the reference keeps them (the scene's setting).
//   e.g. bench_solve_work_precision testdata/scenes/piston_slap.toml markers/piston.pin/position 0 wp.csv
// The error is max |s - s_ref| over the samples divided by max |s_ref - mean(s_ref)|.
#include <ctime>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "common/hdf5.hpp"
#include "common/log.hpp"
#include "solve/run.hpp"
#include "solve/scene.hpp"

using namespace nvh;
using namespace nvh::solve;

namespace {

struct Outcome {
  double cpu_s = 0;
  long steps = 0, rejected = 0, newton_failures = 0, events = 0;
  Eigen::VectorXd signal;
  bool ok = true;
};

Outcome run(const std::filesystem::path& scene_file, const IntegratorSettings& settings, const std::string& signal,
            int column) {
  Scene scene = read_scene(scene_file);
  scene.integrator = settings;
  std::ostringstream sink;
  const Logger log(sink, "bench", Verbosity::kQuiet);
  RunOptions options;
  options.output = std::filesystem::temp_directory_path() / ("wp_" + std::to_string(::getpid()) + ".h5");
  options.progress = Progress::Style::kNone;
  Outcome o;
  const std::clock_t start = std::clock();
  try {
    const RunSummary s = run_scene(scene, options, make_provenance("bench", 0, nullptr, {}), log);
    o.steps = s.statistics.steps;
    o.rejected = s.statistics.rejected_steps;
    o.newton_failures = s.statistics.nonlinear_failures;
    o.events = s.statistics.events;
  } catch (const std::exception& e) {
    o.ok = false;
    std::cerr << "  run failed: " << e.what() << "\n";
  }
  o.cpu_s = double(std::clock() - start) / CLOCKS_PER_SEC;
  if (o.ok) {
    const h5::File f = h5::File::open_read(options.output);
    o.signal = f.root().read_matrix(signal).col(column);
  }
  std::filesystem::remove(options.output);
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5 || argc > 8) {
    std::cerr << "usage: bench_solve_work_precision SCENE SIGNAL COLUMN OUT.csv [REFERENCE_RTOL [FINEST_RTOL "
                 "[events-off]]]\n";
    return 2;
  }
  const double reference_rtol = argc > 5 ? std::stod(argv[5]) : 1e-11;
  const double finest = argc > 6 ? std::stod(argv[6]) : 1e-10;
  const bool compare_events = argc > 7 && std::string(argv[7]) == "events-off";
  const std::filesystem::path scene = argv[1];
  const std::string signal = argv[2];
  const int column = std::stoi(argv[3]);
  const Scene base = read_scene(scene);
  IntegratorSettings ref = base.integrator;
  ref.method = "ida";
  ref.max_order = 5;
  ref.rtol = reference_rtol;
  ref.atol = reference_rtol * 1e-2;
  ref.max_step = base.integrator.max_step;
  const Outcome reference = run(scene, ref, signal, column);
  if (!reference.ok) {
    std::cerr << "the reference run failed\n";
    return 1;
  }
  const double scale = (reference.signal.array() - reference.signal.mean()).abs().maxCoeff();
  std::ofstream csv(argv[4]);
  csv << "method,setting,cpu_s,steps,rejected_steps,newton_failures,events,error\n";
  std::cout << "scene " << scene << ", signal " << signal << "[" << column << "], reference IDA rtol " << reference_rtol << ": "
            << reference.cpu_s << " s CPU, " << reference.steps << " steps, " << reference.rejected << " rejected, "
            << reference.events << " events\n";
  std::cout << std::setw(32) << "method" << std::setw(10) << "setting" << std::setw(10) << "CPU s" << std::setw(9)
            << "steps" << std::setw(9) << "rejected" << std::setw(9) << "Newton" << std::setw(8) << "events"
            << std::setw(14) << "error\n";
  auto report = [&](const std::string& method, double setting, const Outcome& o) {
    const double err = o.ok && o.signal.size() == reference.signal.size()
                           ? (o.signal - reference.signal).cwiseAbs().maxCoeff() / scale
                           : std::numeric_limits<double>::quiet_NaN();
    std::cout << std::setw(32) << method << std::setw(10) << setting << std::setw(10) << o.cpu_s << std::setw(9)
              << o.steps << std::setw(9) << o.rejected << std::setw(9) << o.newton_failures << std::setw(8) << o.events
              << std::setw(14) << err << (o.ok ? "" : "  (failed)") << "\n";
    csv << method << "," << setting << "," << o.cpu_s << "," << o.steps << "," << o.rejected << ","
        << o.newton_failures << "," << o.events << "," << err << "\n";
  };
  for (const bool events : {true, false}) {
    if (!events && !compare_events) break;
    const std::string suffix = events ? "" : " no-events";
    for (double tol : {1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10}) {
      if (tol < finest * 0.999) break;
      IntegratorSettings s = base.integrator;
      s.method = "ida";
      s.events = events;
      s.rtol = tol;
      s.atol = tol * 1e-2;
      report("ida" + suffix, tol, run(scene, s, signal, column));
    }
    for (double step : {1e-4, 5e-5, 2e-5, 1e-5, 5e-6}) {
      IntegratorSettings s = base.integrator;
      s.method = "generalized-alpha";
      s.step = step;
      s.rtol = 1e-8;
      s.atol = 1e-10;
      s.adaptive = true;
      s.events = events;
      report("generalized-alpha" + suffix, step, run(scene, s, signal, column));
    }
    for (double macro : {1e-3, 5e-4, 2e-4, 1e-4, 5e-5}) {
      IntegratorSettings s = base.integrator;
      s.method = "split";
      s.macro_step = macro;
      s.exchange = "gauss-seidel";
      s.coupling_correction = true;
      s.rtol = 1e-6;
      s.atol = 1e-8;
      s.events = events;
      report("split" + suffix, macro, run(scene, s, signal, column));
    }
  }
  return 0;
}
