#include "postproc/shaft_angle.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "postproc/signal_input.hpp"

namespace nvh::postproc {

/// Samples per cycle: --samples-per-cycle, or from the highest speed of the angle signal (one streamed pass,
/// made in both cases: it also gives the cycles the signal spans). Checked before any plan or allocation: the
/// angle-domain signal, cycles x M samples, may be at most kMaxResampling times the signal's N samples (more
/// resolves nothing the signal holds, and --cycle 0.01 or --samples-per-cycle 1e6 ran without bound), and M
/// at most kMaxResampling N and kMaxSamplesPerCycle (docs/cli.md, postproc).
int samples_per_cycle_from(const AngleSource& angle, const SignalSource& signal, const OrderOptions& options,
                           std::int64_t block, const Logger& log) {
  constexpr double kMaxResampling = 16;
  AngleProvider provider(angle, signal, block, log);
  const double fs = signal.info().sample_rate_hz;
  double max_speed = 0.0, last = 0.0, first = 0.0;
  std::vector<double> a;
  for (std::int64_t offset = 0; offset < signal.size(); offset += block) {
    a.resize(static_cast<std::size_t>(std::min(block, signal.size() - offset)));
    provider.read(offset, a);
    if (offset == 0) first = a[0];
    // Sample-to-sample speed; noise only raises M (more angle samples), never loses orders.
    for (std::size_t i = 0; i < a.size(); ++i) {
      const double previous = (offset == 0 && i == 0) ? a[0] : (i == 0 ? last : a[i - 1]);
      max_speed = std::max(max_speed, (a[i] - previous) * fs / 360.0);
    }
    last = a.back();
  }
  if (!(max_speed > 0.0)) throw Error("orders: the shaft does not turn in '" + signal.info().address + "'");
  const bool given = options.samples_per_cycle > 0;
  const int m =
      given ? options.samples_per_cycle : choose_samples_per_cycle(fs, max_speed, options.cycle_deg);
  const double n = static_cast<double>(signal.size());
  const double cycles = (last - first) / options.cycle_deg;
  const double resampled = cycles * m;
  std::ostringstream msg;
  msg.precision(6);
  if (given && (m > kMaxSamplesPerCycle || m > kMaxResampling * n)) {
    msg << "--samples-per-cycle " << m << ": more than "
        << std::min<double>(kMaxSamplesPerCycle, kMaxResampling * n) << " (the smaller of "
        << kMaxSamplesPerCycle << " and " << kMaxResampling << " x the " << n << " samples of '"
        << signal.info().address << "')";
    throw Error(msg.str());
  }
  if (resampled > kMaxResampling * n) {
    msg << (given ? "--samples-per-cycle " + std::to_string(m) + " with " : std::string()) << "--cycle "
        << options.cycle_deg << " deg: signal '" << signal.info().address << "' spans " << cycles
        << " cycles, resampled to " << resampled << " angle samples, more than " << kMaxResampling
        << " x its " << n << " samples; expected "
        << (given ? "at most " + std::to_string(static_cast<long long>(kMaxResampling * n / cycles)) +
                        " samples per cycle or a longer cycle"
                  : "a cycle of at least " +
                        std::to_string(options.cycle_deg * resampled / (kMaxResampling * n)) + " deg");
    throw Error(msg.str());
  }
  return m;
}

}  // namespace nvh::postproc
