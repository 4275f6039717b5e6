#include "postproc/spectrum.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "common/error.hpp"

namespace nvh::postproc {

SpectrumType parse_spectrum_type(const std::string& name) {
  if (name == "amplitude" || name == "peak") return SpectrumType::kAmplitude;
  if (name == "rms") return SpectrumType::kRms;
  if (name == "psd") return SpectrumType::kPsd;
  throw Error("spectrum type '" + name + "': expected amplitude, rms or psd");
}

std::string to_string(SpectrumType type) {
  switch (type) {
    case SpectrumType::kAmplitude:
      return "amplitude";
    case SpectrumType::kRms:
      return "rms";
    case SpectrumType::kPsd:
      return "psd";
  }
  return "?";
}

Scaling parse_scaling(const std::string& name) {
  if (name == "amplitude") return Scaling::kAmplitude;
  if (name == "energy") return Scaling::kEnergy;
  throw Error("scaling '" + name + "': expected amplitude (sines read their amplitude) or energy (Parseval)");
}

std::string to_string(Scaling scaling) {
  return scaling == Scaling::kAmplitude ? "amplitude" : "energy";
}

int segment_length_for(const SpectrumOptions& options, double fs, std::int64_t signal_size,
                       const std::string& signal_name) {
  int n = options.segment_length;
  if (n <= 0) {
    if (!(options.resolution_hz > 0.0)) throw Error("spectrum: the resolution must be > 0 Hz");
    n = 1;
    while (static_cast<double>(n) < fs / options.resolution_hz - 1e-9 && n < (1 << 30)) n *= 2;
  }
  if (n < 2) {
    std::ostringstream msg;
    if (options.segment_length > 0) {
      msg << "--segment " << n << ": a segment needs at least 2 samples";
    } else {
      msg << "--resolution " << options.resolution_hz << " Hz is coarser than the sample rate allows: at most "
          << fs / 2 << " Hz (half the sample rate " << fs << " Hz of signal '" << signal_name << "')";
    }
    throw Error(msg.str());
  }
  if (n > signal_size) {
    std::ostringstream msg;
    msg << "signal '" << signal_name << "': " << signal_size << " samples (" << signal_size / fs
        << " s) are too short for the asked resolution: one segment needs " << n << " samples (" << n / fs
        << " s, resolution " << fs / n << " Hz); ask for a coarser resolution";
    throw Error(msg.str());
  }
  if (!(options.overlap >= 0.0 && options.overlap < 1.0))
    throw Error("spectrum: overlap must be in [0, 1), got " + std::to_string(options.overlap));
  return n;
}

// ---------------------------------------------------------------------------------------------

FftPlan::FftPlan(int n) : n_(n) {
  in_ = fftw_alloc_real(n);
  out_ = reinterpret_cast<std::complex<double>*>(fftw_alloc_complex(n / 2 + 1));
  // FFTW_ESTIMATE: no timing runs (a plan per signal is cheap; the transform dominates anyway).
  plan_ = fftw_plan_dft_r2c_1d(n, in_, reinterpret_cast<fftw_complex*>(out_), FFTW_ESTIMATE);
  if (plan_ == nullptr) throw Error("FFTW: cannot make a plan of size " + std::to_string(n));
}

FftPlan::~FftPlan() {
  fftw_destroy_plan(static_cast<fftw_plan>(plan_));
  fftw_free(in_);
  fftw_free(out_);
}

void FftPlan::execute() {
  fftw_execute(static_cast<fftw_plan>(plan_));
}

// ---------------------------------------------------------------------------------------------

WelchAccumulator::WelchAccumulator(double fs, int n, const SpectrumOptions& options)
    : fs_(fs),
      options_(options),
      window_(make_window(options.window, n)),
      plan_(n),
      hop_(std::max(1, static_cast<int>(std::lround(n * (1.0 - options.overlap))))),
      power_sum_(n / 2 + 1, 0.0) {}

void WelchAccumulator::process_segment(const double* segment) {
  const int n = plan_.size();
  double* in = plan_.input();
  const double* w = window_.w.data();
  for (int i = 0; i < n; ++i) in[i] = w[i] * segment[i];
  plan_.execute();
  const std::complex<double>* X = plan_.output();
  for (std::size_t k = 0; k < power_sum_.size(); ++k) power_sum_[k] += std::norm(X[k]);
  ++averages_;
}

void WelchAccumulator::push(std::span<const double> samples) {
  const std::size_t n = static_cast<std::size_t>(plan_.size());
  // Append, transform every complete segment, keep the tail that a later segment starts in.
  pending_.insert(pending_.end(), samples.begin(), samples.end());
  while (pending_.size() - pending_start_ >= n) {
    process_segment(pending_.data() + pending_start_);
    pending_start_ += static_cast<std::size_t>(hop_);
  }
  if (pending_start_ > 0) {
    const std::size_t keep_from = std::min(pending_start_, pending_.size());
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(keep_from));
    pending_start_ -= keep_from;
  }
}

Spectrum WelchAccumulator::result(const std::string& unit) const {
  const int n = plan_.size();
  const std::size_t bins = power_sum_.size();
  Spectrum s;
  s.type = options_.type;
  s.scaling = options_.scaling;
  s.window = options_.window;
  s.segment_length = n;
  s.overlap = 1.0 - static_cast<double>(hop_) / n;
  s.averages = averages_;
  s.resolution_hz = fs_ / n;
  s.enbw_hz = window_.nenbw_bins() * fs_ / n;
  s.derivative = options_.derivative;
  s.frequency_hz.resize(static_cast<Eigen::Index>(bins));
  s.values.resize(static_cast<Eigen::Index>(bins));
  const double m = averages_ > 0 ? static_cast<double>(averages_) : 1.0;
  const std::string d_unit = derived_unit(unit, options_.derivative);
  for (std::size_t k = 0; k < bins; ++k) {
    const double f = fs_ * static_cast<double>(k) / n;
    const bool edge = k == 0 || (n % 2 == 0 && k == bins - 1);
    const double c = edge ? 1.0 : 2.0;
    const double mean_power = power_sum_[k] / m;
    double value = 0.0;
    if (options_.type == SpectrumType::kPsd) {
      value = c * mean_power / (fs_ * window_.sum_squares);
    } else {
      const double rms = options_.scaling == Scaling::kAmplitude
                             ? std::sqrt(c * mean_power) / window_.sum
                             : std::sqrt(c * mean_power / (n * window_.sum_squares));
      value = options_.type == SpectrumType::kAmplitude && !edge ? std::sqrt(2.0) * rms : rms;
    }
    if (options_.derivative != 0) {
      const double omega = 2.0 * std::numbers::pi * f;
      const double factor = (k == 0 && options_.derivative < 0) ? 0.0 : std::pow(omega, options_.derivative);
      value *= options_.type == SpectrumType::kPsd ? factor * factor : factor;
    }
    s.frequency_hz[static_cast<Eigen::Index>(k)] = f;
    s.values[static_cast<Eigen::Index>(k)] = value;
  }
  s.unit = options_.type == SpectrumType::kPsd ? "(" + d_unit + ")^2/Hz" : d_unit;
  return s;
}

Spectrum welch_spectrum(std::span<const double> samples, double fs, const SpectrumOptions& options,
                        const std::string& unit) {
  const int n = segment_length_for(options, fs, static_cast<std::int64_t>(samples.size()), "in memory");
  WelchAccumulator welch(fs, n, options);
  welch.push(samples);
  return welch.result(unit);
}

std::string derived_unit(const std::string& unit, int derivative) {
  if (derivative == 0) return unit;
  const std::vector<std::string> chain = {"m", "m/s", "m/s^2", "m/s^3"};
  for (int i = 0; i < static_cast<int>(chain.size()); ++i) {
    if (chain[i] == unit) {
      const int j = i + derivative;
      if (j >= 0 && j < static_cast<int>(chain.size())) return chain[j];
    }
  }
  return (unit.empty() ? "1" : unit) + "*s^" + std::to_string(-derivative);
}

}  // namespace nvh::postproc
