#pragma once
// The infinitely long journal bearing (Sommerfeld 1904) with the half-Sommerfeld (Guembel) condition, for
// any motion of the journal: the pressure in closed form, kept where it is positive.
//
// Without axial flow the Reynolds equation integrates once around the circumference:
//   h^3 dp/dtheta = 12 mu R^2 (Gamma(theta) + C),   Gamma = -A cos(theta) - B sin(theta) (an antiderivative
//   of G,
// G = omega_m dh/dtheta + dh/dt = A sin - B cos as in short_bearing.hpp); C makes p periodic:
//   C = -oint Gamma / h^3 / oint 1 / h^3,  and p = 0 at the maximum film (Sommerfeld's gauge).
// Every integral is exact by the Sommerfeld substitution (film_quadrature.hpp). The positive region is
// bounded by zeros of p, found on a 720-point subdivision and refined by Newton; over it, integration by
// parts turns the force into int p' N with N = (sin, -cos):
//   F = 12 mu R^3 L int_{p>0} (Gamma + C) (sin theta, -cos theta) / h^3 d theta.
// The Jacobian is by central differences of this closed form (relative step 1e-6): the positive region
// moves with e, which makes the analytic derivative long for a model kept for comparison.
// Per unit width this is the mid-plane of a very wide bearing; side flow is zero.
#include "solve/bearing/bearing.hpp"

namespace nvh::bearing {

FilmResult evaluate_long(const BearingSpec& spec, const Kinematics& k);

/// The long-bearing pressure (Pa, full Sommerfeld: negative values kept) at the shell angle theta.
double long_bearing_pressure(const BearingSpec& spec, const Kinematics& k, double theta);

}  // namespace nvh::bearing
