#include "postproc/commands.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <future>
#include <map>
#include <set>
#include <sstream>

#include "common/error.hpp"
#include "common/hdf5.hpp"
#include "common/output_path.hpp"
#include "common/progress.hpp"
#include "postproc/levels.hpp"
#include "postproc/octave.hpp"
#include "postproc/signal.hpp"
#include "postproc/stats.hpp"

namespace nvh::postproc {
namespace {

// ---------------------------------------------------------------------------------------------
// Reading

/// Read a signal block by block (with a progress bar on long signals) and hand each block on.
void for_each_block(const SignalSource& source, std::int64_t block, const Logger& log,
                    const std::string& label,
                    const std::function<void(std::int64_t, std::span<const double>)>& consume) {
  const std::int64_t n = source.size();
  std::unique_ptr<Progress> progress;
  if (n > 4 * block) progress = std::make_unique<Progress>(log, label, n);
  std::vector<double> buffer;
  for (std::int64_t offset = 0; offset < n; offset += block) {
    const std::int64_t count = std::min(block, n - offset);
    buffer.resize(static_cast<std::size_t>(count));
    source.read(offset, buffer);
    consume(offset, buffer);
    if (progress) progress->update(offset + count);
  }
  if (progress) progress->finish();
}

std::vector<SignalSource> open_signals(const CommonOptions& common) {
  if (common.signals.empty())
    throw Error("no signal given; expected FILE.h5:/dataset, FILE.csv:column or FILE.uff");
  std::vector<SignalSource> sources;
  std::set<std::string> names;
  for (const std::string& address : common.signals) {
    sources.push_back(SignalSource::open(address));
    const std::string& name = sources.back().info().name;
    if (!names.insert(name).second)
      throw Error("two signals are named '" + name + "' in the output; name them with NAME=ADDRESS");
  }
  return sources;
}

std::string quantity_for(const CommonOptions& common, const SignalInfo& info, int derivative = 0) {
  std::string q = common.quantity.empty() ? quantity_of_unit(info.unit) : common.quantity;
  if (derivative == 0) return q;
  const std::vector<std::string> chain = {"displacement", "velocity", "acceleration"};
  const auto at = std::find(chain.begin(), chain.end(), q);
  if (at == chain.end()) return "";
  const long j = (at - chain.begin()) + derivative;
  return j >= 0 && j < 3 ? chain[static_cast<std::size_t>(j)] : "";
}

// ---------------------------------------------------------------------------------------------
// Writing

struct Output {
  h5::File file;
  h5::Group root;
};

/// The provenance (SHA-256 of every input file) is computed on a second thread while the analysis runs: on a
/// 500 MB result file hashing costs about as much as a spectrum.
std::future<Provenance> start_provenance(const std::vector<SignalSource>& sources, int argc,
                                         const char* const* argv) {
  std::vector<std::filesystem::path> inputs;
  for (const SignalSource& s : sources)
    if (!s.info().file.empty() && std::find(inputs.begin(), inputs.end(), s.info().file) == inputs.end())
      inputs.push_back(s.info().file);
  return std::async(std::launch::async,
                    [inputs, argc, argv] { return make_provenance("postproc", argc, argv, inputs); });
}

Output create_output(const CommonOptions& common, std::future<Provenance>& provenance,
                     const std::string& analysis) {
  const Provenance p = provenance.get();
  Output out{h5::File::create(common.output), {}};
  out.root = out.file.root();
  out.root.set_attribute("format", kPostprocFormat);
  out.root.set_attribute("format_version", kPostprocFormatVersion);
  out.root.set_attribute("units", "SI");
  out.root.set_attribute("analysis", analysis);
  write_provenance(out.root, p);
  return out;
}

/// Time of the last sample of a (windowed) signal, s.
double window_end_s(const SignalInfo& info) {
  return info.start_time_s + static_cast<double>(info.size - 1) / info.sample_rate_hz;
}

/// The signal and the analysis window (`info` describes the samples analysed: the window, if any).
void describe_signal(h5::Group& g, const SignalInfo& info, const AnalysisWindow& window) {
  g.set_attribute("signal", info.address);
  g.set_attribute("signal_unit", info.unit.empty() ? std::string("unknown") : info.unit);
  g.set_attribute("sample_rate_hz", info.sample_rate_hz);
  g.set_attribute("samples", static_cast<std::int64_t>(info.size));
  g.set_attribute("duration_s", static_cast<double>(info.size) / info.sample_rate_hz);
  g.set_attribute("window_start_s", info.start_time_s);
  g.set_attribute("window_end_s", window_end_s(info));
  g.set_attribute("window_skip_cycles", static_cast<std::int64_t>(window.skip_cycles));
}

void write_reference(h5::Group& g, const std::string& dataset, const LevelReference& ref, bool psd = false) {
  g.set_attribute("units", ref.label(psd), dataset);
  g.set_attribute("reference", ref.value, dataset);
  g.set_attribute("reference_unit", ref.unit, dataset);
  g.set_attribute("reference_source", ref.source, dataset);
  g.set_attribute("quantity", ref.quantity.empty() ? std::string("unknown") : ref.quantity, dataset);
}

/// CSV with a header row; columns of equal length. Written to a temporary and closed; the command commits
/// the CSV files after the HDF5 output, so that a failure leaves none of them.
void write_csv(std::vector<TextOutput>& csvs, const std::filesystem::path& path,
               const std::vector<std::string>& header, const std::vector<const Eigen::VectorXd*>& columns) {
  TextOutput& csv = csvs.emplace_back(path);
  std::ostream& out = csv.stream();
  out.precision(10);
  for (std::size_t c = 0; c < header.size(); ++c) out << (c ? "," : "") << header[c];
  out << "\n";
  const Eigen::Index rows = columns.empty() ? 0 : columns.front()->size();
  for (Eigen::Index r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < columns.size(); ++c) out << (c ? "," : "") << (*columns[c])[r];
    out << "\n";
  }
  csv.close();
}

/// The HDF5 output, then the CSV files: called once everything is written.
void commit_outputs(Output& out, std::vector<TextOutput>& csvs) {
  out.file.commit();
  for (TextOutput& csv : csvs) csv.commit();
}

/// Before any work: the outputs (HDF5 and the CSV files, `csv_prefix` + signal name, or `csv_names`) may not
/// replace an input signal or angle file, and must be writable.
void check_outputs(const CommonOptions& common, const std::vector<SignalSource>& sources,
                   const AngleSource* angle, const std::string& csv_prefix,
                   std::vector<std::string> csv_names = {}) {
  std::vector<std::filesystem::path> inputs;
  for (const std::string& address : common.signals) inputs.push_back(SignalSource::file_of(address));
  if (angle && !angle->address.empty() && angle->address.front() != '/')
    inputs.push_back(SignalSource::file_of(angle->address));
  std::vector<std::filesystem::path> outputs{common.output};
  if (common.csv_dir) {
    if (csv_names.empty())
      for (const SignalSource& s : sources) csv_names.push_back(csv_prefix + s.info().name + ".csv");
    for (const std::string& name : csv_names) outputs.push_back(*common.csv_dir / name);
  }
  check_outputs_are_not_inputs(outputs, inputs);
  check_output_writable(common.output);
  if (common.csv_dir) check_output_directory(*common.csv_dir);
}

Eigen::VectorXd to_vector(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

// ---------------------------------------------------------------------------------------------
// Shaft angle for orders and harmonics

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

// ---------------------------------------------------------------------------------------------
// Analysis window (docs/postproc.md section 2.1)

/// Restrict `signal` to the analysis window: --start/--end, then --skip-cycles with the shaft angle
/// (`angle` may be null when the subcommand has none). No-op without a window.
void apply_window(SignalSource& signal, const AnalysisWindow& window, const AngleSource* angle,
                  double cycle_deg, std::int64_t block, const Logger& log) {
  if (!window.active()) return;
  const SampleRange range =
      time_window_samples(signal.info(), signal.file_start_time_s(), signal.file_size(), window);
  signal.restrict_to(range.first, range.count);
  if (window.skip_cycles <= 0) return;
  if (!angle) throw Error("--skip-cycles needs a shaft angle; this subcommand has none");
  AngleProvider provider(*angle, signal, block, log);
  CycleSkipper skipper(cycle_deg, window.skip_cycles);
  std::vector<double> a;
  for (std::int64_t offset = 0; offset < signal.size() && !skipper.found(); offset += block) {
    a.resize(static_cast<std::size_t>(std::min(block, signal.size() - offset)));
    provider.read(offset, a);
    skipper.push(a);
  }
  if (!skipper.found() || signal.size() - skipper.sample() < 2) {
    std::ostringstream msg;
    msg << "--skip-cycles " << window.skip_cycles << ": signal '" << signal.info().address
        << "' does not reach the shaft angle " << skipper.target_deg() << " deg (" << window.skip_cycles
        << " whole cycles of " << cycle_deg << " deg) inside the window; expected fewer cycles to skip";
    throw Error(msg.str());
  }
  signal.restrict_to(range.first + skipper.sample(), range.count - skipper.sample());
  log.detail(signal.info().name + ": --skip-cycles " + std::to_string(window.skip_cycles) +
             ": analysis starts at " + std::to_string(signal.info().start_time_s) + " s");
}

/// The cycles of `all` (tracked over the samples of `read`, a window with margins) lying wholly inside the
/// samples `window` of `read`; start times shifted to count from the file's first sample.
OrderSpectra cycles_in_window(const OrderSpectra& all, const SampleRange& window, const SignalSource& read) {
  const double fs = read.info().sample_rate_hz;
  const double from = static_cast<double>(window.first) / fs,
               to = static_cast<double>(window.first + window.count - 1) / fs;
  // To within a sample: the first sample of a window set by --skip-cycles is the one at or just after the
  // boundary, so the boundary itself may lie up to one sample before it.
  const double slack = 1.0 / fs;
  std::vector<Eigen::Index> keep;
  for (Eigen::Index c = 0; c < all.rpm.size(); ++c) {
    const double end = all.start_time_s[c] + 60.0 * (all.cycle_deg / 360.0) / all.rpm[c];  // next boundary
    if (all.start_time_s[c] >= from - slack && end <= to + slack) keep.push_back(c);
  }
  OrderSpectra s = all;
  const auto n = static_cast<Eigen::Index>(keep.size());
  s.amplitude.resize(n, all.amplitude.cols());
  s.phase_deg.resize(n, all.phase_deg.cols());
  s.rpm.resize(n);
  s.start_time_s.resize(n);
  for (Eigen::Index r = 0; r < n; ++r) {
    s.amplitude.row(r) = all.amplitude.row(keep[r]);
    s.phase_deg.row(r) = all.phase_deg.row(keep[r]);
    s.rpm[r] = all.rpm[keep[r]];
    s.start_time_s[r] = all.start_time_s[keep[r]] + static_cast<double>(read.first_sample()) / fs;
  }
  return s;
}

/// Adds the window to an error of an analysis that the window made too short: the message names the options.
[[noreturn]] void rethrow_in_window(const Error& e, const AnalysisWindow& window, const SignalSource& s) {
  if (!window.active()) throw e;
  std::ostringstream msg;
  msg << e.what() << " (analysis window " << window.describe() << ": " << s.size() << " samples, "
      << s.info().start_time_s << " to " << window_end_s(s.info()) << " s; widen the window)";
  throw Error(msg.str());
}

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

}  // namespace

// ---------------------------------------------------------------------------------------------

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

void run_orders(const OrdersCommand& command, const Logger& log, int argc, const char* const* argv) {
  const CommonOptions& common = command.common;
  std::vector<SignalSource> sources = open_signals(common);
  check_outputs(common, sources, &command.angle, "orders_");
  std::vector<TextOutput> csvs;
  // The window's samples (`windows`); the tracker reads up to kTrackerMargin samples more on either side,
  // when the file has them, so that every cycle lying wholly inside the window is analysed (its kernel
  // reaches 131 samples beyond an angle sample, orders.cpp).
  constexpr std::int64_t kTrackerMargin = 256;
  std::vector<SignalInfo> windows;
  std::vector<SampleRange> in_window;  // the window inside the samples read
  for (SignalSource& s : sources) {
    apply_window(s, common.window, &command.angle, command.options.cycle_deg, common.block, log);
    windows.push_back(s.info());
    in_window.push_back({0, s.size()});
    if (common.window.active()) {
      const std::int64_t first = std::max<std::int64_t>(0, s.first_sample() - kTrackerMargin);
      const std::int64_t end = std::min(s.file_size(), s.first_sample() + s.size() + kTrackerMargin);
      in_window.back().first = s.first_sample() - first;
      s.restrict_to(first, end - first);
    }
  }
  std::future<Provenance> provenance = start_provenance(sources, argc, argv);
  std::vector<int> samples_per_cycle;
  for (const SignalSource& s : sources)
    samples_per_cycle.push_back(samples_per_cycle_from(command.angle, s, command.options, common.block, log));
  std::vector<OrderSpectra> results;
  std::vector<std::unique_ptr<CampbellAccumulator>> campbells;
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const SignalInfo& info = sources[i].info();
    AngleProvider angle(command.angle, sources[i], common.block, log);
    OrderTracker tracker(info.sample_rate_hz, command.options, samples_per_cycle[i]);
    std::unique_ptr<CampbellAccumulator> campbell;
    if (command.campbell) {
      std::int64_t n = 16;  // (an int overflowed on a tiny --campbell-resolution)
      while (n < info.sample_rate_hz / command.campbell_resolution_hz && n <= windows[i].size) n *= 2;
      if (n > windows[i].size)
        rethrow_in_window(
            Error("orders: signal '" + info.address + "' is too short for a Campbell frame of " +
                  std::to_string(n) + " samples; lower --campbell-resolution"),
            common.window, sources[i]);
      campbell = std::make_unique<CampbellAccumulator>(
          info.sample_rate_hz, static_cast<int>(n),
          std::min(command.campbell_fmax_hz, info.sample_rate_hz / 2), command.campbell_rpm_step);
    }
    std::vector<double> a;
    for_each_block(
        sources[i], common.block, log, "orders " + info.name,
        [&](std::int64_t offset, std::span<const double> x) {
          a.resize(x.size());
          angle.read(offset, a);
          tracker.push(x, a);
          if (!campbell) return;
          // The Campbell frames see the window only.
          const SampleRange w = in_window[i];
          const std::int64_t from = std::clamp<std::int64_t>(w.first - offset, 0, std::ssize(x));
          const std::int64_t to = std::clamp<std::int64_t>(w.first + w.count - offset, 0, std::ssize(x));
          if (to > from)
            campbell->push(x.subspan(static_cast<std::size_t>(from), static_cast<std::size_t>(to - from)),
                           std::span<const double>(a).subspan(static_cast<std::size_t>(from),
                                                              static_cast<std::size_t>(to - from)));
        });
    results.push_back(common.window.active() ? cycles_in_window(tracker.result(), in_window[i], sources[i])
                                             : tracker.result());
    if (results.back().amplitude.rows() == 0) {
      std::ostringstream msg;
      msg << "orders: signal '" << info.address << "' holds no complete " << command.options.cycle_deg
          << " deg cycle of the shaft angle; a longer signal is needed";
      rethrow_in_window(Error(msg.str()), common.window, sources[i]);
    }
    campbells.push_back(std::move(campbell));
  }

  Output out = create_output(common, provenance, "orders");
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const SignalInfo& info = sources[i].info();
    const OrderSpectra& s = results[i];
    const LevelReference ref =
        level_reference(quantity_for(common, info), info.unit, common.velocity_reference);
    Eigen::MatrixXd level(s.amplitude.rows(), s.amplitude.cols());
    for (Eigen::Index r = 0; r < level.rows(); ++r)
      for (Eigen::Index c = 0; c < level.cols(); ++c)
        level(r, c) = level_db(c == 0 ? s.amplitude(r, c) : s.amplitude(r, c) / std::sqrt(2.0), ref);
    h5::Group g = out.root.create_group("orders/" + info.name);
    describe_signal(g, windows[i], common.window);
    g.write("order", s.order);
    g.set_attribute("units", "1 (multiples of the shaft speed)", "order");
    g.write("rpm", s.rpm);
    g.set_attribute("units", "rpm", "rpm");
    g.set_attribute("description", "mean shaft speed of each cycle", "rpm");
    g.write("start_time_s", s.start_time_s);
    g.set_attribute("units", "s", "start_time_s");
    g.write("amplitude", s.amplitude);
    g.set_attribute("units", info.unit.empty() ? std::string("1") : info.unit, "amplitude");
    g.set_attribute("description", "peak amplitude per (cycle, order)", "amplitude");
    g.write("phase_deg", s.phase_deg);
    g.set_attribute("units", "deg", "phase_deg");
    g.set_attribute("description", "cosine phase per (cycle, order), angle zero at the cycle start",
                    "phase_deg");
    g.write("level_db", level);
    write_reference(g, "level_db", ref);
    g.set_attribute("cycle_deg", s.cycle_deg);
    g.set_attribute("samples_per_cycle", static_cast<std::int64_t>(s.samples_per_cycle));
    g.set_attribute("interpolation", command.options.interpolation == Interpolation::kSinc
                                         ? std::string("band-limited (Kaiser-windowed sinc, half-width 16)")
                                         : std::string("linear"));
    g.set_attribute("angle_source", command.angle.kind + " " + command.angle.address);
    if (campbells[i]) {
      h5::Group c = g.create_group("campbell");
      const Eigen::VectorXd rpm = campbells[i]->rpm(), f = campbells[i]->frequency_hz();
      const Eigen::MatrixXd amp = campbells[i]->amplitude();
      Eigen::MatrixXd lv(amp.rows(), amp.cols());
      for (Eigen::Index r = 0; r < amp.rows(); ++r)
        for (Eigen::Index k = 0; k < amp.cols(); ++k) lv(r, k) = level_db(amp(r, k), ref);
      c.write("rpm", rpm);
      c.set_attribute("units", "rpm", "rpm");
      c.write("frequency_hz", f);
      c.set_attribute("units", "Hz", "frequency_hz");
      c.write("amplitude", amp);
      c.set_attribute("units", info.unit.empty() ? std::string("1") : info.unit, "amplitude");
      c.set_attribute("description",
                      "RMS per (speed bin, frequency), Hann frames power-averaged per speed bin",
                      "amplitude");
      c.write("level_db", lv);
      write_reference(c, "level_db", ref);
      c.set_attribute("rpm_step", command.campbell_rpm_step);
    }
    std::ostringstream msg;
    msg.precision(5);
    msg << info.name << ": " << s.amplitude.rows() << " cycles of " << s.cycle_deg << " deg, "
        << s.samples_per_cycle << " samples per cycle, orders 0-" << s.order[s.order.size() - 1] << ", "
        << s.rpm.minCoeff() << "-" << s.rpm.maxCoeff() << " rpm";
    log.info(msg.str());
    if (common.csv_dir) {
      std::vector<std::string> header = {"rpm", "start_time_s"};
      std::vector<Eigen::VectorXd> cols;
      for (Eigen::Index k = 0; k < s.order.size(); ++k) {
        std::ostringstream name;
        name << "order_" << s.order[k];
        header.push_back(name.str());
        cols.push_back(s.amplitude.col(k));
      }
      std::vector<const Eigen::VectorXd*> ptrs = {&s.rpm, &s.start_time_s};
      for (const auto& c : cols) ptrs.push_back(&c);
      write_csv(csvs, *common.csv_dir / ("orders_" + info.name + ".csv"), header, ptrs);
    }
  }
  if (command.cut) {
    // One mean order spectrum per signal (steady runs at different speeds) against its mean speed.
    const Eigen::Index orders =
        std::min_element(results.begin(), results.end(), [](const auto& a, const auto& b) {
          return a.order.size() < b.order.size();
        })->order.size();
    Eigen::VectorXd rpm(static_cast<Eigen::Index>(results.size()));
    Eigen::MatrixXd amp(static_cast<Eigen::Index>(results.size()), orders);
    std::vector<std::string> names;
    for (std::size_t i = 0; i < results.size(); ++i) {
      rpm[static_cast<Eigen::Index>(i)] = results[i].rpm.mean();
      amp.row(static_cast<Eigen::Index>(i)) = results[i].amplitude.leftCols(orders).colwise().mean();
      names.push_back(sources[i].info().name);
    }
    h5::Group c = out.root.create_group("orders/cut");
    c.write("rpm", rpm);
    c.set_attribute("units", "rpm", "rpm");
    c.write("order", Eigen::VectorXd(results.front().order.head(orders)));
    c.write("amplitude", amp);
    c.set_attribute("description", "mean peak amplitude over the cycles of each signal, per (signal, order)",
                    "amplitude");
    c.write("signal", names);
  }
  commit_outputs(out, csvs);
}

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

}  // namespace nvh::postproc
