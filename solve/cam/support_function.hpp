#pragma once
// The support function of a cam surface: what a flat-faced (mushroom) follower sees of a cam profile
// (cam_profile.hpp), used by solve/elements/flat_face_cam.cpp.
//
// A flat face whose normal points from the cam towards the face in the direction u(phi) = [cos phi, sin phi]
// of the cam's frame touches the cam where the profile's tangent is parallel to the face. The distance from
// the cam's axis to that tangent line is the support function h(phi) = max over the surface of X . u(phi)
// (R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed., Industrial Press 2009, section 7.4, the
// flat-faced follower; the support function of a convex curve: e.g. H. Guggenheimer, Differential Geometry,
// 1963, section 2-3). Its derivatives carry the follower's kinematics:
//   h(phi)                   the face's distance from the axis (the follower's lift is h - Rb),
//   h'(phi) = X . u'(phi)    the contact point's offset along the face from the line through the axis along
//   u, h + h'' = R_c            the cam surface's radius of curvature at the contact point,
// so a flat follower needs a convex cam (R_c > 0 everywhere; check_flat_follower_fits).
//
// The cam surface is the inner offset by Rr of the pitch curve P(psi) = rho(psi) [cos psi, sin psi] (the
// profile's convention), so h = P(psi*) . u - Rr at the pitch curve's point psi* whose outward normal is u.
// The normal's angle there is psi - atan2(rho', rho), which differs from psi by less than pi/2, so psi* is
// the root in (phi - pi/2, phi + pi/2) of
//   G(psi) = psi - atan2(rho'(psi), rho(psi)) - phi,   G' = (rho^2 + 2 rho'^2 - rho rho'') / (rho^2 + rho'^2)
// (G' = |P'| kappa >= 0 on a convex curve: G is monotonic), found by Newton's method safeguarded by
// bisection. A straight flank (kappa = 0, R_c infinite) is allowed: there h' jumps as the face passes
// parallel to it (the follower's velocity jumps; a flat follower suits curved flanks).
#include <string>

#include "solve/cam/cam_profile.hpp"

namespace nvh::solve::cam {

/// The support function of the cam surface in the direction phi (rad, in the cam's frame) and its
/// derivatives by phi: m, m/rad, m/rad^2; the surface's radius of curvature at the contact point (m, h +
/// h''); the polar angle psi* of the pitch curve's point there (rad).
struct Support {
  double h = 0, dh = 0, ddh = 0;
  double radius = 0;
  double psi = 0;
};
Support support(const CamProfile& profile, double phi);

/// Checks on `samples` points of the pitch curve that the cam surface is convex (its curvature >= 0, up to
/// round-off on straight flanks). Throws nvh::Error naming `what`, the cam angle (deg, the lift's angle of
/// the most concave point, as check_roller_fits) and the surface's radius of curvature there (mm, negative).
void check_flat_follower_fits(const CamProfile& profile, const std::string& what, int samples = 3600);

}  // namespace nvh::solve::cam
