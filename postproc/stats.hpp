#pragma once
// Time-domain statistics of a signal, streamed: mean, RMS, peak (largest |x|), crest factor peak / RMS;
// band-limited RMS from a PSD; amplitude and phase of the harmonics of the running speed (the k-th order
// of the shaft, from the order tracker, averaged over cycles: the "effective acceleration" tables of
// compressor and engine mount studies).
#include <cstdint>
#include <span>
#include <vector>

#include "postproc/orders.hpp"
#include "postproc/spectrum.hpp"

namespace nvh::postproc {

class StatsAccumulator {
 public:
  void push(std::span<const double> x);
  std::int64_t count() const { return count_; }
  double mean() const;
  double rms() const;  ///< sqrt(mean of x^2), the mean included
  double peak() const { return peak_; }
  double crest_factor() const;  ///< peak / RMS

 private:
  std::int64_t count_ = 0;
  double sum_ = 0.0;  // Kahan-free running sums are enough at double precision for 1e8 samples
  double sum_squares_ = 0.0;
  double peak_ = 0.0;
};

/// RMS in [f_low, f_high] from an energy-correct PSD (edge bins weighted by their overlap).
double band_rms_from_psd(const Spectrum& psd, double f_low, double f_high);

/// One harmonic of the running speed, averaged over the analysed cycles.
struct Harmonic {
  double order = 0.0;
  double amplitude = 0.0;         ///< mean of the per-cycle peak amplitudes
  double phase_deg = 0.0;         ///< circular mean of the per-cycle cosine phases
  double amplitude_spread = 0.0;  ///< standard deviation of the per-cycle amplitudes
};

/// The harmonics `orders` (each must be a multiple of 360 / cycle_deg) from per-cycle order spectra.
std::vector<Harmonic> harmonics(const OrderSpectra& spectra, const std::vector<double>& orders);

}  // namespace nvh::postproc
