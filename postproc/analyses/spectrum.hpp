#pragma once
// postproc spectrum: Welch spectra (amplitude, RMS or PSD) with dB levels (docs/postproc.md sections 3.1,
// 4.1, 5).
#include "common/log.hpp"
#include "postproc/options.hpp"
#include "postproc/spectrum.hpp"

namespace nvh::postproc {

struct SpectrumCommand {
  CommonOptions common;
  SpectrumOptions options;
  double fmax_hz = 0.0;  ///< 0: up to Nyquist
};

/// Runs the analysis on every signal and writes `common.output`; an error leaves no output.
void run_spectrum(const SpectrumCommand& command, const Logger& log, int argc, const char* const* argv);

}  // namespace nvh::postproc
