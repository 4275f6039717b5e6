#pragma once
// Cam profiles for roller followers: the follower lift s(theta) against cam angle and the pitch curve it
// defines (the path of the roller's centre in the cam's frame).
//
// Convention (docs/valvetrain.md, section 1): a cam profile is the lift s(theta) (m) that a radial, in-line
// translating roller follower of radius Rr sees as the cam turns by theta (rad) about its +z axis, the
// follower lying on the cam marker's +x axis at theta = 0. In the cam's own frame (the marker's x-y plane)
// the roller's centre then runs on the pitch curve
//   P(psi) = rho(psi) [cos psi, sin psi],   rho(psi) = Rb + Rr + s(-psi),
// psi the polar angle about +z from +x. The cam surface is the inner offset of the pitch curve by Rr. Any
// other follower (a pivoting roller lever, an offset lifter) uses the same pitch curve: its roller's centre
// is kept at distance >= 0 from it (solve/elements/roller_cam.cpp).
//
// A profile answers lift(theta) with the derivatives by theta (the cam's kinematics: velocity = s' omega,
// acceleration = s'' omega^2 at constant speed omega) and is periodic in 2 pi. Which profiles exist and their
// closed forms: tangent_cam.cpp (the paper's eccentric circular cam, 001 eq. 1, and the tangent cam of
// circular arcs and straight flanks), table_cam.cpp (a tabulated lift), polynomial_cam.cpp (polynomial flanks
// with opening and closing ramps for the lash). Constructors and per-profile readers: profiles.hpp.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "common/input.hpp"

namespace nvh::solve::cam {

/// The lift and its derivatives by the cam angle: m, m/rad, m/rad^2, m/rad^3.
struct Lift {
  double s = 0, ds = 0, dds = 0, ddds = 0;
};

class CamProfile {
 public:
  virtual ~CamProfile() = default;
  virtual std::string kind() const = 0;
  /// The lift at cam angle theta (rad, any value: periodic in 2 pi).
  virtual Lift lift(double theta) const = 0;
  /// The base circle radius Rb (m) and the roller radius Rr (m) the lift is defined for.
  virtual double base_radius() const = 0;
  virtual double roller_radius() const = 0;
  /// Largest lift (m) and the cam angle where it occurs (rad, in [0, 2 pi)).
  virtual double max_lift() const = 0;
  virtual double max_lift_angle() const = 0;
};

/// A point of the pitch curve in the cam's frame (m): rho(psi) [cos psi, sin psi], with d/dpsi and d2/dpsi2,
/// its unit outward normal and its signed radius of curvature (m; > 0 convex, < 0 concave, inf on a line).
struct PitchPoint {
  double x = 0, y = 0;
  double dx = 0, dy = 0;
  double ddx = 0, ddy = 0;
  double nx = 0, ny = 0;
  double radius_of_curvature = 0;
  double radius_derivative = 0;  // d(radius_of_curvature)/dpsi (m/rad); 0 where the radius is infinite
};
PitchPoint pitch_point(const CamProfile& profile, double psi);

/// The foot of a point c = (cx, cy) of the cam's frame (m) on the pitch curve: the point P(psi) whose normal
/// passes through c, found by Newton on f(psi) = (P - c) . P'(psi) = 0 from psi = atan2(cy, cx) (a convex
/// pitch curve near c converges in a few steps; the step is limited to 0.2 rad so that a poor start cannot
/// jump to another lobe). `gap` = n . (c - P) is the signed distance of c from the curve (> 0 outside).
struct PitchFoot {
  double psi = 0;  // the foot's polar angle (rad)
  PitchPoint point;
  double gap = 0;  // m
};
PitchFoot pitch_foot(const CamProfile& profile, double cx, double cy);

/// The radius of curvature (m) of the cam surface under the roller: that of the pitch curve minus Rr
/// (> 0 convex, < 0 concave).
double surface_radius_of_curvature(const CamProfile& profile, double psi);

/// Checks a profile on a fine grid of `samples` angles: the cam surface must not undercut (the pitch curve's
/// convex radius of curvature larger than the roller's radius). Throws nvh::Error naming `what`, the cam
/// angle (deg) of the worst point and both radii.
void check_roller_fits(const CamProfile& profile, const std::string& what, int samples = 3600);

/// The profile of a scene or component table: `profile = "tangent" | "eccentric" | "table" | "polynomial"`
/// and its keys (docs/valvetrain.md). Relative file names start at `base`; files read are appended to
/// `inputs`.
std::unique_ptr<CamProfile> read_cam_profile(const input::Table& t, const std::filesystem::path& base,
                                             std::vector<std::filesystem::path>& inputs);

}  // namespace nvh::solve::cam
