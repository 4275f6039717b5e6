#pragma once
// The postproc subcommands as library functions: read signals block by block, run the analyses, write the
// HDF5 output (layout in docs/postproc.md section 5) and, on request, CSV files. main.cpp is a thin CLI over
// these; tests call them directly too.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/log.hpp"
#include "common/provenance.hpp"
#include "postproc/analysis_window.hpp"
#include "postproc/orders.hpp"
#include "postproc/spectrum.hpp"

namespace nvh::postproc {

/// Output format of postproc files.
inline constexpr const char* kPostprocFormat = "nvh-postproc";
inline constexpr const char* kPostprocFormatVersion = "1.0";

struct CommonOptions {
  std::vector<std::string> signals;              ///< signal addresses (signal.hpp)
  std::filesystem::path output;                  ///< HDF5 file to write
  std::optional<std::filesystem::path> csv_dir;  ///< also write CSV files here
  std::string quantity;  ///< overrides the quantity the unit implies ("" = from the unit)
  std::string velocity_reference = "engine";  ///< "engine" (5e-8 m/s) or "iso" (1e-9 m/s)
  std::int64_t block = 1 << 20;               ///< samples per read
  AnalysisWindow window;  ///< --start / --end / --skip-cycles (skip_cycles: orders and stats only)
};

struct SpectrumCommand {
  CommonOptions common;
  SpectrumOptions options;
  double fmax_hz = 0.0;  ///< 0: up to Nyquist
};

struct OctaveCommand {
  CommonOptions common;
  int fraction = 3;  ///< b of 1/b octave
  double fmin_hz = 20.0;
  double fmax_hz = 0.0;           ///< 0: 10 kHz or the highest band below every signal's Nyquist frequency
  std::string method = "filter";  ///< "filter" (time-domain bank) or "fft" (band summation)
  std::string weighting = "Z";    ///< "Z" (none) or "A"
  double interval_s = 0.0;        ///< Leq interval (filter method); 0: none
};

struct AngleSource {
  std::string kind = "angle";                ///< "angle" (deg, unwrapped), "speed" (rpm) or "tacho"
  std::string address = "/crank_angle_deg";  ///< "/path" alone: that dataset in each signal's own file
  int pulses_per_rev = 1;
  double threshold = 0.5;
};

struct OrdersCommand {
  CommonOptions common;
  AngleSource angle;
  OrderOptions options;
  bool cut = false;  ///< also /orders/cut: one mean order spectrum per signal against rpm
  bool campbell = false;
  double campbell_rpm_step = 50.0;
  double campbell_fmax_hz = 2000.0;
  double campbell_resolution_hz = 2.0;
};

struct StatsCommand {
  CommonOptions common;
  std::optional<std::pair<double, double>> band_hz;  ///< band-limited RMS over [lo, hi]
  double band_resolution_hz = 1.0;
  std::vector<double> harmonics;  ///< orders of the running speed (needs the angle)
  AngleSource angle;
  double cycle_deg = 360.0;
};

/// Each runs the analysis on every signal and writes `common.output`; an error leaves no output.
/// `argv` goes into the provenance.
void run_spectrum(const SpectrumCommand& command, const Logger& log, int argc, const char* const* argv);
void run_octave(const OctaveCommand& command, const Logger& log, int argc, const char* const* argv);
void run_orders(const OrdersCommand& command, const Logger& log, int argc, const char* const* argv);
void run_stats(const StatsCommand& command, const Logger& log, int argc, const char* const* argv);

}  // namespace nvh::postproc
