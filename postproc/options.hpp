#pragma once
// Options every analysis shares (signals, output, CSV, quantity, dB reference, analysis window) and the shaft
// angle source of the analyses that need one; the postproc file format's name. docs/postproc.md section 1.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "postproc/analysis_window.hpp"

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

struct AngleSource {
  std::string kind = "angle";                ///< "angle" (deg, unwrapped), "speed" (rpm) or "tacho"
  std::string address = "/crank_angle_deg";  ///< "/path" alone: that dataset in each signal's own file
  int pulses_per_rev = 1;
  double threshold = 0.5;
};

}  // namespace nvh::postproc
