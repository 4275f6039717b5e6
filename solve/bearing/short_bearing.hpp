#pragma once
// The short journal bearing (Ocvirk 1952; Dubois and Ocvirk, NACA Report 1157, 1953) with the
// half-Sommerfeld (Guembel) condition, for any motion of the journal: closed form.
//
// Dropping the circumferential pressure flow (L/D -> 0), the Reynolds equation integrates twice across the
// width (z from the mid-plane, p = 0 at z = +-L/2):
//   p(theta, z) = 6 mu G(theta) / h^3 (z^2 - L^2/4),   G = omega_m dh/dtheta + dh/dt,   omega_m = (wj + ws)/2
// and p is kept where it is positive, i.e. where G < 0: a half circle (beta - pi, beta) since
// G = A sin(theta) - B cos(theta) = rho sin(theta - beta), A = omega_m ex - ey_dot, B = omega_m ey + ex_dot.
// Force on the journal:  F = mu R L^3 int_{G<0} G n / h^3 d theta,  n = (cos theta, sin theta).
// Its derivatives need no boundary terms (G = 0 at both ends):
//   dF/dex = mu R L^3 int (omega_m sin / h^3 + 3 G cos / h^4) n,  dF/dex_dot = -mu R L^3 int cos n / h^3, ...
// Friction: Couette shear over the full circle plus the pressure-gradient shear (docs/bearing.md).
// Side flow: Q = -R L int_{G<0} G d theta = 2 rho R L.
#include "solve/bearing/bearing.hpp"

namespace nvh::bearing {

/// Film force, torques, flows and the analytic Jacobian of the short bearing. Supply pressure, holes and
/// grooves are ignored (the closed form assumes a flooded film); feed_flow is set to the side flow.
FilmResult evaluate_short(const BearingSpec& spec, const Kinematics& k, Detail detail = Detail::kFull);

}  // namespace nvh::bearing
