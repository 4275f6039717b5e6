// postproc: spectra, fractional-octave levels, order analysis and statistics of signals from solve's results,
// any HDF5 or CSV file, or measurements in UFF58. A thin CLI over postproc/commands.hpp.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <iostream>

#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "common/log.hpp"
#include "common/output_path.hpp"
#include "common/version.hpp"
#include "postproc/commands.hpp"

namespace {

constexpr const char* kDescription =
    R"(postproc - spectra, 1/3-octave levels, orders and statistics (step 3 of 3: condense -> solve -> postproc)

Signals (docs/postproc.md section 2):
  FILE.h5:/dataset                  1-D dataset; sample rate from a 'sample_rate_hz' attribute on it or a
                                    group above it, else from a uniformly spaced 'time' dataset beside it
  FILE.h5:/markers/top1/acceleration[2]   column 2 (0-based; or [x] [y] [z]) of an (n, 3) dataset
  FILE.csv:column                   CSV with a header row and a time column (time, time_s or t)
  FILE.uff[:N]                      N-th dataset 58 (ASCII or binary) of a universal file, default 1
  NAME=ADDRESS                      name the signal NAME in the outputs
Each subcommand writes one HDF5 file (-o) with /spectrum, /octave, /orders or /stats groups per signal,
units and dB references as attributes and provenance; --csv DIR adds CSV tables, --plot DIR PNG figures.

Exit codes: 0 success; 1 bad input or failed run (the message names the signal, file and what was
expected; no output is written); 2 bad command line; 3 interrupted.)";

void add_common(CLI::App* sub, nvh::postproc::CommonOptions& c, std::string& plot_dir, std::string& csv_dir) {
  sub->add_option("SIGNAL", c.signals, "signals to analyse (see postproc --help)")->required();
  sub->add_option("-o,--output", c.output, "HDF5 file to write (temporary, renamed when complete)")
      ->required();
  sub->add_option("--csv", csv_dir, "also write CSV tables into this directory");
  sub->add_option("--plot", plot_dir, "also write PNG plots into this directory (python3-matplotlib)");
  sub->add_option("--quantity", c.quantity,
                  "acceleration, velocity, displacement, pressure, force or power (default: from the unit)")
      ->check(CLI::IsMember({"acceleration", "velocity", "displacement", "pressure", "force", "power"}));
  sub->add_option("--velocity-reference", c.velocity_reference,
                  "dB reference of velocity: engine (5e-8 m/s, default) or iso (1e-9 m/s, ISO 1683)")
      ->check(CLI::IsMember({"engine", "iso"}));
  // The analysis window (docs/postproc.md section 2.1): leave out a start transient.
  sub->add_option_function<double>(
      "--start", [&c](double t) { c.window.start_s = t; },
      "analyse from this time, s, on the signal's time axis (default: its first sample)");
  sub->add_option_function<double>(
      "--end", [&c](double t) { c.window.end_s = t; },
      "analyse up to this time, s (default: the signal's last sample)");
}

void add_skip_cycles(CLI::App* sub, nvh::postproc::CommonOptions& c) {
  sub->add_option("--skip-cycles", c.window.skip_cycles,
                  "drop the first N whole cycles (--cycle) of the shaft angle after --start")
      ->check(CLI::NonNegativeNumber);
}

void add_angle(CLI::App* sub, nvh::postproc::AngleSource& a) {
  sub->add_option(
      "--angle", a.address,
      "shaft angle in deg, unwrapped (default /crank_angle_deg: that dataset in each signal's file; "
      "or a full signal address)");
  sub->add_option("--angle-kind", a.kind, "what --angle holds: angle (deg), speed (rpm) or tacho (pulses)")
      ->check(CLI::IsMember({"angle", "speed", "tacho"}));
  sub->add_option("--pulses-per-rev", a.pulses_per_rev, "tacho pulses per revolution")
      ->check(CLI::PositiveNumber);
  sub->add_option("--threshold", a.threshold, "tacho trigger level (rising crossings)");
}

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
  std::string plot_dir, csv_dir;

  SpectrumCommand spectrum;
  std::string window = "hann", type = "rms", scaling = "amplitude";
  int integrate = 0, differentiate = 0;
  CLI::App* s = app.add_subcommand("spectrum", "Welch spectra: amplitude, RMS or PSD, with dB levels");
  add_common(s, spectrum.common, plot_dir, csv_dir);
  s->add_option("--window", window, "rectangular, hann (default), hamming, flattop, blackman-harris");
  s->add_option("--type", type, "amplitude (peak), rms (default) or psd")
      ->check(CLI::IsMember({"amplitude", "rms", "psd"}));
  s->add_option("--scaling", scaling, "amplitude (sines read right, default) or energy (broadband right)")
      ->check(CLI::IsMember({"amplitude", "energy"}));
  s->add_option("--resolution", spectrum.options.resolution_hz, "frequency resolution, Hz (default 1)")
      ->check(CLI::PositiveNumber);
  s->add_option("--segment", spectrum.options.segment_length,
                "segment length, samples (overrides --resolution)")
      ->check(CLI::PositiveNumber);
  s->add_option("--overlap", spectrum.options.overlap, "segment overlap fraction in [0, 1) (default 0.5)");
  s->add_option("--integrate", integrate,
                "integrate N times in the frequency domain (acceleration -> velocity)")
      ->check(CLI::Range(0, 2));
  s->add_option("--differentiate", differentiate, "differentiate N times in the frequency domain")
      ->check(CLI::Range(0, 2));
  s->add_option("--fmax", spectrum.fmax_hz, "store bins up to this frequency, Hz (default: Nyquist)");

  OctaveCommand octave;
  CLI::App* o = app.add_subcommand("octave", "fractional-octave band levels (IEC 61260-1), A-weighting, Leq");
  add_common(o, octave.common, plot_dir, csv_dir);
  o->add_option("--fraction", octave.fraction, "b of 1/b-octave bands: 1, 3 (default), 6, 12, 24 (at most 48)")
      ->check(CLI::Range(1, 48));
  o->add_option("--fmin", octave.fmin_hz, "lowest band (nominal mid-band), Hz (default 20)")
      ->check(CLI::PositiveNumber);
  o->add_option("--fmax", octave.fmax_hz, "highest band, Hz (default: 10000 or the highest below Nyquist)")
      ->check(CLI::PositiveNumber);
  o->add_option("--method", octave.method, "filter (time-domain bank, default) or fft (band summation)")
      ->check(CLI::IsMember({"filter", "fft"}));
  o->add_option("--weighting", octave.weighting, "Z (none, default) or A (IEC 61672-1)")
      ->check(CLI::IsMember({"Z", "A"}));
  o->add_option("--interval", octave.interval_s, "Leq interval for band levels over time, s (filter method)")
      ->check(CLI::NonNegativeNumber);

  OrdersCommand orders;
  std::string interpolation = "sinc";
  CLI::App* r =
      app.add_subcommand("orders", "computed order tracking: order spectra per cycle, cuts, Campbell");
  add_common(r, orders.common, plot_dir, csv_dir);
  add_angle(r, orders.angle);
  add_skip_cycles(r, orders.common);
  r->add_option("--cycle", orders.options.cycle_deg,
                "analysis cycle, deg (720: 0.5-order resolution, default)")
      ->check(CLI::PositiveNumber);
  r->add_option("--samples-per-cycle", orders.options.samples_per_cycle,
                "angle samples per cycle (default: auto)")
      ->check(CLI::PositiveNumber);
  r->add_option("--max-order", orders.options.max_order,
                "highest order stored (default: 0.8 x angle Nyquist)")
      ->check(CLI::PositiveNumber);
  r->add_option("--interpolation", interpolation, "sinc (band-limited, default) or linear")
      ->check(CLI::IsMember({"sinc", "linear"}));
  r->add_flag("--cut", orders.cut,
              "also /orders/cut: mean order spectrum of each signal against its mean rpm");
  r->add_flag("--campbell", orders.campbell, "also a Campbell diagram (rpm x frequency) per signal");
  r->add_option("--campbell-rpm-step", orders.campbell_rpm_step, "speed bin of the Campbell diagram, rpm")
      ->check(CLI::PositiveNumber);
  r->add_option("--campbell-fmax", orders.campbell_fmax_hz, "highest Campbell frequency, Hz")
      ->check(CLI::PositiveNumber);
  r->add_option("--campbell-resolution", orders.campbell_resolution_hz, "Campbell frequency resolution, Hz")
      ->check(CLI::PositiveNumber);

  StatsCommand stats;
  std::vector<double> band;
  CLI::App* t =
      app.add_subcommand("stats", "RMS, peak, crest factor, band RMS, harmonics of the running speed");
  add_common(t, stats.common, plot_dir, csv_dir);
  t->add_option("--band", band, "band-limited RMS over LOW HIGH, Hz")->expected(2);
  t->add_option("--harmonics", stats.harmonics,
                "orders of the running speed: amplitude and phase (needs the angle)")
      ->delimiter(',');
  t->add_option("--cycle", stats.cycle_deg, "cycle for the harmonics, deg (default 360: whole orders)")
      ->check(CLI::PositiveNumber);
  add_angle(t, stats.angle);
  add_skip_cycles(t, stats.common);

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
    if (!plot_dir.empty()) check_output_directory(plot_dir);
    std::filesystem::path output;
    if (*s) {
      if (integrate && differentiate) throw Error("give --integrate or --differentiate, not both");
      spectrum.options.window = parse_window(window);
      spectrum.options.type = parse_spectrum_type(type);
      spectrum.options.scaling = parse_scaling(scaling);
      spectrum.options.derivative = differentiate - integrate;
      if (!csv_dir.empty()) spectrum.common.csv_dir = csv_dir;
      run_spectrum(spectrum, log, argc, argv);
      output = spectrum.common.output;
    } else if (*o) {
      if (!csv_dir.empty()) octave.common.csv_dir = csv_dir;
      run_octave(octave, log, argc, argv);
      output = octave.common.output;
    } else if (*r) {
      orders.options.interpolation =
          interpolation == "linear" ? Interpolation::kLinear : Interpolation::kSinc;
      if (!csv_dir.empty()) orders.common.csv_dir = csv_dir;
      run_orders(orders, log, argc, argv);
      output = orders.common.output;
    } else if (*t) {
      if (band.size() == 2) stats.band_hz = std::make_pair(band[0], band[1]);
      if (!csv_dir.empty()) stats.common.csv_dir = csv_dir;
      run_stats(stats, log, argc, argv);
      output = stats.common.output;
    }
    log.info("wrote " + output.string());
    if (!plot_dir.empty()) {
      // Plots are drawn by Debian's python3-matplotlib from the file just written
      // (postproc/plot_postproc.py).
      const char* script_env = std::getenv("NVH_POSTPROC_PLOT");
      const std::string script = script_env ? script_env : NVH_POSTPROC_PLOT_SCRIPT;
      std::filesystem::create_directories(plot_dir);
      const std::string command =
          "/usr/bin/python3 '" + script + "' '" + output.string() + "' '" + plot_dir + "'";
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
