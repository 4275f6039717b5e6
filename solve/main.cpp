// solve: integrate a multibody scene in time (step 2 of 3: condense -> solve -> postproc).
// A thin CLI over the solve library (solve/run.hpp); `solve bearing-map` is the bearing characteristics tool.
#include <CLI/CLI.hpp>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "common/log.hpp"
#include "common/output_path.hpp"
#include "common/provenance.hpp"
#include "common/version.hpp"
#include "solve/advise.hpp"
#include "solve/element_registry.hpp"
#include "solve/run.hpp"
#include "solve/scene.hpp"
#if __has_include("solve/bearing/bearing_map_cli.hpp")
#include "solve/bearing/bearing_map_cli.hpp"
#define NVH_HAVE_BEARING_MAP 1
#endif

namespace {

constexpr const char* kDescription =
    R"(solve - integrate a multibody scene in time (step 2 of 3: condense -> solve -> postproc)

Reads a scene file (TOML, docs/scene-format.md): bodies (ground, rigid, point masses, flexible, and
sliders and rotors: rigid bodies of one coordinate on a fixed axis, their guide's or bearing's
reaction written as the body's support_force) with markers, ideal joints (fixed, revolute,
spherical, prismatic, cylindrical, in-line, distance, in-plane, and cam: a roller held on a cam's
pitch curve; redundant equations of closed planar loops are found and removed), force elements
(listed below: spring-dampers, Maxwell mounts, bushings, torsional couplings, contacts with
clearance and friction, tables, motor curves, hydrodynamic journal bearings, roller followers on
cams), speed drivers, lift drivers (a kinematic cam on a slider:
docs/valvetrain.md), loads against time or crank angle (cylinder
pressure x piston area, periodic over 720 deg), a clock (crank angle; end by time, angle or cycles).
It integrates the differential-algebraic equations with SUNDIALS IDA (variable-order BDF, KLU sparse
solver) or generalized-alpha, and writes RESULTS.h5 at a fixed sample rate: time, crank angle,
marker positions / velocities / accelerations (global axes), body states, element forces, joint
reactions, solver statistics (docs/results-format.md). The file grows in chunks while the run goes
on: a run killed at any moment leaves a readable file (status = "running"), and one stopped by
SIGTERM/SIGINT (Slurm's time limit, Ctrl-C) writes a checkpoint: continue it with --restart.

Examples:
  solve testdata/scenes/slider_crank.toml -o slider_crank.h5
  solve scene.toml -o out.h5 --restart          # continue an interrupted run
  solve bearing-map bearing.toml -o map.h5      # journal bearing characteristics (docs/bearing.md)
  solve --advise scene.toml --band 2000         # method, step and mode counts for a 2 kHz band; no run

Advice (--advise, docs/cli.md): the model is linearised at its start and its modes (frequency,
damping, the bodies and elements that carry them) are set against the band the results must cover
(--band, else half the output sample rate) and against the integrators' stability theory that
bench/stability_map.py measured: BDF orders 3-5 grow modes damped below 0.0698 / 0.287 / 0.618 for a
band of omega h; generalized-alpha is stable at any step. It prints the method, max_step or step
(20 per period of the band's top), rtol, max_order, each flexible body's modes (up to 2 x the band)
and warnings where the scene's own settings lie outside; it writes nothing.

Exit codes: 0 success; 1 bad input or a failed run (the message names the file, line and key, or
the time and the body / joint / element that failed; samples so far are kept); 2 bad command line;
3 interrupted (output flushed, checkpoint written).)";

/// The element types the scene accepts, from solve's element registry (so a new element appears here by
/// registering itself): section, type, marker keys and the registry's one-line summary, wrapped.
std::string element_types_help() {
  std::ostringstream out;
  out << "Element types (the element registry; details in docs/scene-format.md section 4):\n";
  for (const nvh::solve::ElementType* et : nvh::solve::builtin_elements().all()) {
    std::string markers;
    for (const auto& k : et->marker_keys) markers += (markers.empty() ? "" : ", ") + k;
    out << "  [[" << et->section << "]] type = \"" << et->name << "\"  (markers: " << markers << ")\n";
    std::istringstream words(et->summary);
    std::string line = "     ", word;
    while (words >> word) {
      if (line.size() + word.size() + 1 > 104) out << line << "\n", line = "     ";
      line += " " + word;
    }
    out << line << "\n";
  }
  return out.str();
}

}  // namespace

int main(int argc, char** argv) {
  using namespace nvh;
  using namespace nvh::solve;
  install_interrupt_handler("solve");
#ifdef NVH_HAVE_BEARING_MAP
  if (argc > 1 && std::strcmp(argv[1], "bearing-map") == 0)
    return nvh::bearing::bearing_map_main(argc - 1, argv + 1);
#endif
  CLI::App app{kDescription, "solve"};
  app.get_formatter()->column_width(34);
  app.footer(element_types_help());
  std::string scene_file, output_file;
  bool restart = false, quiet = false, verbose = false;
  std::string progress_style = "auto";
  app.add_option("SCENE", scene_file, "scene file (.toml); see docs/scene-format.md")->required();
  CLI::Option* output_option = app.add_option("-o,--output", output_file, "results file to write (.h5)");
  bool advise_only = false;
  nvh::solve::AdviceOptions advice_options;
  CLI::Option* advise_flag = app.add_flag(
      "--advise", advise_only,
      "print advice instead of running: the model's modes, and the method, step, tolerance and flexible "
      "modes for the band; writes nothing");
  app.add_option("--band", advice_options.band_hz,
                 "with --advise: the band's top frequency in Hz (default: half the output sample rate)")
      ->check(CLI::PositiveNumber)
      ->needs(advise_flag);
  output_option->excludes(advise_flag);
  app.add_flag("--restart", restart, "continue an interrupted run from the checkpoint in the results file");
  app.add_option("--progress", progress_style,
                 "progress display: auto (bar on a terminal, lines in logs), bar, lines, none")
      ->check(CLI::IsMember({"auto", "bar", "lines", "none"}));
  CLI::Option* quiet_flag = app.add_flag("-q,--quiet", quiet, "print errors only");
  app.add_flag("-v,--verbose", verbose, "print more detail")->excludes(quiet_flag);
  app.set_version_flag("--version", std::string("solve ") + kVersion);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : static_cast<int>(ExitCode::kUsage);
  }
  if (!advise_only && output_file.empty()) {
    std::cerr << "--output is required (or --advise)\nRun with --help for more information.\n";
    return static_cast<int>(ExitCode::kUsage);
  }
  const Logger log(std::cerr, "solve",
                   quiet     ? Verbosity::kQuiet
                   : verbose ? Verbosity::kVerbose
                             : Verbosity::kNormal);
  try {
    if (advise_only) {  // read and build the scene, linearise it, print the advice; no results file
      Scene scene = read_scene(scene_file);
      std::cout << format_advice(advise(scene, advice_options, log), scene);
      return 0;
    }
    // Before any work: the results may not replace the scene or a file it reads, and must be writable.
    check_outputs_are_not_inputs({output_file}, {scene_file});
    check_output_writable(output_file);
    Scene scene = read_scene(scene_file);
    for (const std::string& w : scene.warnings) log.warning(w);
    check_outputs_are_not_inputs({output_file}, scene.input_files);
    const Provenance provenance = make_provenance("solve", argc, argv, scene.input_files);
    RunOptions options;
    options.output = output_file;
    options.restart = restart;
    options.progress = progress_style == "bar"     ? Progress::Style::kBar
                       : progress_style == "lines" ? Progress::Style::kLines
                       : progress_style == "none"  ? Progress::Style::kNone
                                                   : Progress::Style::kAuto;
    {
      std::ostringstream what;
      what << "scene \"" << scene.name << "\": " << scene.model.bodies.size() << " bodies, "
           << scene.model.constraints.size() << " joints/drivers (" << scene.model.constraint_equations()
           << " equations), " << scene.model.forces.size() << " force elements; " << scene.model.size()
           << " unknowns; " << scene.integrator.method;
      log.info(what.str());
    }
    const RunSummary s = run_scene(scene, options, provenance, log);
    std::ostringstream out;
    out << (s.status == "complete" ? "wrote " : "interrupted; kept ") << output_file << ": " << s.samples
        << " samples to t = " << s.end_time << " s; " << s.statistics.steps << " steps ("
        << s.statistics.rejected_steps << " rejected), " << s.statistics.newton_iterations
        << " Newton iterations, " << s.statistics.jacobian_evaluations << " Jacobians, " << s.wall_seconds
        << " s";
    if (!scene.model.constraints.empty())
      out << "; constraint drift at most " << s.max_position_drift << " (position), " << s.max_velocity_drift
          << " (velocity)";
    log.info(out.str());
    // Which unknowns set the step: what a user changes first when a run is slow (tolerances, velocity_atol,
    // fewer modes; docs/scene-format.md section 7).
    if (const std::string held = error_test_holders(scene.model, s.statistics.error_test_steps);
        !held.empty())
      log.info("steps set by (IDA's error test, share of the steps): " + held);
    return s.status == "complete" ? 0 : static_cast<int>(ExitCode::kInterrupted);
  } catch (const Interrupted& e) {  // before the results file existed: nothing written
    log.error(std::string(e.what()) + "; nothing written");
    return static_cast<int>(ExitCode::kInterrupted);
  } catch (const Error& e) {
    // Every message names the scene file: a model that cannot be assembled or a run that fails (a time and an
    // element) come from the scene's numbers, and a batch log of many scenes must point at the one to change.
    const std::string name = std::filesystem::path(scene_file).filename().string();
    const std::string message = e.what();
    log.error(message.find(name) == std::string::npos ? scene_file + ": " + message : message);
    return static_cast<int>(ExitCode::kFailure);
  } catch (const std::exception& e) {
    log.error(std::string("unexpected failure: ") + e.what());
    return static_cast<int>(ExitCode::kFailure);
  }
}
