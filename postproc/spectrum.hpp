#pragma once
// Single-sided spectra by Welch's method (Welch 1967, IEEE Trans. Audio Electroacoust. 15(2)): the signal is
// cut into segments of N samples overlapping by a fraction r, each windowed and transformed (FFTW, one plan
// reused for all segments), and the squared magnitudes averaged:
//   <|X_k|^2> = (1/M) sum_m |X_m[k]|^2,   X_m[k] = sum_n w[n] x[mH + n] e^{-2 pi i k n / N},  H = N (1 - r)
// with c_k = 2 for 0 < k < N/2 and 1 at DC and Nyquist, S1 = sum w[n], S2 = sum w[n]^2. The scalings
// (Heinzel, Ruediger, Schilling 2002, "Spectrum and spectral density estimation by the DFT", eqs. 19-24):
//   amplitude-correct:  RMS_k = sqrt(c_k <|X_k|^2>) / S1     a sine of amplitude A reads A / sqrt 2 at its
//   bin energy-correct:     RMS_k = sqrt(c_k <|X_k|^2> / (N S2))  sum_k RMS_k^2 = mean square (Parseval), so
//                                                             broadband and band levels are right
//   PSD_k = c_k <|X_k|^2> / (f_s S2)   (unit^2/Hz, always energy-correct)
// and the peak amplitude spectrum is sqrt(2) RMS_k (RMS_k itself at DC and Nyquist).
// Integration and differentiation in the frequency domain multiply each bin's magnitude by (2 pi f)^d
// (d > 0 differentiates, d < 0 integrates; the phase is irrelevant for magnitudes); the DC bin of an
// integral is set to 0.
#include <Eigen/Core>
#include <complex>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "postproc/window.hpp"

namespace nvh::postproc {

enum class SpectrumType { kAmplitude, kRms, kPsd };
enum class Scaling { kAmplitude, kEnergy };

SpectrumType parse_spectrum_type(const std::string& name);  ///< "amplitude", "rms", "psd"
std::string to_string(SpectrumType type);
Scaling parse_scaling(const std::string& name);  ///< "amplitude", "energy"
std::string to_string(Scaling scaling);

struct SpectrumOptions {
  WindowKind window = WindowKind::kHann;
  int segment_length = 0;      ///< N, samples; 0: from resolution_hz (next power of two at or above fs/df)
  double resolution_hz = 1.0;  ///< used when segment_length is 0
  double overlap = 0.5;        ///< r in [0, 1)
  SpectrumType type = SpectrumType::kRms;
  Scaling scaling = Scaling::kAmplitude;  ///< for amplitude and RMS spectra
  int derivative = 0;                     ///< +1, +2: differentiate; -1, -2: integrate
};

/// Segment length the options give at a sample rate (error if longer than the signal, naming both).
int segment_length_for(const SpectrumOptions& options, double sample_rate_hz, std::int64_t signal_size,
                       const std::string& signal_name);

/// A real-to-complex FFT of one size through FFTW; the plan is made once and reused.
class FftPlan {
 public:
  explicit FftPlan(int n);
  ~FftPlan();
  FftPlan(const FftPlan&) = delete;
  FftPlan& operator=(const FftPlan&) = delete;
  int size() const { return n_; }
  double* input() { return in_; }                              ///< n values
  const std::complex<double>* output() const { return out_; }  ///< n/2 + 1 bins
  void execute();

 private:
  int n_;
  double* in_ = nullptr;
  std::complex<double>* out_ = nullptr;
  void* plan_ = nullptr;
};

struct Spectrum {
  Eigen::VectorXd frequency_hz;
  Eigen::VectorXd values;  ///< peak amplitude, RMS or PSD, in `unit`
  std::string unit;
  SpectrumType type = SpectrumType::kRms;
  Scaling scaling = Scaling::kAmplitude;
  WindowKind window = WindowKind::kHann;
  int segment_length = 0;
  double overlap = 0.0;
  std::int64_t averages = 0;
  double resolution_hz = 0.0;  ///< f_s / N
  double enbw_hz = 0.0;        ///< equivalent noise bandwidth of one bin, NENBW f_s / N
  int derivative = 0;
};

/// Welch averaging fed block by block (memory: one segment and the running sum).
class WelchAccumulator {
 public:
  WelchAccumulator(double sample_rate_hz, int segment_length, const SpectrumOptions& options);
  void push(std::span<const double> samples);
  std::int64_t averages() const { return averages_; }
  /// The averaged spectrum; `unit` is the signal's unit (changed by the derivative order).
  Spectrum result(const std::string& unit) const;
  /// Mean of |X_k|^2 over the segments so far (unscaled; for band summation).
  const std::vector<double>& power_sum() const { return power_sum_; }

 private:
  void process_segment(const double* segment);
  double fs_;
  SpectrumOptions options_;
  Window window_;
  FftPlan plan_;
  int hop_;
  std::vector<double> pending_;  // samples not yet consumed by a full segment
  std::size_t pending_start_ = 0;
  std::vector<double> power_sum_;
  std::int64_t averages_ = 0;
};

/// Welch spectrum of samples held in memory.
Spectrum welch_spectrum(std::span<const double> samples, double sample_rate_hz,
                        const SpectrumOptions& options, const std::string& unit = "");

/// The unit after `derivative` time derivatives (m/s^2 -1-> m/s -1-> m; other units get "*s^-d").
std::string derived_unit(const std::string& unit, int derivative);

}  // namespace nvh::postproc
