#include "postproc/orders.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>

#include "common/error.hpp"
#include "postproc/spectrum.hpp"
#include "postproc/window.hpp"

namespace nvh::postproc {
namespace {

constexpr int kHalfWidth = 16;          // L: sinc kernel half-width, input samples (at beta = 1)
constexpr double kKaiserBeta = 8.0;     // Kaiser window shape (about -80 dB side lobes)
constexpr int kTablePerUnit = 1024;     // kernel table resolution (linear interpolation between entries)
constexpr double kMinBeta = 1.0 / 8.0;  // lowest cut-off factor (speeds below f_s/(8 M) per cycle alias)
constexpr std::int64_t kReach = static_cast<std::int64_t>(kHalfWidth / kMinBeta) + 3;

// Modified Bessel function I0 by its power series (converges fast for the arguments used, <= 8).
double bessel_i0(double x) {
  double sum = 1.0, term = 1.0;
  for (int k = 1; k < 60; ++k) {
    term *= (x / (2.0 * k)) * (x / (2.0 * k));
    sum += term;
    if (term < 1e-17 * sum) break;
  }
  return sum;
}

std::vector<double> kernel_table() {
  std::vector<double> t(kHalfWidth * kTablePerUnit + 2, 0.0);
  const double norm = bessel_i0(kKaiserBeta);
  for (std::size_t i = 0; i + 1 < t.size(); ++i) {
    const double u = static_cast<double>(i) / kTablePerUnit;
    const double r = u / kHalfWidth;
    const double window = r < 1.0 ? bessel_i0(kKaiserBeta * std::sqrt(1.0 - r * r)) / norm : 0.0;
    const double sinc = u == 0.0 ? 1.0 : std::sin(std::numbers::pi * u) / (std::numbers::pi * u);
    t[i] = sinc * window;
  }
  return t;
}

// Cubic Hermite on [0, 1] with end values y0, y1 and slopes m0, m1 (per unit of u).
double hermite(double y0, double y1, double m0, double m1, double u) {
  const double u2 = u * u, u3 = u2 * u;
  return (2 * u3 - 3 * u2 + 1) * y0 + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * y1 + (u3 - u2) * m1;
}
double hermite_slope(double y0, double y1, double m0, double m1, double u) {
  const double u2 = u * u;
  return (6 * u2 - 6 * u) * y0 + (3 * u2 - 4 * u + 1) * m0 + (-6 * u2 + 6 * u) * y1 + (3 * u2 - 2 * u) * m1;
}

// sum_m x[m] h(|u0 - m beta|) over m = 0..count-1, h from the table (linear interpolation, zero beyond L).
// The hot loop of the resampler; compiled twice (AVX2/FMA and baseline) and chosen at load time.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("arch=x86-64-v3", "default")))
#endif
double
kernel_sum(const double* x, int count, double u0, double beta, const double* table) {
  double sum = 0.0;
  for (int m = 0; m < count; ++m) {
    const double u = std::min(std::abs(u0 - m * beta), static_cast<double>(kHalfWidth));  // table ends in 0
    const double s = u * kTablePerUnit;
    const int i = static_cast<int>(s);
    const double f = s - static_cast<double>(i);
    sum += x[m] * (table[i] + f * (table[i + 1] - table[i]));
  }
  return sum;
}

}  // namespace

int choose_samples_per_cycle(double fs, double max_rev_per_s, double cycle_deg) {
  const double cycle_s = cycle_deg / 360.0 / max_rev_per_s;
  int m = 16;
  while (m < fs * cycle_s && m < (1 << 24)) m *= 2;
  return m;
}

// ---------------------------------------------------------------------------------------------

struct OrderTracker::Impl {
  double fs;
  OrderOptions options;
  int m;          // samples per cycle
  double dtheta;  // deg between angle samples
  std::vector<double> table = kernel_table();
  FftPlan plan;
  int max_k;  // highest order bin reported

  // Buffer of recent samples: x[i], th[i] are absolute sample base + i.
  std::vector<double> x, th;
  std::int64_t base = 0;
  std::int64_t pos = 0;  // absolute index with th[pos] <= next target (search hint)
  bool started = false;
  double next_theta = 0.0;

  std::vector<double> cycle;
  double cycle_start_t = 0.0;
  double cycle_start_theta = 0.0;
  // A completed cycle waits for the time of the next cycle's start to know its speed.
  bool pending = false;
  std::vector<double> pending_amp, pending_phase;
  double pending_start_t = 0.0;
  double pending_last_t = 0.0;  // time of the cycle's last angle sample

  std::vector<std::vector<double>> amp_rows, phase_rows;
  std::vector<double> rpm, start_t;

  Impl(double fs_, const OrderOptions& o, int m_)
      : fs(fs_), options(o), m(m_), dtheta(o.cycle_deg / m_), plan(m_) {
    const double nyquist_order = 0.5 * m * 360.0 / options.cycle_deg;
    const double max_order = options.max_order > 0.0 ? options.max_order : 0.8 * nyquist_order;
    // In double before the cast: a --max-order of 1e308 would overflow an int (undefined behaviour).
    max_k = static_cast<int>(
        std::min(static_cast<double>(m / 2 - 1), std::floor(max_order * options.cycle_deg / 360.0 + 1e-9)));
  }

  double at(std::int64_t i) const { return x[static_cast<std::size_t>(i - base)]; }
  double angle(std::int64_t i) const { return th[static_cast<std::size_t>(i - base)]; }
  std::int64_t end() const { return base + static_cast<std::int64_t>(x.size()); }

  double sinc_value(double p, double beta) const {
    const auto center = static_cast<std::int64_t>(std::floor(p));
    const auto reach = static_cast<std::int64_t>(std::ceil(kHalfWidth / beta));
    const std::int64_t first = center - reach + 1;
    return beta * kernel_sum(&x[static_cast<std::size_t>(first - base)], static_cast<int>(2 * reach),
                             (p - static_cast<double>(first)) * beta, beta, table.data());
  }

  void finish_cycle() {
    double* in = plan.input();
    std::copy(cycle.begin(), cycle.end(), in);
    plan.execute();
    const std::complex<double>* X = plan.output();
    pending_amp.assign(max_k + 1, 0.0);
    pending_phase.assign(max_k + 1, 0.0);
    for (int k = 0; k <= max_k; ++k) {
      pending_amp[k] = std::abs(X[k]) * (k == 0 ? 1.0 : 2.0) / m;
      pending_phase[k] = std::arg(X[k]) * 180.0 / std::numbers::pi;
    }
    pending = true;
    pending_start_t = cycle_start_t;
    cycle.clear();
  }

  void close_pending(double end_t) {
    if (!pending) return;
    amp_rows.push_back(pending_amp);
    phase_rows.push_back(pending_phase);
    start_t.push_back(pending_start_t);
    rpm.push_back(60.0 * (options.cycle_deg / 360.0) / (end_t - pending_start_t));
    pending = false;
  }

  void run() {
    if (!started) {
      if (end() - base < kReach + 2) return;
      const double first = angle(base + kReach);
      next_theta = std::ceil(first / options.cycle_deg) * options.cycle_deg;
      pos = base + kReach;
      started = true;
    }
    while (true) {
      // Find i with th[i] <= target < th[i+1], leaving room for the kernel and the Hermite neighbours.
      std::int64_t i = pos;
      while (i + 1 < end() && angle(i + 1) <= next_theta) ++i;
      if (i + kReach + 2 >= end()) {
        pos = i;
        break;
      }
      const double y0 = angle(i), y1 = angle(i + 1);
      const double m0 = 0.5 * (y1 - angle(i - 1)), m1 = 0.5 * (angle(i + 2) - y0);
      double u = (next_theta - y0) / (y1 - y0);
      for (int it = 0; it < 6; ++it) {  // Newton; converges in 2-3 steps from the linear guess
        const double slope = hermite_slope(y0, y1, m0, m1, u);
        if (slope <= 0.0) break;
        const double step = (hermite(y0, y1, m0, m1, u) - next_theta) / slope;
        u = std::clamp(u - step, 0.0, 1.0);
        if (std::abs(step) < 1e-13) break;
      }
      const double p = static_cast<double>(i) + u;
      const double t = p / fs;
      const double speed = std::max(1e-300, hermite_slope(y0, y1, m0, m1, u) * fs);  // deg/s
      double value;
      if (options.interpolation == Interpolation::kLinear) {
        value = at(i) + u * (at(i + 1) - at(i));
      } else {
        const double rate = speed * m / options.cycle_deg;  // angle samples per second
        value = sinc_value(p, std::clamp(rate / fs, kMinBeta, 1.0));
      }
      if (cycle.empty()) {
        close_pending(t);
        cycle_start_t = t;
        cycle_start_theta = next_theta;
      }
      cycle.push_back(value);
      if (static_cast<int>(cycle.size()) == m) {
        pending_last_t = t;
        finish_cycle();
        next_theta = cycle_start_theta + options.cycle_deg;
      } else {
        next_theta = cycle_start_theta + static_cast<double>(cycle.size()) * dtheta;
      }
      pos = i;
    }
    // Drop samples the kernel can no longer reach.
    const std::int64_t keep_from = pos - kReach - 2;
    if (keep_from - base > (1 << 16)) {
      const auto drop = static_cast<std::size_t>(keep_from - base);
      x.erase(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(drop));
      th.erase(th.begin(), th.begin() + static_cast<std::ptrdiff_t>(drop));
      base = keep_from;
    }
  }
};

namespace {
// Checked before the FFT plan is made (FFTW aborted on 2^31 - 1 points, the plan was made before this check).
int checked_samples_per_cycle(double fs, const OrderOptions& options, int m) {
  if (m < 8 || m > kMaxSamplesPerCycle)
    throw Error("orders: --samples-per-cycle " + std::to_string(m) + ": expected 8 to " +
                std::to_string(kMaxSamplesPerCycle));
  if (!(std::isfinite(options.cycle_deg) && options.cycle_deg > 0))
    throw Error("orders: the cycle must be a finite angle > 0 deg");
  if (!(std::isfinite(fs) && fs > 0)) throw Error("orders: the sample rate must be finite and > 0 Hz");
  return m;
}
}  // namespace

OrderTracker::OrderTracker(double fs, const OrderOptions& options, int samples_per_cycle)
    : impl_(std::make_unique<Impl>(fs, options, checked_samples_per_cycle(fs, options, samples_per_cycle))) {}

OrderTracker::~OrderTracker() = default;

void OrderTracker::push(std::span<const double> x, std::span<const double> angle_deg) {
  if (x.size() != angle_deg.size()) throw Error("orders: signal and angle blocks differ in length");
  Impl& d = *impl_;
  const std::int64_t first = d.end();
  for (std::size_t i = 0; i < angle_deg.size(); ++i) {
    const double previous = i > 0 ? angle_deg[i - 1] : (d.th.empty() ? angle_deg[0] : d.th.back());
    if (angle_deg[i] < previous) {
      std::ostringstream msg;
      msg << "orders: the shaft angle decreases at sample " << first + static_cast<std::int64_t>(i) << " ("
          << previous << " -> " << angle_deg[i]
          << " deg); expected an unwrapped, increasing angle (a crank angle in deg, not modulo 720)";
      throw Error(msg.str());
    }
  }
  d.x.insert(d.x.end(), x.begin(), x.end());
  d.th.insert(d.th.end(), angle_deg.begin(), angle_deg.end());
  d.run();
}

OrderSpectra OrderTracker::result() const {
  const Impl& d = *impl_;
  std::vector<std::vector<double>> amp = d.amp_rows, phase = d.phase_rows;
  std::vector<double> rpm = d.rpm, start = d.start_t;
  if (d.pending) {
    // The last complete cycle (the signal ends before the next one starts): its speed from the time between
    // its first and last angle samples, (M - 1) dtheta apart.
    amp.push_back(d.pending_amp);
    phase.push_back(d.pending_phase);
    start.push_back(d.pending_start_t);
    rpm.push_back(60.0 * (d.m - 1) * d.dtheta / 360.0 / (d.pending_last_t - d.pending_start_t));
  }
  OrderSpectra s;
  s.cycle_deg = d.options.cycle_deg;
  s.samples_per_cycle = d.m;
  const auto cycles = static_cast<Eigen::Index>(amp.size());
  const Eigen::Index orders = d.max_k + 1;
  s.order.resize(orders);
  for (Eigen::Index k = 0; k < orders; ++k) s.order[k] = static_cast<double>(k) * 360.0 / d.options.cycle_deg;
  s.amplitude.resize(cycles, orders);
  s.phase_deg.resize(cycles, orders);
  s.rpm.resize(cycles);
  s.start_time_s.resize(cycles);
  for (Eigen::Index c = 0; c < cycles; ++c) {
    for (Eigen::Index k = 0; k < orders; ++k) {
      s.amplitude(c, k) = amp[c][k];
      s.phase_deg(c, k) = phase[c][k];
    }
    s.rpm[c] = rpm[c];
    s.start_time_s[c] = start[c];
  }
  return s;
}

OrderSpectra order_spectra(std::span<const double> x, std::span<const double> angle_deg, double fs,
                           const OrderOptions& options) {
  if (x.size() != angle_deg.size()) throw Error("orders: signal and angle differ in length");
  if (x.size() < 4) throw Error("orders: signal too short");
  int m = options.samples_per_cycle;
  if (m <= 0) {
    double max_speed = 0.0;  // rev/s
    for (std::size_t i = 1; i < angle_deg.size(); ++i)
      max_speed = std::max(max_speed, (angle_deg[i] - angle_deg[i - 1]) * fs / 360.0);
    m = choose_samples_per_cycle(fs, max_speed, options.cycle_deg);
  }
  OrderTracker tracker(fs, options, m);
  tracker.push(x, angle_deg);
  return tracker.result();
}

// ---------------------------------------------------------------------------------------------

void SpeedIntegrator::angle(std::span<const double> rpm, std::span<double> angle_deg) {
  for (std::size_t i = 0; i < rpm.size(); ++i) {
    if (started_) theta_ += 3.0 * dt_ * (last_rpm_ + rpm[i]);  // 6 deg/s per rpm, trapezoid
    started_ = true;
    last_rpm_ = rpm[i];
    angle_deg[i] = theta_;
  }
}

TachoAngle::TachoAngle(double fs, int pulses_per_rev, double threshold)
    : fs_(fs), step_deg_(360.0 / pulses_per_rev), threshold_(threshold) {
  if (pulses_per_rev < 1) throw Error("orders: pulses per revolution must be >= 1");
}

void TachoAngle::push_pulses(std::span<const double> tacho) {
  for (double v : tacho) {
    if (seen_ > 0 && last_ < threshold_ && v >= threshold_)
      times_.push_back((static_cast<double>(seen_ - 1) + (threshold_ - last_) / (v - last_)) / fs_);
    last_ = v;
    ++seen_;
  }
}

void TachoAngle::angle(std::int64_t offset, std::span<double> out) const {
  const std::size_t n = times_.size();
  if (n < 3)
    throw Error("orders: the tacho signal has " + std::to_string(n) + " pulses above the threshold " +
                std::to_string(threshold_) + "; at least 3 are needed");
  auto slope = [&](std::size_t j) {  // deg/s at pulse j (central difference; one-sided at the ends)
    if (j == 0) return step_deg_ / (times_[1] - times_[0]);
    if (j + 1 == n) return step_deg_ / (times_[n - 1] - times_[n - 2]);
    return 2.0 * step_deg_ / (times_[j + 1] - times_[j - 1]);
  };
  std::size_t j = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double t = static_cast<double>(offset + static_cast<std::int64_t>(i)) / fs_;
    if (t <= times_.front()) {
      out[i] = (t - times_.front()) * slope(0);
      continue;
    }
    if (t >= times_.back()) {
      out[i] = static_cast<double>(n - 1) * step_deg_ + (t - times_.back()) * slope(n - 1);
      continue;
    }
    if (j >= n - 1 || times_[j] > t)
      j = static_cast<std::size_t>(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin()) - 1;
    while (times_[j + 1] <= t) ++j;
    const double h = times_[j + 1] - times_[j];
    const double u = (t - times_[j]) / h;
    out[i] = hermite(static_cast<double>(j) * step_deg_, static_cast<double>(j + 1) * step_deg_, slope(j) * h,
                     slope(j + 1) * h, u);
  }
}

// ---------------------------------------------------------------------------------------------

struct CampbellAccumulator::Impl {
  double fs;
  int n;
  int bins;
  double rpm_step;
  Window window;
  FftPlan plan;
  std::vector<double> x, th;
  std::map<long, std::pair<std::vector<double>, int>> by_speed;  // speed bin -> (power sum, frames)
  Impl(double fs_, int n_, double fmax, double step)
      : fs(fs_),
        n(n_),
        bins(std::min(n_ / 2 + 1, static_cast<int>(std::floor(fmax * n_ / fs_)) + 1)),
        rpm_step(step),
        window(make_window(WindowKind::kHann, n_)),
        plan(n_) {}
};

CampbellAccumulator::CampbellAccumulator(double fs, int frame_length, double fmax_hz, double rpm_step)
    : impl_(std::make_unique<Impl>(fs, frame_length, fmax_hz, rpm_step)) {}
CampbellAccumulator::~CampbellAccumulator() = default;

void CampbellAccumulator::push(std::span<const double> x, std::span<const double> angle_deg) {
  Impl& d = *impl_;
  d.x.insert(d.x.end(), x.begin(), x.end());
  d.th.insert(d.th.end(), angle_deg.begin(), angle_deg.end());
  const std::size_t hop = static_cast<std::size_t>(d.n / 2);
  std::size_t start = 0;
  while (start + static_cast<std::size_t>(d.n) <= d.x.size()) {
    double* in = d.plan.input();
    for (int i = 0; i < d.n; ++i) in[i] = d.window.w[i] * d.x[start + i];
    d.plan.execute();
    const double speed_rpm = (d.th[start + d.n - 1] - d.th[start]) / (d.n - 1) * d.fs / 6.0;
    auto& [sum, frames] = d.by_speed[std::lround(speed_rpm / d.rpm_step)];
    if (sum.empty()) sum.assign(d.bins, 0.0);
    for (int k = 0; k < d.bins; ++k) sum[k] += std::norm(d.plan.output()[k]);
    ++frames;
    start += hop;
  }
  d.x.erase(d.x.begin(), d.x.begin() + static_cast<std::ptrdiff_t>(start));
  d.th.erase(d.th.begin(), d.th.begin() + static_cast<std::ptrdiff_t>(start));
}

Eigen::VectorXd CampbellAccumulator::rpm() const {
  Eigen::VectorXd r(static_cast<Eigen::Index>(impl_->by_speed.size()));
  Eigen::Index i = 0;
  for (const auto& [bin, data] : impl_->by_speed) r[i++] = static_cast<double>(bin) * impl_->rpm_step;
  return r;
}

Eigen::VectorXd CampbellAccumulator::frequency_hz() const {
  Eigen::VectorXd f(impl_->bins);
  for (int k = 0; k < impl_->bins; ++k) f[k] = impl_->fs * k / impl_->n;
  return f;
}

Eigen::MatrixXd CampbellAccumulator::amplitude() const {
  const Impl& d = *impl_;
  Eigen::MatrixXd a(static_cast<Eigen::Index>(d.by_speed.size()), d.bins);
  Eigen::Index i = 0;
  for (const auto& [bin, data] : d.by_speed) {
    for (int k = 0; k < d.bins; ++k) {
      const double c = (k == 0) ? 1.0 : 2.0;
      a(i, k) = std::sqrt(c * data.first[k] / data.second) / d.window.sum;  // RMS, amplitude-correct
    }
    ++i;
  }
  return a;
}

}  // namespace nvh::postproc
