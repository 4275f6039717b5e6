#include "postproc/analyses/stats.hpp"

#include <algorithm>
#include <memory>
#include <sstream>

#include "common/error.hpp"
#include "postproc/analysis.hpp"
#include "postproc/cli_options.hpp"
#include "postproc/output.hpp"
#include "postproc/shaft_angle.hpp"
#include "postproc/signal_input.hpp"
#include "postproc/spectrum.hpp"
#include "postproc/stats.hpp"
#include "postproc/windowing.hpp"

namespace nvh::postproc {

void run_stats(const StatsCommand& command, const Logger& log, int argc, const char* const* argv) {
  const CommonOptions& common = command.common;
  std::vector<SignalSource> sources = open_signals(common);
  check_outputs(common, sources, &command.angle, "", {"stats.csv"});
  for (SignalSource& s : sources)
    apply_window(s, common.window, &command.angle, command.cycle_deg, common.block, log);
  std::future<Provenance> provenance = start_provenance(sources, argc, argv);
  struct Result {
    StatsAccumulator stats;
    double band_rms = 0.0;
    std::vector<Harmonic> harmonics;
  };
  std::vector<Result> results(sources.size());
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const SignalInfo& info = sources[i].info();
    std::unique_ptr<WelchAccumulator> welch;
    if (command.band_hz) {
      SpectrumOptions o;
      o.type = SpectrumType::kPsd;
      o.resolution_hz = command.band_resolution_hz;
      if (command.band_hz->second >= info.sample_rate_hz / 2)
        throw Error("stats: band upper limit " + std::to_string(command.band_hz->second) +
                    " Hz is at or above the Nyquist frequency of '" + info.address + "'");
      int n = 0;
      try {
        n = segment_length_for(o, info.sample_rate_hz, info.size, info.address);
      } catch (const Error& e) {
        rethrow_in_window(e, common.window, sources[i]);
      }
      welch = std::make_unique<WelchAccumulator>(info.sample_rate_hz, n, o);
    }
    std::unique_ptr<AngleProvider> angle;
    std::unique_ptr<OrderTracker> tracker;
    OrderOptions oo;
    oo.cycle_deg = command.cycle_deg;
    if (!command.harmonics.empty()) {
      const int m = samples_per_cycle_from(command.angle, sources[i], oo, common.block, log);
      const double top = *std::max_element(command.harmonics.begin(), command.harmonics.end());
      oo.max_order = std::max(top, 0.8 * 0.5 * m * 360.0 / oo.cycle_deg);
      angle = std::make_unique<AngleProvider>(command.angle, sources[i], common.block, log);
      tracker = std::make_unique<OrderTracker>(info.sample_rate_hz, oo, m);
    }
    std::vector<double> a;
    for_each_block(sources[i], common.block, log, "stats " + info.name,
                   [&](std::int64_t offset, std::span<const double> x) {
                     results[i].stats.push(x);
                     if (welch) welch->push(x);
                     if (tracker) {
                       a.resize(x.size());
                       angle->read(offset, a);
                       tracker->push(x, a);
                     }
                   });
    if (welch)
      results[i].band_rms =
          band_rms_from_psd(welch->result(info.unit), command.band_hz->first, command.band_hz->second);
    if (tracker) {
      try {
        results[i].harmonics = harmonics(tracker->result(), command.harmonics);
      } catch (const Error& e) {
        rethrow_in_window(e, common.window, sources[i]);
      }
    }
  }
  Output out = create_output(common, provenance, "stats");
  std::vector<TextOutput> csvs;
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const SignalInfo& info = sources[i].info();
    const Result& r = results[i];
    const std::string unit = info.unit.empty() ? "1" : info.unit;
    h5::Group g = out.root.create_group("stats/" + info.name);
    describe_signal(g, info, common.window);
    g.write("mean", r.stats.mean());
    g.set_attribute("units", unit, "mean");
    g.write("rms", r.stats.rms());
    g.set_attribute("units", unit, "rms");
    g.write("peak", r.stats.peak());
    g.set_attribute("units", unit, "peak");
    g.write("crest_factor", r.stats.crest_factor());
    g.set_attribute("units", "1", "crest_factor");
    std::ostringstream msg;
    msg.precision(6);
    msg << info.name << ": RMS " << r.stats.rms() << " " << unit << ", peak " << r.stats.peak()
        << ", crest factor " << r.stats.crest_factor();
    if (command.band_hz) {
      g.write("band_rms", r.band_rms);
      g.set_attribute("units", unit, "band_rms");
      g.set_attribute("band_hz", std::vector<double>{command.band_hz->first, command.band_hz->second},
                      "band_rms");
      msg << ", RMS " << command.band_hz->first << "-" << command.band_hz->second << " Hz " << r.band_rms;
    }
    if (!r.harmonics.empty()) {
      std::vector<double> order, amp, phase;
      for (const Harmonic& h : r.harmonics) {
        order.push_back(h.order);
        amp.push_back(h.amplitude);
        phase.push_back(h.phase_deg);
        msg << "\n  order " << h.order << ": amplitude " << h.amplitude << " " << unit << ", phase "
            << h.phase_deg << " deg";
      }
      g.write("harmonic_order", to_vector(order));
      g.write("harmonic_amplitude", to_vector(amp));
      g.set_attribute("units", unit, "harmonic_amplitude");
      g.set_attribute("description", "mean over the shaft cycles of the peak amplitude of each order",
                      "harmonic_amplitude");
      g.write("harmonic_phase_deg", to_vector(phase));
      g.set_attribute("units", "deg", "harmonic_phase_deg");
      g.set_attribute("description", "cosine phase re the shaft angle zero (circular mean)",
                      "harmonic_phase_deg");
    }
    log.info(msg.str());
  }
  if (common.csv_dir) {
    // The statistics table: one row per signal, the columns of the HDF5 datasets.
    TextOutput& csv = csvs.emplace_back(*common.csv_dir / "stats.csv");
    std::ostream& table = csv.stream();
    table.precision(10);
    table << "signal,unit,mean,rms,peak,crest_factor";
    if (command.band_hz) table << ",band_rms";
    for (const Harmonic& h : results.front().harmonics)
      table << ",order_" << h.order << "_amplitude,order_" << h.order << "_phase_deg";
    table << "\n";
    for (std::size_t i = 0; i < sources.size(); ++i) {
      const Result& r = results[i];
      table << sources[i].info().name << ","
            << (sources[i].info().unit.empty() ? "1" : sources[i].info().unit) << "," << r.stats.mean() << ","
            << r.stats.rms() << "," << r.stats.peak() << "," << r.stats.crest_factor();
      if (command.band_hz) table << "," << r.band_rms;
      for (const Harmonic& h : r.harmonics) table << "," << h.amplitude << "," << h.phase_deg;
      table << "\n";
    }
    csv.close();
  }
  commit_outputs(out, csvs);
}

namespace {

class StatsAnalysis final : public Analysis {
 public:
  void add_options(CLI::App& t, CliShared& shared) override {
    add_common(t, command_.common, shared);
    t.add_option("--band", band_, "band-limited RMS over LOW HIGH, Hz")->expected(2);
    t.add_option("--harmonics", command_.harmonics,
                 "orders of the running speed: amplitude and phase (needs the angle)")
        ->delimiter(',');
    t.add_option("--cycle", command_.cycle_deg, "cycle for the harmonics, deg (default 360: whole orders)")
        ->check(CLI::PositiveNumber);
    add_angle(t, command_.angle);
    add_skip_cycles(t, command_.common);
  }

  void run(const Logger& log, int argc, const char* const* argv) override {
    if (band_.size() == 2) command_.band_hz = std::make_pair(band_[0], band_[1]);
    run_stats(command_, log, argc, argv);
  }

  std::filesystem::path output() const override { return command_.common.output; }

 private:
  StatsCommand command_;
  std::vector<double> band_;
};

}  // namespace

std::unique_ptr<Analysis> make_stats_analysis() {
  return std::make_unique<StatsAnalysis>();
}

}  // namespace nvh::postproc
