#pragma once
// The shaft angle at a signal's samples for order tracking and harmonics (docs/postproc.md section 4.3): an
// angle signal (deg, unwrapped), a speed (rpm, integrated) or a tacho (pulses); and the angle-domain sampling
// it implies.
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/log.hpp"
#include "postproc/options.hpp"
#include "postproc/orders.hpp"
#include "postproc/signal.hpp"
#include "postproc/signal_input.hpp"

namespace nvh::postproc {

class AngleProvider {
 public:
  /// The angle at the samples of `signal` (inside its analysis window, if restricted): always the angle of
  /// the whole file, so that a window does not move the angle zero of a speed or tacho source.
  AngleProvider(const AngleSource& angle, const SignalSource& signal, std::int64_t block, const Logger& log) {
    const SignalInfo& info = signal.info();
    std::string address = angle.address;
    if (!address.empty() && address[0] == '/') address = info.file.string() + ":" + address;
    source_ = std::make_unique<SignalSource>(SignalSource::open(address));
    const SignalInfo& a = source_->info();
    if (a.size != signal.file_size() ||
        std::abs(a.sample_rate_hz - info.sample_rate_hz) > 1e-9 * info.sample_rate_hz) {
      std::ostringstream msg;
      msg << "orders: the " << angle.kind << " signal '" << a.address << "' (" << a.size << " samples at "
          << a.sample_rate_hz << " Hz) does not match signal '" << info.address << "' (" << signal.file_size()
          << " samples at " << info.sample_rate_hz << " Hz); they must be sampled together";
      throw Error(msg.str());
    }
    kind_ = angle.kind;
    first_ = signal.first_sample();
    if (kind_ == "speed") {
      speed_ = std::make_unique<SpeedIntegrator>(a.sample_rate_hz);
      if (first_ > 0) {  // integrate up to the window: theta(0) = 0 at the file's first sample
        source_->restrict_to(0, first_);
        std::vector<double> out;
        for_each_block(*source_, block, log, "speed before the window",
                       [&](std::int64_t, std::span<const double> rpm) {
                         out.resize(rpm.size());
                         speed_->angle(rpm, out);
                       });
      }
    } else if (kind_ == "tacho") {
      tacho_ = std::make_unique<TachoAngle>(a.sample_rate_hz, angle.pulses_per_rev, angle.threshold);
      for_each_block(*source_, block, log, "tacho pulses",
                     [&](std::int64_t, std::span<const double> x) { tacho_->push_pulses(x); });
    } else if (kind_ != "angle") {
      throw Error("orders: angle source '" + kind_ + "': expected angle, speed or tacho");
    }
    if (kind_ != "tacho") source_->restrict_to(first_, info.size);
  }

  /// Angle (deg) at samples [offset, offset + out.size()) of the signal; called with consecutive ranges.
  void read(std::int64_t offset, std::span<double> out) {
    if (kind_ == "tacho") {
      tacho_->angle(first_ + offset, out);
      return;
    }
    source_->read(offset, out);
    if (kind_ == "speed") {
      buffer_.assign(out.begin(), out.end());
      speed_->angle(buffer_, out);
    }
  }

 private:
  std::string kind_;
  std::int64_t first_ = 0;
  std::unique_ptr<SignalSource> source_;
  std::unique_ptr<SpeedIntegrator> speed_;
  std::unique_ptr<TachoAngle> tacho_;
  std::vector<double> buffer_;
};

/// Samples per cycle: --samples-per-cycle, or from the highest speed of the angle signal (one streamed pass,
/// made in both cases: it also gives the cycles the signal spans), with the limits of docs/cli.md (postproc).
int samples_per_cycle_from(const AngleSource& angle, const SignalSource& signal, const OrderOptions& options,
                           std::int64_t block, const Logger& log);

}  // namespace nvh::postproc
