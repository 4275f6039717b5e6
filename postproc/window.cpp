#include "postproc/window.hpp"

#include <cmath>
#include <numbers>

#include "common/error.hpp"

namespace nvh::postproc {

WindowKind parse_window(const std::string& name) {
  if (name == "rectangular" || name == "rect" || name == "none") return WindowKind::kRectangular;
  if (name == "hann" || name == "hanning") return WindowKind::kHann;
  if (name == "hamming") return WindowKind::kHamming;
  if (name == "flattop" || name == "flat-top") return WindowKind::kFlatTop;
  if (name == "blackman-harris" || name == "blackmanharris") return WindowKind::kBlackmanHarris;
  throw Error("window '" + name + "': expected one of rectangular, hann, hamming, flattop, blackman-harris");
}

std::string to_string(WindowKind kind) {
  switch (kind) {
    case WindowKind::kRectangular:
      return "rectangular";
    case WindowKind::kHann:
      return "hann";
    case WindowKind::kHamming:
      return "hamming";
    case WindowKind::kFlatTop:
      return "flattop (HFT90D)";
    case WindowKind::kBlackmanHarris:
      return "blackman-harris";
  }
  return "?";
}

Window make_window(WindowKind kind, int n) {
  std::vector<double> c;  // cosine-sum coefficients c_k of w[n] = sum_k c_k cos(2 pi k n / N)
  switch (kind) {
    case WindowKind::kRectangular:
      c = {1.0};
      break;
    case WindowKind::kHann:
      c = {0.5, -0.5};
      break;
    case WindowKind::kHamming:
      c = {0.54, -0.46};
      break;
    case WindowKind::kBlackmanHarris:
      c = {0.35875, -0.48829, 0.14128, -0.01168};
      break;
    case WindowKind::kFlatTop:
      c = {1.0, -1.942604, 1.340318, -0.440811, 0.043097};
      break;
  }
  Window window;
  window.kind = kind;
  window.w.resize(n);
  for (int i = 0; i < n; ++i) {
    double v = 0.0;
    for (std::size_t k = 0; k < c.size(); ++k)
      v += c[k] * std::cos(2.0 * std::numbers::pi * static_cast<double>(k) * i / n);
    window.w[i] = v;
    window.sum += v;
    window.sum_squares += v * v;
  }
  return window;
}

}  // namespace nvh::postproc
