#include "postproc/cli_options.hpp"

namespace nvh::postproc {

void add_output_options(CLI::App& sub, CommonOptions& c, CliShared& shared) {
  sub.add_option("-o,--output", c.output, "HDF5 file to write (temporary, renamed when complete)")
      ->required();
  sub.add_option_function<std::string>(
      "--csv",
      [&c](const std::string& dir) {
        if (!dir.empty()) c.csv_dir = dir;
      },
      "also write CSV tables into this directory");
  sub.add_option("--plot", shared.plot_dir, "also write PNG plots into this directory (python3-matplotlib)");
}

void add_time_window(CLI::App& sub, CommonOptions& c) {
  // The analysis window (docs/postproc.md section 2.1): leave out a start transient.
  sub.add_option_function<double>(
      "--start", [&c](double t) { c.window.start_s = t; },
      "analyse from this time, s, on the signal's time axis (default: its first sample)");
  sub.add_option_function<double>(
      "--end", [&c](double t) { c.window.end_s = t; },
      "analyse up to this time, s (default: the signal's last sample)");
  add_angle_window(sub, c);
}

void add_angle_window(CLI::App& sub, CommonOptions& c) {
  // The shaft-angle window (docs/postproc.md section 2.1): e.g. -30..+90 deg about a cylinder's firing TDC.
  sub.add_option_function<std::vector<double>>(
         "--angle-window",
         [&c](const std::vector<double>& a) {
           c.window.angle_from_deg = a.at(0);
           c.window.angle_to_deg = a.at(1);
         },
         "FROM,TO: analyse only the samples whose shaft angle lies in [FROM, TO], deg (after --start/--end)")
      ->expected(2)
      ->delimiter(',');
  sub.add_option_function<double>(
      "--angle-period", [&c](double p) { c.window.angle_period_deg = p; },
      "the angle window repeats with this period, deg (720: a 4-stroke cycle); its last whole occurrence is "
      "used");
  sub.add_option(
      "--window-angle", c.window.angle_address,
      "the unwrapped shaft angle of --angle-window, deg (default /crank_angle_deg: that dataset in each "
      "signal's file; or a full signal address)");
}

void add_common(CLI::App& sub, CommonOptions& c, CliShared& shared) {
  sub.add_option("SIGNAL", c.signals, "signals to analyse (see postproc --help)")->required();
  add_output_options(sub, c, shared);
  sub.add_option("--quantity", c.quantity,
                 "acceleration, velocity, displacement, pressure, force or power (default: from the unit)")
      ->check(CLI::IsMember({"acceleration", "velocity", "displacement", "pressure", "force", "power"}));
  sub.add_option("--velocity-reference", c.velocity_reference,
                 "dB reference of velocity: engine (5e-8 m/s, default) or iso (1e-9 m/s, ISO 1683)")
      ->check(CLI::IsMember({"engine", "iso"}));
  add_time_window(sub, c);
}

void add_skip_cycles(CLI::App& sub, CommonOptions& c) {
  sub.add_option("--skip-cycles", c.window.skip_cycles,
                 "drop the first N whole cycles (--cycle) of the shaft angle after --start")
      ->check(CLI::NonNegativeNumber);
}

void add_angle(CLI::App& sub, AngleSource& a) {
  sub.add_option(
      "--angle", a.address,
      "shaft angle in deg, unwrapped (default /crank_angle_deg: that dataset in each signal's file; "
      "or a full signal address)");
  sub.add_option("--angle-kind", a.kind, "what --angle holds: angle (deg), speed (rpm) or tacho (pulses)")
      ->check(CLI::IsMember({"angle", "speed", "tacho"}));
  sub.add_option("--pulses-per-rev", a.pulses_per_rev, "tacho pulses per revolution")
      ->check(CLI::PositiveNumber);
  sub.add_option("--threshold", a.threshold, "tacho trigger level (rising crossings)");
}

}  // namespace nvh::postproc
