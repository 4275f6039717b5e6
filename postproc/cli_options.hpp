#pragma once
// Command-line options shared by the analyses (docs/postproc.md section 1): the signals, the output files,
// the quantity and dB reference, the analysis window and the shaft angle.
#include <CLI/CLI.hpp>

#include "postproc/analysis.hpp"
#include "postproc/options.hpp"

namespace nvh::postproc {

/// -o, --csv, --plot.
void add_output_options(CLI::App& sub, CommonOptions& c, CliShared& shared);
/// --start, --end and the shaft-angle window (add_angle_window).
void add_time_window(CLI::App& sub, CommonOptions& c);
/// --angle-window, --angle-period, --window-angle (docs/postproc.md section 2.1).
void add_angle_window(CLI::App& sub, CommonOptions& c);
/// SIGNAL..., the output options, --quantity, --velocity-reference, --start, --end, the angle window.
void add_common(CLI::App& sub, CommonOptions& c, CliShared& shared);
/// --skip-cycles.
void add_skip_cycles(CLI::App& sub, CommonOptions& c);
/// --angle, --angle-kind, --pulses-per-rev, --threshold.
void add_angle(CLI::App& sub, AngleSource& a);

}  // namespace nvh::postproc
