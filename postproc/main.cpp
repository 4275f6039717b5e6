// postproc: spectra, fractional-octave levels, order analysis and statistics of signals from solve's results,
// any HDF5 or CSV file, or measurements in UFF58. A thin CLI over the registered analyses
// (postproc/analysis.hpp): it knows none of them by name.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <vector>

#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "common/log.hpp"
#include "common/output_path.hpp"
#include "common/version.hpp"
#include "postproc/analysis.hpp"

namespace {

constexpr const char* kDescription =
    R"(postproc - spectra, 1/3-octave levels, orders, statistics, surface ERP (step 3 of 3: condense -> solve -> postproc)

Signals (docs/postproc.md section 2):
  FILE.h5:/dataset                  1-D dataset; sample rate from a 'sample_rate_hz' attribute on it or a
                                    group above it, else from a uniformly spaced 'time' dataset beside it
  FILE.h5:/markers/top1/acceleration[2]   column 2 (0-based; or [x] [y] [z]) of an (n, 3) dataset
  FILE.csv:column                   CSV with a header row and a time column (time, time_s or t)
  FILE.uff[:N]                      N-th dataset 58 (ASCII or binary) of a universal file, default 1
  NAME=ADDRESS                      name the signal NAME in the outputs
Each subcommand writes one HDF5 file (-o) with /spectrum, /octave, /orders or /stats groups per signal,
units and dB references as attributes and provenance; --csv DIR adds CSV tables, --plot DIR PNG figures.
erp reads a results file and a superelement instead of signals (postproc erp --help).

Exit codes: 0 success; 1 bad input or failed run (the message names the signal, file and what was
expected; no output is written); 2 bad command line; 3 interrupted.)";

}  // namespace

int main(int argc, char** argv) {
  using namespace nvh;
  using namespace nvh::postproc;
  install_interrupt_handler("postproc");
  CLI::App app{kDescription, "postproc"};
  app.require_subcommand(1);
  app.fallthrough();  // -q / -v also after the subcommand
  app.set_version_flag("--version", std::string("postproc ") + kVersion);
  bool quiet = false, verbose = false;
  CLI::Option* quiet_flag = app.add_flag("-q,--quiet", quiet, "print errors only");
  app.add_flag("-v,--verbose", verbose, "print more detail")->excludes(quiet_flag);
  // One subcommand per registered analysis (postproc/analysis.cpp); each declares its own options.
  CliShared shared;
  std::vector<std::unique_ptr<Analysis>> instances;
  std::vector<CLI::App*> subcommands;
  for (const AnalysisEntry& entry : analyses()) {
    instances.push_back(entry.make());
    subcommands.push_back(app.add_subcommand(entry.name, entry.summary));
    instances.back()->add_options(*subcommands.back(), shared);
  }

  try {
    app.parse(argc, argv);
    // CLI11 reads "nan" and "inf" as numbers, and NaN passes every range check: every number given on the
    // command line must be finite (--campbell-fmax nan sized a vector from NaN).
    for (const CLI::App* sub : app.get_subcommands()) {
      for (const CLI::Option* option : sub->get_options()) {
        if (option->get_type_name().rfind("FLOAT", 0) != 0) continue;
        for (const std::string& text : option->results()) {
          const double value = std::strtod(text.c_str(), nullptr);
          if (!std::isfinite(value))
            throw CLI::ValidationError(option->get_name(), "'" + text + "' is not a finite number");
        }
      }
    }
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : static_cast<int>(ExitCode::kUsage);
  }
  const Logger log(std::cerr, "postproc",
                   quiet     ? Verbosity::kQuiet
                   : verbose ? Verbosity::kVerbose
                             : Verbosity::kNormal);
  try {
    // Before any work: the plot directory must be writable (the other outputs are checked by each command).
    if (!shared.plot_dir.empty()) check_output_directory(shared.plot_dir);
    std::filesystem::path output;
    for (std::size_t i = 0; i < instances.size(); ++i) {
      if (!*subcommands[i]) continue;
      instances[i]->run(log, argc, argv);
      output = instances[i]->output();
    }
    log.info("wrote " + output.string());
    if (!shared.plot_dir.empty()) {
      // Plots are drawn by Debian's python3-matplotlib from the file just written
      // (postproc/plot_postproc.py).
      const char* script_env = std::getenv("NVH_POSTPROC_PLOT");
      const std::string script = script_env ? script_env : NVH_POSTPROC_PLOT_SCRIPT;
      std::filesystem::create_directories(shared.plot_dir);
      const std::string command =
          "/usr/bin/python3 '" + script + "' '" + output.string() + "' '" + shared.plot_dir + "'";
      log.detail("plot: " + command);
      if (std::system(command.c_str()) != 0) {
        // Exit code 1 means no output: a pipeline (make) must not take the HDF5 file for a finished step.
        std::error_code ignored;
        std::filesystem::remove(output, ignored);
        throw Error("plotting failed (" + command + "); the HDF5 output " + output.string() + " is removed");
      }
    }
    return static_cast<int>(ExitCode::kSuccess);
  } catch (const Error& e) {
    log.error(e.what());
    return static_cast<int>(ExitCode::kFailure);
  } catch (const std::exception& e) {
    log.error(std::string("unexpected failure: ") + e.what());
    return static_cast<int>(ExitCode::kFailure);
  }
}
