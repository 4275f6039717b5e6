#include "solve/stability.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Eigenvalues>

#include "common/error.hpp"

namespace nvh::solve {

double bdf_growth(int k, std::complex<double> z) {
  if (k < 1 || k > 5) throw Error("bdf_growth: order " + std::to_string(k) + " is not in 1..5");
  // With u = 1 - 1/xi the characteristic equation is the polynomial sum_{j=1..k} u^j / j - z = 0; its roots
  // (the eigenvalues of the companion matrix of the monic form) give xi = 1 / (1 - u).
  Eigen::MatrixXcd companion = Eigen::MatrixXcd::Zero(k, k);
  const double lead = 1.0 / k;  // coefficient of u^k
  for (int j = 1; j < k; ++j) companion(j, j - 1) = 1.0;
  for (int j = 0; j < k; ++j) {
    const std::complex<double> c = j == 0 ? -z : std::complex<double>(1.0 / j);  // coefficient of u^j
    companion(j, k - 1) = -c / lead;
  }
  const Eigen::VectorXcd u = Eigen::ComplexEigenSolver<Eigen::MatrixXcd>(companion, false).eigenvalues();
  double growth = 0;
  for (Eigen::Index r = 0; r < u.size(); ++r) {
    const std::complex<double> d = 1.0 - u[r];
    growth = std::max(growth, std::abs(d) == 0 ? INFINITY : 1.0 / std::abs(d));
  }
  return growth;
}

double generalized_alpha_growth(double rho_inf, std::complex<double> z) {
  const double am = (3 - rho_inf) / (2 * (1 + rho_inf)), af = 1 / (1 + rho_inf), g = 0.5 + am - af;
  const std::complex<double> a = am - g * af * z;
  const std::complex<double> b = 1 - 2 * am - z * ((1 - g) * af + g * (1 - af));
  const std::complex<double> c = -(1 - am) - z * (1 - g) * (1 - af);
  const std::complex<double> root = std::sqrt(b * b - 4.0 * a * c);
  return std::max(std::abs((-b + root) / (2.0 * a)), std::abs((-b - root) / (2.0 * a)));
}

std::complex<double> mode_z(double omega, double zeta, double h) {
  const double z = std::clamp(zeta, -1.0, 1.0);
  return omega * h * std::complex<double>(-z, std::sqrt(1 - z * z));
}

double bdf_critical_damping(int k) {
  // cos of the A(alpha) angles (Hairer & Wanner II, Table V.2.3): 86.03, 73.35, 51.84 deg.
  constexpr double kAlphaDeg[] = {90, 90, 86.03, 73.35, 51.84};
  if (k < 1 || k > 5) throw Error("bdf_critical_damping: order " + std::to_string(k) + " is not in 1..5");
  return k <= 2 ? 0.0 : std::cos(kAlphaDeg[k - 1] * std::numbers::pi / 180);
}

std::optional<std::pair<double, double>> bdf_unstable_band(int k, double zeta) {
  constexpr double kTol = 1e-12;
  const auto grows = [&](double wh) { return bdf_growth(k, mode_z(1.0, zeta, wh)) > 1 + kTol; };
  const auto edge = [&](double stable, double unstable) {  // bisection in log(omega h)
    for (int it = 0; it < 60 && std::abs(unstable / stable - 1) > 1e-7; ++it) {
      const double mid = std::sqrt(stable * unstable);
      (grows(mid) ? unstable : stable) = mid;
    }
    return std::sqrt(stable * unstable);
  };
  // Scan 1e-2 .. 1e3 at 40 points per decade (the bands are decades wide), then refine the edges.
  const int n = 200;
  const auto at = [&](int i) { return 1e-2 * std::pow(10.0, 5.0 * i / n); };
  int first = -1;
  for (int i = 0; i <= n && first < 0; ++i)
    if (grows(at(i))) first = i;
  if (first < 0) return std::nullopt;
  int last = first;
  while (last < n && grows(at(last + 1))) ++last;
  const double lower = first == 0 ? 0.0 : edge(at(first - 1), at(first));
  const double upper = last == n ? at(n) : edge(at(last + 1), at(last));
  return std::make_pair(lower, upper);
}

}  // namespace nvh::solve
