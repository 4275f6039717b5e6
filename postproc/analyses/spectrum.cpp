#include "postproc/analyses/spectrum.hpp"

#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "postproc/analysis.hpp"
#include "postproc/cli_options.hpp"
#include "postproc/csv.hpp"
#include "postproc/levels.hpp"
#include "postproc/output.hpp"
#include "postproc/signal_input.hpp"
#include "postproc/windowing.hpp"

namespace nvh::postproc {

void run_spectrum(const SpectrumCommand& command, const Logger& log, int argc, const char* const* argv) {
  const CommonOptions& common = command.common;
  std::vector<SignalSource> sources = open_signals(common);
  check_outputs(common, sources, nullptr, "spectrum_");
  for (SignalSource& s : sources) apply_window(s, common.window, nullptr, 0.0, common.block, log);
  std::future<Provenance> provenance = start_provenance(sources, argc, argv);
  std::vector<TextOutput> csvs;
  std::vector<int> lengths;
  for (const SignalSource& s : sources) {
    try {
      lengths.push_back(
          segment_length_for(command.options, s.info().sample_rate_hz, s.size(), s.info().address));
    } catch (const Error& e) {
      rethrow_in_window(e, common.window, s);
    }
  }
  Output out = create_output(common, provenance, "spectrum");
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const SignalInfo& info = sources[i].info();
    WelchAccumulator welch(info.sample_rate_hz, lengths[i], command.options);
    for_each_block(sources[i], common.block, log, "spectrum " + info.name,
                   [&](std::int64_t, std::span<const double> x) { welch.push(x); });
    Spectrum s = welch.result(info.unit);
    Eigen::Index bins = s.frequency_hz.size();
    if (command.fmax_hz > 0.0)
      while (bins > 1 && s.frequency_hz[bins - 1] > command.fmax_hz) --bins;
    const Eigen::VectorXd f = s.frequency_hz.head(bins), values = s.values.head(bins);
    const LevelReference ref =
        level_reference(quantity_for(common, info, s.derivative), s.unit, common.velocity_reference);
    const bool psd = s.type == SpectrumType::kPsd;
    Eigen::VectorXd level(bins);
    for (Eigen::Index k = 0; k < bins; ++k) {
      const double rms = s.type == SpectrumType::kAmplitude && k > 0 ? values[k] / std::sqrt(2.0) : values[k];
      level[k] = psd ? psd_level_db(values[k], ref) : level_db(rms, ref);
    }

    h5::Group g = out.root.create_group("spectrum/" + info.name);
    describe_signal(g, info, common.window);
    g.write("frequency_hz", f);
    g.set_attribute("units", "Hz", "frequency_hz");
    g.write("amplitude", values);
    g.set_attribute("units", s.unit.empty() ? std::string("1") : s.unit, "amplitude");
    g.set_attribute("spectrum_type", to_string(s.type), "amplitude");
    g.set_attribute("description",
                    psd ? "power spectral density, single-sided, Welch average (energy-correct)"
                        : std::string(s.type == SpectrumType::kAmplitude ? "peak amplitude" : "RMS") +
                              " per bin, single-sided, Welch average, " + to_string(s.scaling) +
                              "-correct scaling",
                    "amplitude");
    g.write("level_db", level);
    write_reference(g, "level_db", ref, psd);
    g.set_attribute("description", psd ? "10 log10(PSD / reference^2)" : "20 log10(RMS / reference)",
                    "level_db");
    g.set_attribute("window", to_string(s.window));
    g.set_attribute("scaling", psd ? std::string("energy") : to_string(s.scaling));
    g.set_attribute("segment_length", static_cast<std::int64_t>(s.segment_length));
    g.set_attribute("overlap", s.overlap);
    g.set_attribute("averages", static_cast<std::int64_t>(s.averages));
    g.set_attribute("resolution_hz", s.resolution_hz);
    g.set_attribute("enbw_hz", s.enbw_hz);
    g.set_attribute("derivative", static_cast<std::int64_t>(s.derivative));
    std::ostringstream msg;
    msg.precision(6);
    msg << info.name << ": " << s.averages << " averages of " << s.segment_length << " samples, resolution "
        << s.resolution_hz << " Hz, " << to_string(s.window) << " window";
    log.info(msg.str());
    if (common.csv_dir)
      write_csv(csvs, *common.csv_dir / ("spectrum_" + info.name + ".csv"),
                {"frequency_hz", "amplitude_" + (s.unit.empty() ? std::string("1") : s.unit), "level_db"},
                {&f, &values, &level});
  }
  commit_outputs(out, csvs);
}

namespace {

class SpectrumAnalysis final : public Analysis {
 public:
  void add_options(CLI::App& s, CliShared& shared) override {
    add_common(s, command_.common, shared);
    s.add_option("--window", window_, "rectangular, hann (default), hamming, flattop, blackman-harris");
    s.add_option("--type", type_, "amplitude (peak), rms (default) or psd")
        ->check(CLI::IsMember({"amplitude", "rms", "psd"}));
    s.add_option("--scaling", scaling_, "amplitude (sines read right, default) or energy (broadband right)")
        ->check(CLI::IsMember({"amplitude", "energy"}));
    s.add_option("--resolution", command_.options.resolution_hz, "frequency resolution, Hz (default 1)")
        ->check(CLI::PositiveNumber);
    s.add_option("--segment", command_.options.segment_length,
                 "segment length, samples (overrides --resolution)")
        ->check(CLI::PositiveNumber);
    s.add_option("--overlap", command_.options.overlap, "segment overlap fraction in [0, 1) (default 0.5)");
    s.add_option("--integrate", integrate_,
                 "integrate N times in the frequency domain (acceleration -> velocity)")
        ->check(CLI::Range(0, 2));
    s.add_option("--differentiate", differentiate_, "differentiate N times in the frequency domain")
        ->check(CLI::Range(0, 2));
    s.add_option("--fmax", command_.fmax_hz, "store bins up to this frequency, Hz (default: Nyquist)");
  }

  void run(const Logger& log, int argc, const char* const* argv) override {
    if (integrate_ && differentiate_) throw Error("give --integrate or --differentiate, not both");
    command_.options.window = parse_window(window_);
    command_.options.type = parse_spectrum_type(type_);
    command_.options.scaling = parse_scaling(scaling_);
    command_.options.derivative = differentiate_ - integrate_;
    run_spectrum(command_, log, argc, argv);
  }

  std::filesystem::path output() const override { return command_.common.output; }

 private:
  SpectrumCommand command_;
  std::string window_ = "hann", type_ = "rms", scaling_ = "amplitude";
  int integrate_ = 0, differentiate_ = 0;
};

}  // namespace

std::unique_ptr<Analysis> make_spectrum_analysis() {
  return std::make_unique<SpectrumAnalysis>();
}

}  // namespace nvh::postproc
