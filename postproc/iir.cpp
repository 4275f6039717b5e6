#include "postproc/iir.hpp"

#include <cmath>
#include <numbers>

#include "common/error.hpp"

namespace nvh::postproc {
namespace {

using cd = std::complex<double>;

cd bilinear(cd s, double fs) {
  return (2.0 * fs + s) / (2.0 * fs - s);
}

double prewarp(double f, double fs) {
  return 2.0 * fs * std::tan(std::numbers::pi * f / fs);
}

// Butterworth low-pass prototype poles (cut-off 1 rad/s), left half plane, upper half first.
std::vector<cd> prototype_poles(int n) {
  std::vector<cd> poles;
  for (int k = 0; k < n; ++k)
    poles.push_back(std::polar(1.0, std::numbers::pi * (2.0 * k + n + 1.0) / (2.0 * n)));
  return poles;
}

// A section with the digital pole pair {z, conj(z)} (or two real poles) and the given numerator.
Biquad section(cd z1, cd z2, double b0, double b1, double b2) {
  Biquad q;
  q.b0 = b0;
  q.b1 = b1;
  q.b2 = b2;
  q.a1 = -(z1 + z2).real();
  q.a2 = (z1 * z2).real();
  return q;
}

// Spread a total gain evenly over the sections (keeps intermediate signals of similar size).
void normalize(std::vector<Biquad>& sections, double f_ref, double fs) {
  cd h = 1.0;
  for (const Biquad& q : sections) h *= q.response(f_ref, fs);
  const double per_section = std::pow(1.0 / std::abs(h), 1.0 / static_cast<double>(sections.size()));
  for (Biquad& q : sections) {
    q.b0 *= per_section;
    q.b1 *= per_section;
    q.b2 *= per_section;
  }
}

}  // namespace

std::complex<double> Biquad::response(double f, double fs) const {
  const cd z1 = std::polar(1.0, -2.0 * std::numbers::pi * f / fs);  // z^-1
  return (b0 + b1 * z1 + b2 * z1 * z1) / (1.0 + a1 * z1 + a2 * z1 * z1);
}

std::complex<double> SosFilter::response(double f, double fs) const {
  cd h = 1.0;
  for (const Biquad& q : sections_) h *= q.response(f, fs);
  return h;
}

void SosFilter::process(std::span<double> x) {
  for (std::size_t j = 0; j < sections_.size(); ++j) {
    const Biquad q = sections_[j];
    double s1 = state_[2 * j], s2 = state_[2 * j + 1];
    for (double& v : x) {
      const double in = v;
      const double y = q.b0 * in + s1;
      s1 = q.b1 * in - q.a1 * y + s2;
      s2 = q.b2 * in - q.a2 * y;
      v = y;
    }
    state_[2 * j] = s1;
    state_[2 * j + 1] = s2;
  }
}

std::vector<Biquad> butterworth_bandpass(int n, double f1, double f2, double f_ref, double fs) {
  if (!(0.0 < f1 && f1 < f2 && f2 < fs / 2.0))
    throw Error("band-pass design: edges must satisfy 0 < f1 < f2 < fs/2");
  const double w1 = prewarp(f1, fs), w2 = prewarp(f2, fs);
  const double w0_squared = w1 * w2, bandwidth = w2 - w1;
  std::vector<Biquad> sections;
  for (const cd p : prototype_poles(n)) {
    if (p.imag() < -1e-12) continue;  // its conjugate gives the conjugate poles
    const cd pb = p * bandwidth;
    const cd root = std::sqrt(pb * pb - 4.0 * w0_squared);
    const cd s_plus = (pb + root) / 2.0, s_minus = (pb - root) / 2.0;
    if (std::abs(p.imag()) <= 1e-12) {
      // Real prototype pole: its two band-pass poles are a conjugate (or real) pair - one section.
      sections.push_back(section(bilinear(s_plus, fs), bilinear(s_minus, fs), 1.0, 0.0, -1.0));
    } else {
      sections.push_back(section(bilinear(s_plus, fs), std::conj(bilinear(s_plus, fs)), 1.0, 0.0, -1.0));
      sections.push_back(section(bilinear(s_minus, fs), std::conj(bilinear(s_minus, fs)), 1.0, 0.0, -1.0));
    }
  }
  normalize(sections, f_ref, fs);
  return sections;
}

std::vector<Biquad> butterworth_lowpass(int n, double fc, double fs) {
  if (n % 2 != 0 || n < 2) throw Error("low-pass design: the order must be even and >= 2");
  if (!(0.0 < fc && fc < fs / 2.0)) throw Error("low-pass design: cut-off must be in (0, fs/2)");
  const double wc = prewarp(fc, fs);
  std::vector<Biquad> sections;
  for (const cd p : prototype_poles(n)) {
    if (p.imag() < 0.0) continue;
    const cd z = bilinear(p * wc, fs);
    sections.push_back(section(z, std::conj(z), 1.0, 2.0, 1.0));  // zeros (1 + z^-1)^2
  }
  normalize(sections, 0.0, fs);
  return sections;
}

}  // namespace nvh::postproc
