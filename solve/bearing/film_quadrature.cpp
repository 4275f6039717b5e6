#include "solve/bearing/film_quadrature.hpp"

#include <cmath>
#include <numbers>

namespace nvh::bearing {

template <int N>
std::array<std::array<double, 2>, N> gauss_legendre() {
  std::array<std::array<double, 2>, N> rule{};
  for (int i = 0; i < N; ++i) {
    // Tricomi's initial guess, then Newton on P_N(x) by the three-term recurrence.
    double x = std::cos(std::numbers::pi * (i + 0.75) / (N + 0.5));
    double dp = 1;
    for (int iter = 0; iter < 100; ++iter) {
      double p0 = 1, p1 = x;
      for (int n = 2; n <= N; ++n) {
        const double p2 = ((2.0 * n - 1) * x * p1 - (n - 1.0) * p0) / n;
        p0 = p1;
        p1 = p2;
      }
      dp = N * (x * p1 - p0) / (x * x - 1);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    rule[i] = {x, 2.0 / ((1 - x * x) * dp * dp)};
  }
  return rule;
}

template std::array<std::array<double, 2>, 32> gauss_legendre<32>();

namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

/// gamma(psi), continuous and increasing over all reals (one branch of the tangent relation per turn).
double gamma_of_psi(double psi, double eps) {
  const double turns = std::round(psi / kTwoPi);
  const double p = psi - kTwoPi * turns;  // in [-pi, pi]
  const double g = 2 * std::atan(std::sqrt((1 + eps) / (1 - eps)) * std::tan(0.5 * p));
  // At p = +-pi the tangent overflows to +-inf or a huge number; atan gives +-pi/2 either way.
  return g + kTwoPi * turns;
}

}  // namespace

void integrate_film(double c, double ex, double ey, double theta_begin, double theta_end,
                    const std::function<void(const FilmPoint&)>& add) {
  static const auto rule = gauss_legendre<32>();
  const double e = std::hypot(ex, ey);
  const double eps = e / c;
  const double phi = e > 0 ? std::atan2(ey, ex) : 0.0;  // angle of the minimum film
  const double cphi = std::cos(phi), sphi = std::sin(phi);
  const double s = std::sqrt(1 - eps * eps);
  const double g0 = gamma_of_psi(theta_begin - phi, eps);
  const double g1 = gamma_of_psi(theta_end - phi, eps);
  const double mid = 0.5 * (g0 + g1), half = 0.5 * (g1 - g0);
  for (const auto& [x, w] : rule) {
    const double g = mid + half * x;
    const double cg = std::cos(g), sg = std::sin(g);
    const double d = 1 + eps * cg;
    const double cpsi = (cg + eps) / d;
    const double spsi = s * sg / d;
    FilmPoint point;
    point.cos_theta = cpsi * cphi - spsi * sphi;
    point.sin_theta = spsi * cphi + cpsi * sphi;
    point.h = c * (1 - eps * eps) / d;
    point.weight = w * half * s / d;  // d theta = d psi = sqrt(1 - eps^2) / (1 + eps cos gamma) d gamma
    add(point);
  }
}

}  // namespace nvh::bearing
