#pragma once
// Butterworth IIR filters as cascades of second-order sections (biquads), designed in the analog domain and
// mapped by the bilinear transform with pre-warped edge frequencies (Oppenheim & Schafer, Discrete-Time
// Signal Processing, 3rd ed., section 7.1.2):
//   s = 2 f_s (1 - z^-1) / (1 + z^-1),   Omega = 2 f_s tan(pi f / f_s).
// Band-pass: the order-n low-pass prototype poles p_k = exp(i pi (2k + n + 1) / (2n)) are mapped by
// s -> (s^2 + W0^2) / (B s) (W0^2 = W1 W2, B = W2 - W1) into 2n poles, each conjugate pair one section with
// zeros at z = +1 and z = -1; the gain is set to 1 at the given reference frequency.
#include <complex>
#include <span>
#include <vector>

namespace nvh::postproc {

/// One section in direct form II transposed: y = b0 x + s1; s1 = b1 x - a1 y + s2; s2 = b2 x - a2 y.
struct Biquad {
  double b0 = 1, b1 = 0, b2 = 0, a1 = 0, a2 = 0;
  std::complex<double> response(double f, double fs) const;
};

/// A cascade of sections with its state, so a long signal can be filtered block by block.
class SosFilter {
 public:
  SosFilter() = default;
  explicit SosFilter(std::vector<Biquad> sections)
      : sections_(std::move(sections)), state_(2 * sections_.size(), 0.0) {}
  /// Filter in place.
  void process(std::span<double> x);
  std::complex<double> response(double f, double fs) const;
  const std::vector<Biquad>& sections() const { return sections_; }

 private:
  std::vector<Biquad> sections_;
  std::vector<double> state_;
};

/// Band-pass of prototype order n (filter order 2n) with -3 dB edges f1 < f2 < fs/2, unit gain at f_ref.
std::vector<Biquad> butterworth_bandpass(int n, double f1, double f2, double f_ref, double fs);
/// Low-pass of order n (even) with -3 dB cut-off fc < fs/2, unit gain at DC.
std::vector<Biquad> butterworth_lowpass(int n, double fc, double fs);

}  // namespace nvh::postproc
