#include "postproc/octave.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "common/error.hpp"

namespace nvh::postproc {
namespace {

const double kG = std::pow(10.0, 0.3);  // octave ratio, base-10 system (IEC 61260-1 eq. 1)
constexpr double kReferenceHz = 1000.0;
constexpr int kBandPrototypeOrder = 3;      // 6th-order band-pass
constexpr int kAntiAliasOrder = 8;          // low-pass before each decimation by 2
constexpr double kAntiAliasCutoff = 0.2;    // of the rate before decimation
constexpr double kMinRateOverCenter = 5.0;  // a band is filtered at the lowest rate >= 5 f_m

// IEC 61260-1 Annex E nominal mid-band frequencies of 1/3-octave bands, one decade (octave ones are a
// subset).
constexpr std::array<double, 10> kNominalMantissa = {1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0};

double nominal_frequency(double exact, int b) {
  const double decade = std::pow(10.0, std::floor(std::log10(exact) + 1e-12));
  const double m = exact / decade;
  if (b == 1 || b == 3) {
    double best = kNominalMantissa[0], distance = 1e9;
    for (double candidate : {1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0, 10.0}) {
      const double d = std::abs(std::log(m / candidate));
      if (d < distance) {
        distance = d;
        best = candidate;
      }
    }
    return best * decade;
  }
  // Other designators: three significant digits.
  const double scale = std::pow(10.0, std::floor(std::log10(exact)) - 2.0);
  return std::round(exact / scale) * scale;
}

}  // namespace

std::vector<Band> fractional_octave_bands(int b, double f_low, double f_high) {
  if (b < 1) throw Error("octave: the bandwidth designator 1/b needs b >= 1, got b = " + std::to_string(b));
  if (!(f_low > 0.0 && f_high >= f_low)) throw Error("octave: need 0 < fmin <= fmax");
  std::vector<Band> bands;
  const double half = std::pow(kG, 1.0 / (2.0 * b));
  // x range wide enough to cover [f_low, f_high]
  const int x_min = static_cast<int>(std::floor(b * std::log(f_low / kReferenceHz) / std::log(kG))) - 2;
  const int x_max = static_cast<int>(std::ceil(b * std::log(f_high / kReferenceHz) / std::log(kG))) + 2;
  for (int x = x_min; x <= x_max; ++x) {
    const double fm = b % 2 == 1 ? kReferenceHz * std::pow(kG, static_cast<double>(x) / b)
                                 : kReferenceHz * std::pow(kG, (2.0 * x + 1.0) / (2.0 * b));
    const double f1 = fm / half, f2 = fm * half;
    // A nominal limit (20 Hz for 19.95 Hz) selects its band: centres within a quarter band of the limits.
    const double slack = std::sqrt(half);
    if (fm >= f_low / slack && fm <= f_high * slack)
      bands.push_back({x, fm, f1, f2, nominal_frequency(fm, b)});
  }
  if (bands.empty()) {
    std::ostringstream msg;
    msg << "octave: no band between --fmin " << f_low << " Hz and --fmax " << f_high
        << " Hz (--fmax defaults to 10 kHz or the highest band below half the sample rate)";
    throw Error(msg.str());
  }
  return bands;
}

double a_weighting_db(double f) {
  // IEC 61672-1:2013 Annex E: pole frequencies (E.2-E.5) and normalization A_1000 = -2.000 dB (E.6).
  constexpr double f1 = 20.598997, f2 = 107.65265, f3 = 737.86223, f4 = 12194.217;
  const double f_sq = f * f;
  const double r = (f4 * f4 * f_sq * f_sq) /
                   ((f_sq + f1 * f1) * std::sqrt((f_sq + f2 * f2) * (f_sq + f3 * f3)) * (f_sq + f4 * f4));
  return 20.0 * std::log10(r) + 2.0;  // A(f) = 20 log10 R_A(f) - A_1000, A_1000 = -2.000 dB
}

// ---------------------------------------------------------------------------------------------

// One octave step of the multirate bank: the bands filtered at this rate and the anti-alias filter that
// makes the next stage's input, packed four cascades to a CascadeLanes4 (one pass over the samples each).
struct OctaveFilterBank::Stage {
  struct Group {
    std::unique_ptr<CascadeLanes4> lanes;
    std::vector<int> slot;  // lane -> band of this stage (index into band_ids), -1: anti-alias or empty
    int output_lane = -1;   // the anti-alias lane, if in this group
  };
  double fs = 0.0;
  std::vector<int> band_ids;
  std::vector<SosFilter> filters;  // the same band-passes, for response()
  SosFilter anti_alias;            // for response()
  std::vector<Group> groups;
  std::vector<double> sum_squares;                 // per band of this stage
  std::vector<std::vector<double>> interval_sums;  // per band: per interval
  std::vector<std::int64_t> interval_counts;       // samples per interval (same for all bands of the stage)
  std::int64_t samples = 0;
};

OctaveFilterBank::OctaveFilterBank(std::vector<Band> bands, double fs, double interval_s,
                                   const std::string& signal_name)
    : bands_(std::move(bands)), fs_(fs), interval_s_(interval_s) {
  // An interval of less than a sample made one interval per sample per band, without bound.
  if (!(interval_s >= 0 && std::isfinite(interval_s)) || (interval_s > 0 && interval_s * fs < 1)) {
    std::ostringstream msg;
    msg << "octave: the Leq interval " << interval_s << " s is not a time of at least one sample (" << 1 / fs
        << " s) of signal '" << signal_name << "'";
    throw Error(msg.str());
  }
  for (const Band& band : bands_) {
    if (band.upper_hz >= fs / 2.0) {
      std::ostringstream msg;
      msg << "octave: band " << band.nominal_hz << " Hz has its upper edge " << band.upper_hz
          << " Hz at or above the Nyquist frequency " << fs / 2.0 << " Hz of signal '" << signal_name
          << "' (sample rate " << fs << " Hz); lower fmax";
      throw Error(msg.str());
    }
  }
  // Stage k runs at fs / 2^k; a band goes to the last stage whose rate is still >= 5 f_m.
  std::vector<int> stage_of(bands_.size(), 0);
  int stages = 1;
  for (std::size_t i = 0; i < bands_.size(); ++i) {
    int k = 0;
    while (fs / std::pow(2.0, k + 1) >= kMinRateOverCenter * bands_[i].center_hz) ++k;
    stage_of[i] = k;
    stages = std::max(stages, k + 1);
  }
  for (int k = 0; k < stages; ++k) {
    auto stage = std::make_unique<Stage>();
    stage->fs = fs / std::pow(2.0, k);
    std::vector<std::vector<Biquad>> cascades;
    for (std::size_t i = 0; i < bands_.size(); ++i) {
      if (stage_of[i] != k) continue;
      const Band& band = bands_[i];
      stage->band_ids.push_back(static_cast<int>(i));
      cascades.push_back(
          butterworth_bandpass(kBandPrototypeOrder, band.lower_hz, band.upper_hz, band.center_hz, stage->fs));
      stage->filters.emplace_back(cascades.back());
    }
    const bool decimate = k + 1 < stages;
    if (decimate) {
      cascades.push_back(butterworth_lowpass(kAntiAliasOrder, kAntiAliasCutoff * stage->fs, stage->fs));
      stage->anti_alias = SosFilter(cascades.back());
    }
    for (std::size_t first = 0; first < cascades.size(); first += CascadeLanes4::kLanes) {
      const std::size_t last = std::min(cascades.size(), first + CascadeLanes4::kLanes);
      Stage::Group group;
      group.lanes = std::make_unique<CascadeLanes4>(
          std::vector<std::vector<Biquad>>(cascades.begin() + static_cast<std::ptrdiff_t>(first),
                                           cascades.begin() + static_cast<std::ptrdiff_t>(last)));
      group.slot.assign(CascadeLanes4::kLanes, -1);
      for (std::size_t c = first; c < last; ++c) {
        const int lane = static_cast<int>(c - first);
        if (c < stage->band_ids.size())
          group.slot[lane] = static_cast<int>(c);
        else
          group.output_lane = lane;
      }
      stage->groups.push_back(std::move(group));
    }
    stage->sum_squares.assign(stage->band_ids.size(), 0.0);
    stage->interval_sums.resize(stage->band_ids.size());
    stages_.push_back(std::move(stage));
  }
}

OctaveFilterBank::~OctaveFilterBank() = default;

void OctaveFilterBank::push(std::span<const double> samples) {
  // Stage 0 reads the block itself; each later stage reads the decimated output of the one before, kept in
  // two buffers of the bank (memory: the block and its half, whatever the signal length).
  const double* input = samples.data();
  std::size_t n = samples.size();
  for (std::size_t k = 0; k < stages_.size(); ++k) {
    Stage& st = *stages_[k];
    if (n == 0) break;
    // Pieces of the block inside one Leq interval (one piece without intervals): (begin, interval index).
    std::vector<std::pair<std::size_t, std::size_t>> pieces;
    const double per_interval = interval_s_ > 0.0 ? interval_s_ * st.fs : 0.0;
    for (std::size_t i = 0; i < n;) {
      std::size_t end = n, index = 0;
      if (per_interval > 0.0) {
        index = static_cast<std::size_t>(
            std::floor(static_cast<double>(st.samples + static_cast<std::int64_t>(i)) / per_interval + 1e-9));
        const auto next =
            static_cast<std::int64_t>(std::ceil(static_cast<double>(index + 1) * per_interval - 1e-9));
        end = std::min(n, static_cast<std::size_t>(
                              std::max<std::int64_t>(next - st.samples, static_cast<std::int64_t>(i) + 1)));
        if (st.interval_counts.size() <= index) st.interval_counts.resize(index + 1, 0);
        st.interval_counts[index] += static_cast<std::int64_t>(end - i);
      }
      pieces.emplace_back(i, index);
      i = end;
    }
    pieces.emplace_back(n, 0);
    decimated_.resize(n / 2 + 1);
    std::size_t decimated = 0;
    for (std::size_t p = 0; p + 1 < pieces.size(); ++p) {
      const std::size_t begin = pieces[p].first, count = pieces[p + 1].first - begin,
                        index = pieces[p].second;
      for (Stage::Group& g : st.groups) {
        double sums[CascadeLanes4::kLanes] = {0.0, 0.0, 0.0, 0.0};
        decimated +=
            g.lanes->process(input + begin, count, sums, g.output_lane, decimated_.data() + decimated);
        for (int lane = 0; lane < CascadeLanes4::kLanes; ++lane) {
          const int slot = g.slot[lane];
          if (slot < 0) continue;
          st.sum_squares[slot] += sums[lane];
          if (per_interval > 0.0) {
            auto& sums_of_band = st.interval_sums[slot];
            if (sums_of_band.size() <= index) sums_of_band.resize(index + 1, 0.0);
            sums_of_band[index] += sums[lane];
          }
        }
      }
    }
    st.samples += static_cast<std::int64_t>(n);
    if (k + 1 == stages_.size()) break;
    decimated_.resize(decimated);
    stage_input_.swap(decimated_);
    input = stage_input_.data();
    n = stage_input_.size();
  }
}

std::vector<double> OctaveFilterBank::mean_square() const {
  // The first CascadeLanes4::kDelay outputs of a stage are the pipeline filling (zeros): not counted.
  std::vector<double> ms(bands_.size(), 0.0);
  for (const auto& st : stages_)
    for (std::size_t j = 0; j < st->band_ids.size(); ++j)
      ms[st->band_ids[j]] = st->sum_squares[j] / static_cast<double>(std::max<std::int64_t>(
                                                     1, st->samples - CascadeLanes4::kDelay));
  return ms;
}

Eigen::MatrixXd OctaveFilterBank::interval_mean_square() const {
  if (interval_s_ <= 0.0) return {};
  // Complete intervals only (the last one of the slowest stage may be cut short; a partial interval is kept
  // when it holds at least half of its samples).
  std::size_t intervals = 0;
  for (const auto& st : stages_) {
    const double per_interval = interval_s_ * st->fs;
    std::size_t complete = 0;
    for (std::size_t i = 0; i < st->interval_counts.size(); ++i)
      if (st->interval_counts[i] >= 0.5 * per_interval) complete = i + 1;
    intervals = intervals == 0 ? complete : std::min(intervals, complete);
  }
  Eigen::MatrixXd ms =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(intervals), static_cast<Eigen::Index>(bands_.size()));
  for (const auto& st : stages_)
    for (std::size_t j = 0; j < st->band_ids.size(); ++j)
      for (std::size_t i = 0; i < intervals && i < st->interval_sums[j].size(); ++i)
        ms(static_cast<Eigen::Index>(i), st->band_ids[j]) =
            st->interval_sums[j][i] / static_cast<double>(std::max<std::int64_t>(
                                          1, st->interval_counts[i] - (i == 0 ? CascadeLanes4::kDelay : 0)));
  return ms;
}

double OctaveFilterBank::band_rate_hz(int band) const {
  for (const auto& st : stages_)
    for (int id : st->band_ids)
      if (id == band) return st->fs;
  return 0.0;
}

double OctaveFilterBank::response(int band, double f) const {
  double h = 1.0;
  for (const auto& st : stages_) {
    for (std::size_t j = 0; j < st->band_ids.size(); ++j)
      if (st->band_ids[j] == band) return h * std::abs(st->filters[j].response(f, st->fs));
    h *= std::abs(st->anti_alias.response(f, st->fs));
  }
  return 0.0;
}

std::vector<double> band_mean_square_from_psd(const Spectrum& psd, const std::vector<Band>& bands) {
  if (psd.type != SpectrumType::kPsd) throw Error("octave: band summation needs a PSD");
  const double df = psd.resolution_hz;
  std::vector<double> ms(bands.size(), 0.0);
  for (std::size_t b = 0; b < bands.size(); ++b) {
    const Band& band = bands[b];
    if (band.upper_hz - band.lower_hz < 2.0 * df) {
      std::ostringstream msg;
      msg << "octave: band " << band.nominal_hz << " Hz is " << band.upper_hz - band.lower_hz
          << " Hz wide, less than 2 bins of " << df
          << " Hz; a longer signal or a finer resolution is needed for FFT band summation";
      throw Error(msg.str());
    }
    const Eigen::Index last = psd.frequency_hz.size() - 1;
    const auto k_lo = static_cast<Eigen::Index>(std::max(0.0, std::floor(band.lower_hz / df - 1.0)));
    const auto k_hi = std::min(last, static_cast<Eigen::Index>(std::ceil(band.upper_hz / df + 1.0)));
    double sum = 0.0;
    for (Eigen::Index k = k_lo; k <= k_hi; ++k) {
      const double lo = std::max(band.lower_hz, psd.frequency_hz[k] - df / 2.0);
      const double hi = std::min(band.upper_hz, psd.frequency_hz[k] + df / 2.0);
      if (hi > lo) sum += psd.values[k] * (hi - lo);
    }
    ms[b] = sum;
  }
  return ms;
}

}  // namespace nvh::postproc
