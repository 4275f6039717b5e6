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

/// Four cascades of up to four sections each run in lock-step, one per lane, software-pipelined across
/// sections (iir.cpp): a stage of the octave bank (three band-passes and the anti-alias low-pass) costs
/// little more than one cascade. Shorter cascades are padded with identity sections. The outputs are those
/// of the cascades delayed by three samples.
class CascadeLanes4 {
 public:
  static constexpr int kLanes = 4;
  static constexpr int kSections = 4;
  /// Samples by which the outputs lag the input (the pipeline fills with zeros first).
  static constexpr int kDelay = kSections - 1;
  /// Lane l gets `cascades[l]` (at most 4 lanes, each at most 4 sections).
  explicit CascadeLanes4(const std::vector<std::vector<Biquad>>& cascades);
  /// Filter x[0..n): lanes with `square_sum` add their output's squares to square_sum[lane]; lane
  /// `output_lane` (or none if < 0) writes every second output sample into `decimated` (phase kept across
  /// calls) and returns how many it wrote.
  std::size_t process(const double* x, std::size_t n, double* square_sum, int output_lane, double* decimated);

 private:
  alignas(32) double b0_[kSections][kLanes], b1_[kSections][kLanes], b2_[kSections][kLanes];
  alignas(32) double a1_[kSections][kLanes], a2_[kSections][kLanes];
  alignas(32) double s1_[kSections][kLanes] = {}, s2_[kSections][kLanes] = {};
  alignas(32) double carry_[kSections][kLanes] = {};  // pipeline registers between sections
  bool keep_next_ = true;
};

/// Band-pass of prototype order n (filter order 2n) with -3 dB edges f1 < f2 < fs/2, unit gain at f_ref.
std::vector<Biquad> butterworth_bandpass(int n, double f1, double f2, double f_ref, double fs);
/// Low-pass of order n (even) with -3 dB cut-off fc < fs/2, unit gain at DC.
std::vector<Biquad> butterworth_lowpass(int n, double fc, double fs);

}  // namespace nvh::postproc
