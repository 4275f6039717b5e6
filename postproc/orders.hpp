#pragma once
// Computed order tracking (Fyfe & Munck 1997, "Analysis of computed order tracking", Mech. Syst. Signal
// Process. 11(2); Blough 2003, "A survey of DSP methods for rotating machinery analysis", section 4).
//
// The signal x(t), sampled at f_s, is resampled at uniform shaft angle: theta_j = theta_0 + j dtheta with
// M = samples_per_cycle points per cycle of `cycle_deg` (720 deg for a 4-stroke engine). The time of each
// angle comes from inverting the shaft angle theta(t) (cubic Hermite between samples, Newton steps); the
// value x(t_j) from band-limited interpolation
//   x(t) = sum_m x[m] beta h(beta (t f_s - m)),  h(u) = sinc(u) w_K(u / L),  |u| <= L,
// a Kaiser-windowed sinc (half-width L = 16 samples, Kaiser beta 8; Oppenheim & Schafer 3rd ed. section
// 4.6 and 7.5.3), with beta = min(1, r / f_s) lowering the cut-off to the angle-domain Nyquist rate when the
// angular sampling rate r = M theta'(t) / cycle_deg falls below f_s (anti-aliasing). Linear interpolation is
// available for comparison (its amplitude loss is |1 - u + u e^{i omega}| at fractional position u).
//
// Each cycle of M angle samples is transformed (rectangular window: every order k 360/cycle_deg is periodic
// in the cycle) into amplitude |X_k| 2 / M (|X_0| / M for order 0) and phase arg X_k (cosine phase, angle
// zero at the cycle start, a multiple of cycle_deg of the shaft angle). With cycle_deg = 720 the orders are
// 0, 0.5, 1, 1.5, ...; the cycle's speed is 60 (cycle_deg/360) / (t_end - t_start) rpm.
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace nvh::postproc {

enum class Interpolation { kLinear, kSinc };

struct OrderOptions {
  double cycle_deg = 720.0;   ///< analysis cycle (720: 4-stroke, order resolution 0.5)
  int samples_per_cycle = 0;  ///< M; 0: chosen by choose_samples_per_cycle
  double max_order = 0.0;     ///< highest order reported; 0: 0.8 x the angle-domain Nyquist order
  Interpolation interpolation = Interpolation::kSinc;
};

/// The largest M (an FFT of M points per cycle; FFTW aborted on 2^31 - 1).
inline constexpr int kMaxSamplesPerCycle = 1 << 24;

/// A power of two M with M / cycle >= f_s / (max shaft speed): no loss at the highest speed.
int choose_samples_per_cycle(double sample_rate_hz, double max_rev_per_s, double cycle_deg);

/// Per-cycle order spectra (rows: cycles; columns: orders).
struct OrderSpectra {
  Eigen::VectorXd order;
  Eigen::MatrixXd amplitude;  ///< peak amplitude per cycle and order, signal unit
  Eigen::MatrixXd phase_deg;  ///< cosine phase, deg
  Eigen::VectorXd rpm;        ///< mean shaft speed of each cycle
  Eigen::VectorXd start_time_s;
  double cycle_deg = 720.0;
  int samples_per_cycle = 0;
};

/// Streaming order tracker: push aligned blocks of the signal and of the shaft angle (deg, increasing,
/// one value per signal sample). Memory: the kernel's reach plus one cycle, whatever the signal length.
class OrderTracker {
 public:
  OrderTracker(double sample_rate_hz, const OrderOptions& options, int samples_per_cycle);
  ~OrderTracker();
  OrderTracker(const OrderTracker&) = delete;
  OrderTracker& operator=(const OrderTracker&) = delete;
  /// Error naming the sample if the angle decreases.
  void push(std::span<const double> x, std::span<const double> angle_deg);
  /// Completed cycles. The first cycle starts at the first multiple of cycle_deg that the interpolation
  /// kernel can reach (about 130 samples into the signal); a cycle cut by the end of the signal is dropped.
  OrderSpectra result() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Whole-signal convenience: order spectra of x with its shaft angle (both in memory).
OrderSpectra order_spectra(std::span<const double> x, std::span<const double> angle_deg,
                           double sample_rate_hz, const OrderOptions& options);

/// Shaft angle from a speed signal (rpm) by the trapezoidal rule, theta(0) = 0; carries its state between
/// blocks.
class SpeedIntegrator {
 public:
  explicit SpeedIntegrator(double sample_rate_hz) : dt_(1.0 / sample_rate_hz) {}
  void angle(std::span<const double> rpm, std::span<double> angle_deg);

 private:
  double dt_;
  double theta_ = 0.0;
  double last_rpm_ = 0.0;
  bool started_ = false;
};

/// Shaft angle from a tacho: rising crossings of `threshold` (linearly interpolated in time) are
/// 360 / pulses_per_rev apart; between them the angle follows a cubic Hermite through the pulse times.
/// First pass: collect pulse times (streamed); then angle_at() for any sample range.
class TachoAngle {
 public:
  TachoAngle(double sample_rate_hz, int pulses_per_rev, double threshold);
  void push_pulses(std::span<const double> tacho);
  /// Angle (deg) at samples [offset, offset + out.size()); error if fewer than 3 pulses were found.
  void angle(std::int64_t offset, std::span<double> out) const;
  std::size_t pulses() const { return times_.size(); }

 private:
  double fs_;
  double step_deg_;
  double threshold_;
  std::int64_t seen_ = 0;
  double last_ = 0.0;
  std::vector<double> times_;  // s from the first sample
};

/// Campbell diagram / waterfall: Hann-windowed frames of N samples (hop N/2), each tagged with its mean
/// speed, power-averaged into speed bins of width rpm_step; RMS amplitude (amplitude-correct) up to fmax.
class CampbellAccumulator {
 public:
  CampbellAccumulator(double sample_rate_hz, int frame_length, double fmax_hz, double rpm_step);
  ~CampbellAccumulator();
  void push(std::span<const double> x, std::span<const double> angle_deg);
  Eigen::VectorXd rpm() const;  ///< centre of each non-empty speed bin
  Eigen::VectorXd frequency_hz() const;
  Eigen::MatrixXd amplitude() const;  ///< (speed bins, frequencies), RMS

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace nvh::postproc
