#include "postproc/analyses/octave.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "postproc/analysis.hpp"
#include "postproc/cli_options.hpp"
#include "postproc/csv.hpp"
#include "postproc/levels.hpp"
#include "postproc/octave.hpp"
#include "postproc/output.hpp"
#include "postproc/signal_input.hpp"
#include "postproc/spectrum.hpp"
#include "postproc/windowing.hpp"

namespace nvh::postproc {

void run_octave(const OctaveCommand& command, const Logger& log, int argc, const char* const* argv) {
  const CommonOptions& common = command.common;
  if (command.method != "filter" && command.method != "fft")
    throw Error("octave: method '" + command.method + "': expected filter or fft");
  if (command.weighting != "Z" && command.weighting != "A")
    throw Error("octave: weighting '" + command.weighting + "': expected Z (none) or A");
  std::vector<SignalSource> sources = open_signals(common);
  check_outputs(common, sources, nullptr, "octave_");
  for (SignalSource& s : sources) apply_window(s, common.window, nullptr, 0.0, common.block, log);
  std::future<Provenance> provenance = start_provenance(sources, argc, argv);
  std::vector<TextOutput> csvs;
  double fmax = command.fmax_hz;
  if (fmax <= 0.0) {
    // Default: up to 10 kHz, but only bands whose upper edge stays below every signal's Nyquist frequency.
    fmax = 10000.0;
    const double half_band = std::pow(10.0, 0.3 / (2.0 * command.fraction));
    for (const SignalSource& s : sources)
      fmax = std::min(fmax, 0.999 * s.info().sample_rate_hz / 2.0 / half_band / std::sqrt(half_band));
  }
  const std::vector<Band> bands = fractional_octave_bands(command.fraction, command.fmin_hz, fmax);
  // Check every signal before writing anything. The Leq intervals: at least 10 samples each, and at most
  // kMaxIntervalValues (interval, band) values in all (80 MB), so --interval 1e-9 is an error, not a hang.
  constexpr double kMaxIntervalValues = 1e7;
  for (const SignalSource& s : sources) {
    OctaveFilterBank check(bands, s.info().sample_rate_hz, 0.0, s.info().address);
    if (command.interval_s <= 0 || command.method != "filter") continue;
    const double fs = s.info().sample_rate_hz, duration = static_cast<double>(s.size()) / fs;
    const double shortest =
        std::max(10.0 / fs, duration * static_cast<double>(bands.size()) / kMaxIntervalValues);
    if (!(command.interval_s >= shortest)) {
      std::ostringstream msg;
      msg << "--interval " << command.interval_s << " s: expected at least " << shortest << " s for signal '"
          << s.info().address << "' (" << duration << " s, " << fs << " Hz, " << bands.size()
          << " bands): 10 samples, and at most " << kMaxIntervalValues << " (interval, band) levels";
      throw Error(msg.str());
    }
  }
  std::vector<int> fft_lengths;
  if (command.method == "fft") {
    const double narrowest = bands.front().upper_hz - bands.front().lower_hz;
    for (const SignalSource& s : sources) {
      SpectrumOptions o;
      o.type = SpectrumType::kPsd;
      o.resolution_hz = narrowest / 4.0;  // at least 4 bins in the narrowest band
      try {
        fft_lengths.push_back(segment_length_for(o, s.info().sample_rate_hz, s.size(), s.info().address));
      } catch (const Error& e) {
        rethrow_in_window(e, common.window, s);
      }
    }
  }
  Output out = create_output(common, provenance, "octave");
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const SignalInfo& info = sources[i].info();
    std::vector<double> ms;
    Eigen::MatrixXd interval_ms;
    if (command.method == "filter") {
      OctaveFilterBank bank(bands, info.sample_rate_hz, command.interval_s, info.address);
      for_each_block(sources[i], common.block, log, "octave " + info.name,
                     [&](std::int64_t, std::span<const double> x) { bank.push(x); });
      ms = bank.mean_square();
      interval_ms = bank.interval_mean_square();
    } else {
      SpectrumOptions o;
      o.type = SpectrumType::kPsd;
      o.window = WindowKind::kHann;
      WelchAccumulator welch(info.sample_rate_hz, fft_lengths[i], o);
      for_each_block(sources[i], common.block, log, "octave " + info.name,
                     [&](std::int64_t, std::span<const double> x) { welch.push(x); });
      ms = band_mean_square_from_psd(welch.result(info.unit), bands);
    }
    const LevelReference ref =
        level_reference(quantity_for(common, info), info.unit, common.velocity_reference);
    const auto nb = static_cast<Eigen::Index>(bands.size());
    Eigen::VectorXd center(nb), lower(nb), upper(nb), nominal(nb), level(nb), weight(nb);
    for (Eigen::Index b = 0; b < nb; ++b) {
      center[b] = bands[b].center_hz;
      lower[b] = bands[b].lower_hz;
      upper[b] = bands[b].upper_hz;
      nominal[b] = bands[b].nominal_hz;
      weight[b] = command.weighting == "A" ? a_weighting_db(bands[b].center_hz) : 0.0;
      level[b] = level_db(std::sqrt(ms[b]), ref) + weight[b];
    }
    const double overall = energy_sum_db(level.data(), static_cast<int>(nb));

    h5::Group g = out.root.create_group("octave/" + info.name);
    describe_signal(g, info, common.window);
    g.write("center_hz", center);
    g.set_attribute("units", "Hz", "center_hz");
    g.set_attribute("description", "exact mid-band frequency, IEC 61260-1 base-10", "center_hz");
    g.write("lower_hz", lower);
    g.set_attribute("units", "Hz", "lower_hz");
    g.write("upper_hz", upper);
    g.set_attribute("units", "Hz", "upper_hz");
    g.write("nominal_hz", nominal);
    g.set_attribute("units", "Hz", "nominal_hz");
    g.write("level_db", level);
    write_reference(g, "level_db", ref);
    g.set_attribute("weighting", command.weighting, "level_db");
    g.write("weighting_db", weight);
    g.set_attribute("units", "dB", "weighting_db");
    g.write("overall_level_db", overall);
    write_reference(g, "overall_level_db", ref);
    g.set_attribute("description", "energy sum of the band levels", "overall_level_db");
    g.set_attribute("fraction", static_cast<std::int64_t>(command.fraction));
    g.set_attribute("method",
                    command.method == "filter"
                        ? std::string("time-domain filter bank: Butterworth order-6 band-pass per band, "
                                      "multirate (decimation by 2 per octave)")
                        : std::string("FFT band summation of a Welch PSD (Hann)"));
    g.set_attribute("weighting",
                    command.weighting == "A" ? std::string("A (IEC 61672-1)") : std::string("Z (none)"));
    if (interval_ms.rows() > 0) {
      Eigen::MatrixXd leq(interval_ms.rows(), nb);
      Eigen::VectorXd start(interval_ms.rows());
      for (Eigen::Index r = 0; r < interval_ms.rows(); ++r) {
        start[r] = info.start_time_s + static_cast<double>(r) * command.interval_s;
        for (Eigen::Index b = 0; b < nb; ++b)
          leq(r, b) = level_db(std::sqrt(interval_ms(r, b)), ref) + weight[b];
      }
      g.write("leq_db", leq);
      write_reference(g, "leq_db", ref);
      g.set_attribute("description", "equivalent level per (interval, band)", "leq_db");
      g.write("interval_start_s", start);
      g.set_attribute("units", "s", "interval_start_s");
      g.set_attribute("interval_s", command.interval_s);
    }
    std::ostringstream msg;
    msg.precision(4);
    msg << info.name << ": " << nb << " bands " << bands.front().nominal_hz << "-" << bands.back().nominal_hz
        << " Hz, overall " << overall << " " << ref.label() << (command.weighting == "A" ? " (A)" : "");
    log.info(msg.str());
    if (common.csv_dir)
      write_csv(csvs, *common.csv_dir / ("octave_" + info.name + ".csv"),
                {"nominal_hz", "center_hz", "lower_hz", "upper_hz", "level_db"},
                {&nominal, &center, &lower, &upper, &level});
  }
  commit_outputs(out, csvs);
}

namespace {

class OctaveAnalysis final : public Analysis {
 public:
  void add_options(CLI::App& o, CliShared& shared) override {
    add_common(o, command_.common, shared);
    o.add_option("--fraction", command_.fraction,
                 "b of 1/b-octave bands: 1, 3 (default), 6, 12, 24 (at most 48)")
        ->check(CLI::Range(1, 48));
    o.add_option("--fmin", command_.fmin_hz, "lowest band (nominal mid-band), Hz (default 20)")
        ->check(CLI::PositiveNumber);
    o.add_option("--fmax", command_.fmax_hz, "highest band, Hz (default: 10000 or the highest below Nyquist)")
        ->check(CLI::PositiveNumber);
    o.add_option("--method", command_.method, "filter (time-domain bank, default) or fft (band summation)")
        ->check(CLI::IsMember({"filter", "fft"}));
    o.add_option("--weighting", command_.weighting, "Z (none, default) or A (IEC 61672-1)")
        ->check(CLI::IsMember({"Z", "A"}));
    o.add_option("--interval", command_.interval_s,
                 "Leq interval for band levels over time, s (filter method)")
        ->check(CLI::NonNegativeNumber);
  }

  void run(const Logger& log, int argc, const char* const* argv) override {
    run_octave(command_, log, argc, argv);
  }

  std::filesystem::path output() const override { return command_.common.output; }

 private:
  OctaveCommand command_;
};

}  // namespace

std::unique_ptr<Analysis> make_octave_analysis() {
  return std::make_unique<OctaveAnalysis>();
}

}  // namespace nvh::postproc
