#pragma once
// The ideal cam joint (`[[joint]] type = "cam"`, docs/valvetrain.md section 2): the roller's centre (marker
// i, on any follower) held on the cam's pitch curve (marker j, on the camshaft: origin on the cam's axis, z_j
// the axis, x_j the zero of the lift's cam angle; cam_profile.hpp). The kinematic cam for every follower - a
// translating lifter, a pivoting lever - where the lift driver (constraint.hpp) only moves a slider: the
// contact of `roller-cam` with an infinitely stiff, bilateral law, whose reaction (the multiplier) is the
// normal force the cam must exert, negative where a real follower would lift off.
//
// One equation, the signed distance of the roller's centre c = A_j^T (p_i - p_j) (its x-y components) from
// the pitch curve (cam::pitch_foot):
//   phi = g(c) = n . (c - P(psi*)) = 0,                                                        (CJ1)
// with the distance field's gradient n (the outward normal at the foot, global axes), so that with r = p_i -
// p_j
//   phi' = n . (v_i - v_j - omega_j x r) = n . v_i - n . v_j - (r x n) . omega_j.             (CJ2)
// No phi_t: the cam turns with its body (a speed driver on the camshaft). The roller's own spin is not a
// coordinate (it rolls without slip and carries no inertia); the follower may move along z_j freely.
#include <memory>

#include "solve/cam/cam_profile.hpp"
#include "solve/constraint.hpp"

namespace nvh::solve {

std::unique_ptr<Constraint> make_cam_joint(std::shared_ptr<const cam::CamProfile> profile);

}  // namespace nvh::solve
