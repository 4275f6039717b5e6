#pragma once
// The extension point of postproc (docs/postproc.md, "Adding an analysis"): every subcommand is one
// Analysis, in one file under postproc/analyses/, registered by one line in postproc/analysis.cpp. main.cpp
// knows none of them: it makes a CLI11 subcommand per registered analysis, lets the analysis declare its
// options on it, parses, and runs the one chosen.
//
// An analysis
//   - declares its options (add_options): usually the shared ones of postproc/cli_options.hpp plus its own;
//   - runs (run): checks the options, reads its inputs (postproc/signal_input.hpp, or files of its own),
//     analyses, and writes its HDF5 file and CSV tables through postproc/output.hpp and postproc/csv.hpp: the
//     HDF5 file is created with the provenance by create_output() and, with the CSV files, renamed into
//     place by commit_outputs() only when everything is written, so that an error leaves no output;
//   - names the file it wrote (output), which main.cpp then hands to the plot script with --plot.
// Errors are nvh::Error with a message naming the input and what was expected (exit code 1).
#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "common/log.hpp"

namespace nvh::postproc {

/// What main.cpp shares with every analysis's options: the --plot directory (drawn by main.cpp).
struct CliShared {
  std::string plot_dir;
};

class Analysis {
 public:
  virtual ~Analysis() = default;
  /// Options: declare the subcommand's arguments on `sub` (bound to members of the analysis).
  virtual void add_options(CLI::App& sub, CliShared& shared) = 0;
  /// Run and write: the analysis on its inputs, its HDF5 output (and CSV files) written and committed.
  /// `argc`/`argv` go into the provenance.
  virtual void run(const Logger& log, int argc, const char* const* argv) = 0;
  /// The HDF5 file written by run().
  virtual std::filesystem::path output() const = 0;
};

/// One registered analysis: its subcommand name, the one-line description of `postproc --help`, and a
/// factory.
struct AnalysisEntry {
  std::string name;
  std::string summary;
  std::unique_ptr<Analysis> (*make)();
};

/// The registry, in the order of `postproc --help` (postproc/analysis.cpp: one line per analysis).
const std::vector<AnalysisEntry>& analyses();

}  // namespace nvh::postproc
