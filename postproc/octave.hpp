#pragma once
// Fractional-octave band levels after IEC 61260-1:2014 (base-10 system) and A-weighting after
// IEC 61672-1:2013.
//
// Bands (IEC 61260-1 eqs. 1-5): octave ratio G = 10^(3/10), reference f_r = 1000 Hz; for a bandwidth
// designator 1/b the exact mid-band frequencies are
//   f_m = f_r G^(x/b)            (b odd)        f_m = f_r G^((2x + 1)/(2b))   (b even),  x integer,
// with band edges f_1 = f_m G^(-1/(2b)), f_2 = f_m G^(1/(2b)).
//
// Two methods:
// - filter bank (time domain): per band a Butterworth band-pass of order 6 (prototype order 3) with its
//   -3 dB edges at f_1, f_2, run at the highest rate f_s / 2^k that keeps f_s / 2^k >= 5 f_m: each
//   octave step down low-passes (order-8 Butterworth at 0.2 of the current rate) and keeps every second
//   sample. The band level is the mean square of the band output. Verified against the class 1 acceptance
//   limits (tests/postproc/test_octave.cpp).
// - FFT band summation (steady signals): the Welch PSD integrated over [f_1, f_2], edge bins weighted by
//   their overlap with the band.
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "postproc/iir.hpp"
#include "postproc/spectrum.hpp"

namespace nvh::postproc {

struct Band {
  int index = 0;            ///< x of IEC 61260-1 (0: the band at 1 kHz)
  double center_hz = 0.0;   ///< exact mid-band frequency f_m
  double lower_hz = 0.0;    ///< f_1
  double upper_hz = 0.0;    ///< f_2
  double nominal_hz = 0.0;  ///< nominal mid-band frequency (IEC 61260-1 Annex E) for labels
};

/// Bands of designator 1/b whose exact mid-band frequency lies in [f_low, f_high] (a nominal value such as
/// 20 or 10000 Hz selects its band). Ascending.
std::vector<Band> fractional_octave_bands(int b, double f_low, double f_high);

/// A-weighting in dB at frequency f (IEC 61672-1:2013 eqs. E.1-E.6; 0.0 dB at 1 kHz).
double a_weighting_db(double f);

/// The time-domain filter bank, fed block by block; mean squares per band and per Leq interval.
class OctaveFilterBank {
 public:
  /// Error naming the band if its upper edge is at or above the Nyquist frequency.
  OctaveFilterBank(std::vector<Band> bands, double sample_rate_hz, double interval_s = 0.0,
                   const std::string& signal_name = "");
  ~OctaveFilterBank();
  OctaveFilterBank(const OctaveFilterBank&) = delete;
  OctaveFilterBank& operator=(const OctaveFilterBank&) = delete;

  void push(std::span<const double> samples);

  const std::vector<Band>& bands() const { return bands_; }
  /// Mean square of each band's output over all samples pushed.
  std::vector<double> mean_square() const;
  /// Leq intervals: mean square per (interval, band); interval i covers [i T, (i+1) T) of band time.
  /// Empty unless an interval was given.
  Eigen::MatrixXd interval_mean_square() const;
  double interval_s() const { return interval_s_; }
  /// Modulus of the band's transfer function at f including the anti-alias filters before it (aliasing
  /// not included).
  double response(int band, double f) const;
  /// Sampling rate at which each band is filtered.
  double band_rate_hz(int band) const;

 private:
  struct Stage;
  std::vector<Band> bands_;
  double fs_;
  double interval_s_;
  std::vector<std::unique_ptr<Stage>> stages_;
  std::vector<double> stage_input_, decimated_;  // ping-pong buffers between stages
};

/// Band mean squares from a PSD (unit^2/Hz, energy-correct Welch): sum of PSD_k df over the bins, each
/// weighted by the fraction of [f_k - df/2, f_k + df/2] inside [f_1, f_2). Error if a band is narrower
/// than 2 bins (the resolution is too coarse for it).
std::vector<double> band_mean_square_from_psd(const Spectrum& psd, const std::vector<Band>& bands);

}  // namespace nvh::postproc
