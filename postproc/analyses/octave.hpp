#pragma once
// postproc octave: 1/b-octave band levels (IEC 61260-1) by a filter bank or FFT band summation,
// A-weighting, Leq per interval (docs/postproc.md sections 3.2, 4.2, 5).
#include <string>

#include "common/log.hpp"
#include "postproc/options.hpp"

namespace nvh::postproc {

struct OctaveCommand {
  CommonOptions common;
  int fraction = 3;  ///< b of 1/b octave
  double fmin_hz = 20.0;
  double fmax_hz = 0.0;           ///< 0: 10 kHz or the highest band below every signal's Nyquist frequency
  std::string method = "filter";  ///< "filter" (time-domain bank) or "fft" (band summation)
  std::string weighting = "Z";    ///< "Z" (none) or "A"
  double interval_s = 0.0;        ///< Leq interval (filter method); 0: none
};

/// Runs the analysis on every signal and writes `common.output`; an error leaves no output.
void run_octave(const OctaveCommand& command, const Logger& log, int argc, const char* const* argv);

}  // namespace nvh::postproc
