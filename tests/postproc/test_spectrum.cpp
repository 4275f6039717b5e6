// Spectra against closed forms: sines of known amplitude (on and off bin, flat-top within 0.01 dB),
// Parseval, white-noise PSD = variance / (f_s / 2), frequency-domain integration, dB references.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "common/error.hpp"
#include "postproc/levels.hpp"
#include "postproc/spectrum.hpp"

using namespace nvh::postproc;

namespace {

constexpr double kPi = std::numbers::pi;

std::vector<double> sine(double amplitude, double f, double fs, int n, double phase = 0.3) {
  std::vector<double> x(n);
  for (int i = 0; i < n; ++i) x[i] = amplitude * std::cos(2 * kPi * f * i / fs + phase);
  return x;
}

double peak(const Spectrum& s) {
  return s.values.maxCoeff();
}

}  // namespace

// A sine of amplitude A reads A in the amplitude spectrum with the flat-top window, whatever its position
// between bins (reference: A itself; tolerance 0.01 dB, the issue's; HFT90D's flatness is 0.0039 dB).
TEST(postproc_spectrum, FlatTopReadsSineAmplitudeOnAndOffBin) {
  const double fs = 2048.0, amplitude = 2.5;
  const int n = 1024;
  SpectrumOptions o;
  o.window = WindowKind::kFlatTop;
  o.segment_length = n;
  o.type = SpectrumType::kAmplitude;
  double worst = 0.0;
  for (double offset : {0.0, 0.1, 0.25, 0.37, 0.5}) {
    const double f = (100.0 + offset) * fs / n;
    const std::vector<double> x = sine(amplitude, f, fs, 8 * n);
    const Spectrum s = welch_spectrum(x, fs, o, "m/s^2");
    const double error_db = 20 * std::log10(peak(s) / amplitude);
    worst = std::max(worst, std::abs(error_db));
    EXPECT_LT(std::abs(error_db), 0.01) << "bin offset " << offset;
  }
  std::printf("flat-top: worst amplitude error %.5f dB over bin offsets 0..0.5\n", worst);
  // The RMS spectrum reads A / sqrt 2.
  o.type = SpectrumType::kRms;
  const Spectrum rms = welch_spectrum(sine(amplitude, 100.0 * fs / n, fs, 4 * n), fs, o);
  EXPECT_NEAR(peak(rms), amplitude / std::sqrt(2.0), 1e-9);
}

// Hann is not flat: half a bin off, it reads -1.42 dB (Harris 1978, Table 1: scallop loss 1.42 dB).
TEST(postproc_spectrum, HannScallopLossMatchesHarris) {
  const double fs = 1024.0;
  const int n = 1024;
  SpectrumOptions o;
  o.window = WindowKind::kHann;
  o.segment_length = n;
  o.type = SpectrumType::kAmplitude;
  const Spectrum s = welch_spectrum(sine(1.0, 200.5, fs, 4 * n), fs, o);
  EXPECT_NEAR(20 * std::log10(peak(s)), -1.42, 0.01);
}

// Parseval: with energy-correct scaling the bins' mean squares add up to the signal's mean square
// (rectangular window, one segment: exact to rounding; Hann with Welch on a stationary signal: the
// mean over segments, still exact for a periodic signal whose periods fill the segments).
TEST(postproc_spectrum, ParsevalHoldsWithEnergyScaling) {
  const double fs = 1000.0;
  const int n = 4000;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.3);
  std::vector<double> x(n);
  double mean_square = 0.0;
  for (double& v : x) {
    v = normal(rng) + 0.4;
    mean_square += v * v / n;
  }
  SpectrumOptions o;
  o.window = WindowKind::kRectangular;
  o.segment_length = n;
  o.scaling = Scaling::kEnergy;
  const Spectrum s = welch_spectrum(x, fs, o);
  EXPECT_NEAR(s.values.squaredNorm(), mean_square, 1e-12 * mean_square);
  o.type = SpectrumType::kPsd;
  const Spectrum psd = welch_spectrum(x, fs, o);
  EXPECT_NEAR(psd.values.sum() * psd.resolution_hz, mean_square, 1e-12 * mean_square);
}

// White noise of variance sigma^2 has the single-sided PSD sigma^2 / (f_s / 2) (reference: the generating
// variance; tolerance 1.5 %: 1023 segments x 511 bins leave a statistical scatter of the mean below 0.3 %).
TEST(postproc_spectrum, WhiteNoisePsdIsVarianceOverBandwidth) {
  const double fs = 1000.0, sigma = 0.3;
  std::mt19937_64 rng(42);
  std::normal_distribution<double> normal(0.0, sigma);
  std::vector<double> x(1 << 19);
  for (double& v : x) v = normal(rng);
  SpectrumOptions o;
  o.window = WindowKind::kHann;
  o.segment_length = 1024;
  o.overlap = 0.5;
  o.type = SpectrumType::kPsd;
  const Spectrum s = welch_spectrum(x, fs, o, "m/s^2");
  const double expected = sigma * sigma / (fs / 2);
  const double mean = s.values.segment(1, s.values.size() - 2).mean();
  EXPECT_NEAR(mean / expected, 1.0, 0.015);
  EXPECT_EQ(s.averages, 1023);
  EXPECT_EQ(s.unit, "(m/s^2)^2/Hz");
}

// Integration in the frequency domain: an acceleration sine A cos(2 pi f t) is a velocity of amplitude
// A / (2 pi f) and a displacement of A / (2 pi f)^2 (closed form; flat-top, 0.01 dB).
TEST(postproc_spectrum, IntegrationDividesByOmega) {
  const double fs = 4096.0, f = 160.0, a = 12.0;
  SpectrumOptions o;
  o.window = WindowKind::kFlatTop;
  o.segment_length = 2048;
  o.type = SpectrumType::kAmplitude;
  o.derivative = -1;
  const std::vector<double> x = sine(a, f, fs, 8192);
  const Spectrum v = welch_spectrum(x, fs, o, "m/s^2");
  EXPECT_EQ(v.unit, "m/s");
  EXPECT_LT(std::abs(20 * std::log10(peak(v) / (a / (2 * kPi * f)))), 0.01);
  o.derivative = -2;
  const Spectrum d = welch_spectrum(x, fs, o, "m/s^2");
  EXPECT_EQ(d.unit, "m");
  EXPECT_LT(std::abs(20 * std::log10(peak(d) / (a / std::pow(2 * kPi * f, 2)))), 0.01);
}

// dB references (ISO 1683:2015 Table 1 and the engine convention v0 = 5e-8 m/s).
TEST(postproc_spectrum, LevelReferences) {
  EXPECT_NEAR(level_db(1e-3, level_reference("velocity", "m/s", "engine")), 20 * std::log10(1e-3 / 5e-8),
              1e-12);
  EXPECT_NEAR(level_db(1e-3, level_reference("velocity", "m/s", "iso")), 120.0, 1e-12);
  EXPECT_NEAR(level_db(1.0, level_reference("acceleration", "m/s^2")), 120.0, 1e-12);
  EXPECT_NEAR(level_db(1.0, level_reference("pressure", "Pa")), 93.9794, 1e-4);
  EXPECT_NEAR(level_db(1e-2, level_reference("power", "W")), 100.0, 1e-12);
  EXPECT_EQ(level_reference("acceleration", "m/s^2").label(), "dB re 1e-06 m/s^2");
}

// Too short a signal for the asked resolution is an error naming the signal and the needed length.
TEST(postproc_spectrum, TooShortForResolutionIsAnError) {
  SpectrumOptions o;
  o.resolution_hz = 0.1;
  try {
    segment_length_for(o, 1000.0, 5000, "run.h5:/x");
    FAIL() << "expected an error";
  } catch (const nvh::Error& e) {
    EXPECT_NE(std::string(e.what()).find("run.h5:/x"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("too short"), std::string::npos) << e.what();
  }
}
