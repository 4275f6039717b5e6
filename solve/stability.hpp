#pragma once
// Linear stability of the integrators on one mode y' = lambda y, z = lambda h (docs/verification.md,
// "Stability map"): the theory that bench/stability_map.py measured solve against, for `solve --advise`.
//
// BDF-k (IDA at order k): the roots xi of  sum_{j=1..k} (1/j) (1 - 1/xi)^j = z  (Hairer & Wanner, Solving
// ODEs II, sec. V.1); a mode grows when max |xi| > 1. BDF 1-2 are A-stable; BDF 3-5 are A(alpha)-stable with
// alpha = 86.03, 73.35, 51.84 deg: a mode of damping ratio zeta (z at the angle arccos(zeta) from the
// negative real axis) is stable at every step only if zeta > cos(alpha) = 0.0698, 0.287, 0.618.
// Generalized-alpha as solve implements it (Jansen, Whiting & Hulbert 2000, first-order form):
//   (alpha_m - gamma alpha_f z) xi^2 + (1 - 2 alpha_m - z ((1 - gamma) alpha_f + gamma (1 - alpha_f))) xi
//     - (1 - alpha_m) - z (1 - gamma)(1 - alpha_f) = 0,
// alpha_m = (3 - rho_inf) / (2 (1 + rho_inf)), alpha_f = 1 / (1 + rho_inf), gamma = 1/2 + alpha_m - alpha_f.
#include <complex>
#include <optional>
#include <utility>

namespace nvh::solve {

/// The largest |xi| of BDF-k (k = 1..5) at z = lambda h: the growth of the mode per step.
double bdf_growth(int k, std::complex<double> z);
/// The largest |xi| of solve's generalized-alpha at z = lambda h.
double generalized_alpha_growth(double rho_inf, std::complex<double> z);
/// z = lambda h of a mode of natural frequency omega (rad/s) and damping ratio zeta (< 1) at step h (s).
std::complex<double> mode_z(double omega, double zeta, double h);
/// cos(alpha_k): BDF-k is stable at every step on modes damped above this ratio (0 for k <= 2).
double bdf_critical_damping(int k);
/// The first interval of omega h in (0, 1e3] where BDF-k makes a mode of damping ratio zeta grow (max |xi| >
/// 1 + 1e-12), edges to 1e-6 relative; a band reaching below 1e-2 is reported from 0. Growth below 1e-12 per
/// step counts as stable (undamped BDF4 grows by O((omega h)^5): its band is reported from 0.012). None when
/// the mode is stable at every step.
std::optional<std::pair<double, double>> bdf_unstable_band(int k, double zeta);

}  // namespace nvh::solve
