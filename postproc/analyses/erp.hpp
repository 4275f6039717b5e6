#pragma once
// postproc erp: normal surface velocity of a flexible body from solve's modal velocities and its
// superelement's exported surface; velocity levels and equivalent radiated power (ERP) in fractional-octave
// bands, per surface region (docs/postproc.md sections 3.5, 4.5, 5). The equations are in
// postproc/surface_radiation.hpp.
#include <filesystem>
#include <string>
#include <vector>

#include "common/log.hpp"
#include "postproc/options.hpp"
#include "postproc/surface_radiation.hpp"
#include "postproc/window.hpp"

namespace nvh::postproc {

struct ErpCommand {
  std::filesystem::path results;       ///< solve's results file
  std::filesystem::path superelement;  ///< the body's superelement file (with /surface)
  std::string body;                    ///< the flexible body's name in the results (/bodies/<body>)
  CommonOptions common;                ///< output, CSV, velocity reference, --start/--end (no signals)
  WindowKind window = WindowKind::kHann;
  int segment_length = 0;      ///< N, samples; 0: from resolution_hz, or the longest power of two
  double resolution_hz = 0.0;  ///< 0: one segment over the longest power of two of samples
  double overlap = 0.5;
  int fraction = 3;                         ///< b of 1/b-octave bands
  double fmin_hz = 0.0;                     ///< 0: 20 Hz or the lowest band at least 2 bins wide
  double fmax_hz = 0.0;                     ///< 0: 10 kHz or the highest band below Nyquist
  double density_kg_m3 = kAirDensity;       ///< rho of the fluid
  double sound_speed_m_s = kAirSoundSpeed;  ///< c of the fluid
  std::vector<SurfaceRegion> regions;
  bool node_spectra = false;   ///< also write the PSD of every surface node
  bool include_rigid = false;  ///< add the frame's rigid-body motion (eq. 1a of surface_radiation.hpp)
};

/// Runs the analysis and writes `common.output`; an error leaves no output.
void run_erp(const ErpCommand& command, const Logger& log, int argc, const char* const* argv);

}  // namespace nvh::postproc
