#pragma once
// Spectral windows (periodic, "DFT-even": w[n] = sum_k c_k cos(2 pi k n / N), n = 0..N-1) and their sums.
//
// Coefficients: Hann and Hamming (Harris 1978, Proc. IEEE 66(1), Table 1); 4-term Blackman-Harris
// (Harris 1978, -92 dB); flat-top HFT90D (Heinzel, Ruediger, Schilling 2002, "Spectrum and spectral density
// estimation by the DFT", section C.2: amplitude flatness 0.0039 dB, NENBW 3.8832 bins).
#include <string>
#include <vector>

namespace nvh::postproc {

enum class WindowKind { kRectangular, kHann, kHamming, kFlatTop, kBlackmanHarris };

/// "rectangular", "hann", "hamming", "flattop", "blackman-harris"; error listing them otherwise.
WindowKind parse_window(const std::string& name);
std::string to_string(WindowKind kind);

struct Window {
  WindowKind kind = WindowKind::kHann;
  std::vector<double> w;
  double sum = 0.0;          ///< S1 = sum w[n]: coherent gain * N (amplitude-correct scaling)
  double sum_squares = 0.0;  ///< S2 = sum w[n]^2 (energy-correct scaling)
  /// Normalized equivalent noise bandwidth N S2 / S1^2, bins (Heinzel eq. 21).
  double nenbw_bins() const { return static_cast<double>(w.size()) * sum_squares / (sum * sum); }
};

Window make_window(WindowKind kind, int n);

}  // namespace nvh::postproc
