#include "postproc/stats.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <sstream>

#include "common/error.hpp"

namespace nvh::postproc {

void StatsAccumulator::push(std::span<const double> x) {
  for (double v : x) {
    sum_ += v;
    sum_squares_ += v * v;
    peak_ = std::max(peak_, std::abs(v));
  }
  count_ += static_cast<std::int64_t>(x.size());
}

double StatsAccumulator::mean() const {
  return count_ > 0 ? sum_ / static_cast<double>(count_) : 0.0;
}
double StatsAccumulator::rms() const {
  return count_ > 0 ? std::sqrt(sum_squares_ / static_cast<double>(count_)) : 0.0;
}
double StatsAccumulator::crest_factor() const {
  return rms() > 0.0 ? peak_ / rms() : 0.0;
}

double band_rms_from_psd(const Spectrum& psd, double f_low, double f_high) {
  if (psd.type != SpectrumType::kPsd) throw Error("stats: band RMS needs a PSD");
  if (!(f_high > f_low)) throw Error("stats: band RMS needs f_low < f_high");
  const double df = psd.resolution_hz;
  double sum = 0.0;
  for (Eigen::Index k = 0; k < psd.frequency_hz.size(); ++k) {
    const double lo = std::max(f_low, psd.frequency_hz[k] - df / 2.0);
    const double hi = std::min(f_high, psd.frequency_hz[k] + df / 2.0);
    if (hi > lo) sum += psd.values[k] * (hi - lo);
  }
  return std::sqrt(sum);
}

std::vector<Harmonic> harmonics(const OrderSpectra& spectra, const std::vector<double>& orders) {
  std::vector<Harmonic> out;
  const double resolution = 360.0 / spectra.cycle_deg;
  const Eigen::Index cycles = spectra.amplitude.rows();
  if (cycles == 0) throw Error("stats: no complete shaft cycle in the signal; harmonics need at least one");
  for (double order : orders) {
    const double kd = order / resolution;
    const auto k = static_cast<Eigen::Index>(std::lround(kd));
    if (std::abs(kd - static_cast<double>(k)) > 1e-9 || k < 0 || k >= spectra.order.size()) {
      std::ostringstream msg;
      msg << "stats: order " << order << " is not on the order grid (multiples of " << resolution << " up to "
          << spectra.order[spectra.order.size() - 1] << ")";
      throw Error(msg.str());
    }
    Harmonic h;
    h.order = order;
    std::complex<double> phasor = 0.0;
    double sum = 0.0, sum_squares = 0.0;
    for (Eigen::Index c = 0; c < cycles; ++c) {
      const double a = spectra.amplitude(c, k);
      sum += a;
      sum_squares += a * a;
      phasor += std::polar(1.0, spectra.phase_deg(c, k) * std::numbers::pi / 180.0);
    }
    h.amplitude = sum / static_cast<double>(cycles);
    h.amplitude_spread =
        std::sqrt(std::max(0.0, sum_squares / static_cast<double>(cycles) - h.amplitude * h.amplitude));
    h.phase_deg = std::arg(phasor) * 180.0 / std::numbers::pi;
    out.push_back(h);
  }
  return out;
}

}  // namespace nvh::postproc
