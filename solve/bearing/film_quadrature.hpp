#pragma once
// Integrals over the film of the closed-form bearings, exact to round-off.
//
// The short- and long-bearing forces are integrals of trigonometric polynomials divided by powers of the
// film thickness h = c (1 - eps cos(psi)), psi measured from the minimum film. Sommerfeld's substitution
//   1 - eps cos(psi) = (1 - eps^2) / (1 + eps cos(gamma)),   d psi = sqrt(1 - eps^2) / (1 + eps cos(gamma)) d
//   gamma
// (tan(gamma/2) = sqrt((1+eps)/(1-eps)) tan(psi/2); Sommerfeld 1904, see e.g. Hamrock, Schmid and Jacobson,
// Fundamentals of Fluid Film Lubrication, 2nd ed. 2004, sec. 10.3) turns every integrand
// cos^m(psi) sin^n(psi) / h^k with k >= m + n + 1 into a trigonometric polynomial in gamma of degree <= k
// - 1. A 32-point Gauss-Legendre rule integrates such a polynomial of degree <= 4 over any interval of length
// <= 2 pi to round-off (error < 1e-14), whatever the eccentricity: this is the closed form evaluated exactly.
#include <array>
#include <functional>

namespace nvh::bearing {

/// One point of the film: shell angle theta (as cos, sin), film thickness h (m) and the quadrature weight
/// (rad: the point stands for weight * d theta).
struct FilmPoint {
  double cos_theta;
  double sin_theta;
  double h;
  double weight;
};

/// Calls `add` at the quadrature points of [theta_begin, theta_end] (theta_end > theta_begin,
/// theta_end - theta_begin <= 2 pi) for the film h = c - ex cos(theta) - ey sin(theta), |e| < c.
/// Exact for integrands q(cos theta, sin theta) / h^k with q a polynomial of degree <= k - 1 <= 4.
void integrate_film(double c, double ex, double ey, double theta_begin, double theta_end,
                    const std::function<void(const FilmPoint&)>& add);

/// Nodes and weights of the n-point Gauss-Legendre rule on [-1, 1] (Newton on P_n; Golub-Welsch not needed).
template <int N>
std::array<std::array<double, 2>, N> gauss_legendre();

}  // namespace nvh::bearing
