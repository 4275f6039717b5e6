#include "postproc/iir.hpp"

#include <cmath>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif
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

CascadeLanes4::CascadeLanes4(const std::vector<std::vector<Biquad>>& cascades) {
  if (cascades.size() > static_cast<std::size_t>(kLanes)) throw Error("CascadeLanes4: more than 4 cascades");
  for (int k = 0; k < kSections; ++k) {
    for (int l = 0; l < kLanes; ++l) {
      Biquad q;  // identity unless lane l has a k-th section
      if (l < static_cast<int>(cascades.size())) {
        if (cascades[l].size() > static_cast<std::size_t>(kSections))
          throw Error("CascadeLanes4: more than 4 sections in a cascade");
        if (k < static_cast<int>(cascades[l].size())) q = cascades[l][k];
      }
      b0_[k][l] = q.b0;
      b1_[k][l] = q.b1;
      b2_[k][l] = q.b2;
      a1_[k][l] = q.a1;
      a2_[k][l] = q.a2;
    }
  }
}

namespace {

// Four doubles processed as one (GCC/Clang vector extension: one AVX or two SSE2 operations per line).
using Lanes = double __attribute__((vector_size(4 * sizeof(double))));

// Denormal numbers (a band-pass ringing down to 1e-310) are up to 100 times slower on x86; flush them to
// zero while filtering (MXCSR FTZ and DAZ bits), restoring the caller's mode afterwards.
class FlushDenormals {
 public:
#if defined(__SSE__)
  FlushDenormals() : saved_(_mm_getcsr()) {
    _mm_setcsr(saved_ | 0x8040);
  }
  ~FlushDenormals() {
    _mm_setcsr(saved_);
  }

 private:
  unsigned saved_;
#endif
};

}  // namespace

// Software-pipelined: in step i, section k filters what section k-1 produced in step i-1, so the four
// sections (x four lanes) are independent within a step and the processor overlaps them; the cascade's
// output is delayed by kSections - 1 samples, which no mean square or decimation notices. Compiled twice
// (x86-64-v3 with AVX2/FMA, and the baseline) and chosen at load time by the CPU.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("arch=x86-64-v3", "default")))
#endif
std::size_t
CascadeLanes4::process(const double* x, std::size_t n, double* square_sum, int output_lane,
                       double* decimated) {
  FlushDenormals flush;
  // Coefficients and state as lane vectors in locals, so they stay in registers across the sample loop.
  Lanes b0[kSections], b1[kSections], b2[kSections], a1[kSections], a2[kSections], s1[kSections],
      s2[kSections];
  Lanes carry[kSections];  // carry[k]: output of section k in the previous step (input of section k + 1)
  for (int k = 0; k < kSections; ++k)
    for (int l = 0; l < kLanes; ++l) {
      b0[k][l] = b0_[k][l];
      b1[k][l] = b1_[k][l];
      b2[k][l] = b2_[k][l];
      a1[k][l] = a1_[k][l];
      a2[k][l] = a2_[k][l];
      s1[k][l] = s1_[k][l];
      s2[k][l] = s2_[k][l];
      carry[k][l] = carry_[k][l];
    }
  const Lanes zero = {0.0, 0.0, 0.0, 0.0};
  Lanes sums = zero;
  std::size_t written = 0;
  bool keep = keep_next_;
  for (std::size_t i = 0; i < n; ++i) {
    Lanes in[kSections];
    in[0] = zero + x[i];
    for (int k = 1; k < kSections; ++k) in[k] = carry[k - 1];
    for (int k = 0; k < kSections; ++k) {  // direct form II transposed, all sections and lanes at once
      const Lanes y = b0[k] * in[k] + s1[k];
      s1[k] = b1[k] * in[k] - a1[k] * y + s2[k];
      s2[k] = b2[k] * in[k] - a2[k] * y;
      carry[k] = y;
    }
    const Lanes v = carry[kSections - 1];
    sums += v * v;
    if (output_lane >= 0) {
      if (keep) decimated[written++] = v[output_lane];
      keep = !keep;
    }
  }
  keep_next_ = keep;
  for (int k = 0; k < kSections; ++k)
    for (int l = 0; l < kLanes; ++l) {
      s1_[k][l] = s1[k][l];
      s2_[k][l] = s2[k][l];
      carry_[k][l] = carry[k][l];
    }
  if (square_sum != nullptr)
    for (int l = 0; l < kLanes; ++l) square_sum[l] += sums[l];
  return written;
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
