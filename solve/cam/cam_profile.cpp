// The pitch curve of a cam profile, the undercut check and the profile reader (cam_profile.hpp).
//
// Pitch curve P(psi) = rho(psi) [cos psi, sin psi], rho(psi) = Rb + Rr + s(-psi), so rho' = -s'(-psi),
// rho'' = s''(-psi). With e = [cos psi, sin psi] and e' = [-sin psi, cos psi]:
//   P' = rho' e + rho e',   P'' = (rho'' - rho) e + 2 rho' e'.
// The curve runs counter-clockwise about the cam's axis, so its outward normal is P' turned clockwise,
// n = [y', -x'] / |P'|. The signed curvature kappa = (x' y'' - y' x'') / |P'|^3 of a plane curve becomes,
// with P' and P'' above, the classic formula for a curve in polar coordinates:
//   kappa = (rho^2 + 2 rho'^2 - rho rho'') / (rho^2 + rho'^2)^(3/2),   R = 1 / kappa,
// > 0 where the curve is convex (bends towards the axis), < 0 where it is concave, inf on a straight piece
// (the tangent cam's flank: there the numerator vanishes up to round-off, and R is merely huge).
// The cam surface is the inner offset of the pitch curve by Rr: its radius of curvature is R - Rr with the
// same sign convention. A convex piece with R <= Rr would need a surface of radius <= 0: the surface
// undercuts (forms a cusp) and the roller cannot follow the lift (check_roller_fits).
#include "solve/cam/cam_profile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "common/error.hpp"
#include "solve/cam/profiles.hpp"

namespace nvh::solve::cam {

std::string format_number(double x, int precision) {
  std::ostringstream out;
  out.precision(precision);
  out << x;
  return out.str();
}

PitchPoint pitch_point(const CamProfile& profile, double psi) {
  const Lift l = profile.lift(-psi);
  const double rho = profile.base_radius() + profile.roller_radius() + l.s;
  const double d1 = -l.ds, d2 = l.dds;
  const double c = std::cos(psi), s = std::sin(psi);
  PitchPoint p;
  p.x = rho * c;
  p.y = rho * s;
  p.dx = d1 * c - rho * s;
  p.dy = d1 * s + rho * c;
  p.ddx = (d2 - rho) * c - 2 * d1 * s;
  p.ddy = (d2 - rho) * s + 2 * d1 * c;
  const double speed = std::hypot(p.dx, p.dy);  // = sqrt(rho^2 + rho'^2) > 0 as rho >= Rb + Rr > 0
  p.nx = p.dy / speed;
  p.ny = -p.dx / speed;
  const double den = rho * rho + 2 * d1 * d1 - rho * d2;
  p.radius_of_curvature = den == 0 ? std::numeric_limits<double>::infinity() : speed * speed * speed / den;
  // R = N / D, N = (rho^2 + rho'^2)^(3/2), D = rho^2 + 2 rho'^2 - rho rho'' (den): dN = 3 sqrt(rho^2 +
  // rho'^2) rho' (rho + rho''), dD = 2 rho rho' + 3 rho' rho'' - rho rho''' (rho''' = -s''' as rho(psi) = ..
  // + s(-psi)).
  if (den != 0) {
    const double d3 = -l.ddds;
    const double dn = 3 * speed * d1 * (rho + d2), dd = 2 * rho * d1 + 3 * d1 * d2 - rho * d3;
    p.radius_derivative = (dn * den - speed * speed * speed * dd) / (den * den);
  }
  return p;
}

PitchFoot pitch_foot(const CamProfile& profile, double cx, double cy) {
  PitchFoot f;
  f.psi = std::atan2(cy, cx);
  f.point = pitch_point(profile, f.psi);
  for (int it = 0; it < 30; ++it) {
    const PitchPoint& pp = f.point;
    const double ex = pp.x - cx, ey = pp.y - cy;
    const double g = ex * pp.dx + ey * pp.dy;
    const double dg = pp.dx * pp.dx + pp.dy * pp.dy + ex * pp.ddx + ey * pp.ddy;
    double step = dg > 0 ? -g / dg : -g / (pp.dx * pp.dx + pp.dy * pp.dy);
    step = std::clamp(step, -0.2, 0.2);
    f.psi += step;
    f.point = pitch_point(profile, f.psi);
    if (std::abs(step) < 1e-14) break;
  }
  f.gap = f.point.nx * (cx - f.point.x) + f.point.ny * (cy - f.point.y);
  return f;
}

double surface_radius_of_curvature(const CamProfile& profile, double psi) {
  return pitch_point(profile, psi).radius_of_curvature - profile.roller_radius();
}

void check_roller_fits(const CamProfile& profile, const std::string& what, int samples) {
  if (samples < 1) throw Error(what + ": check_roller_fits needs at least one sample");
  const double rr = profile.roller_radius();
  double worst = std::numeric_limits<double>::infinity(), worst_psi = 0;
  for (int k = 0; k < samples; ++k) {
    const double psi = 2 * std::numbers::pi * k / samples;
    const double r = pitch_point(profile, psi).radius_of_curvature;
    if (r > 0 && r < worst) {
      worst = r;
      worst_psi = psi;
    }
  }
  if (worst > rr) return;
  const double theta_deg = wrap_2pi(-worst_psi) * 180.0 / std::numbers::pi;
  throw Error(
      what + ": the roller does not fit the cam at cam angle " + format_number(theta_deg, 5) +
      " deg: the pitch curve's radius of curvature there is " + format_number(worst * 1e3) +
      " mm, not larger than the roller's radius " + format_number(rr * 1e3) +
      " mm (the cam surface would undercut; use a smaller roller, a larger base circle or a gentler lift)");
}

std::unique_ptr<CamProfile> read_cam_profile(const input::Table& t, const std::filesystem::path& base,
                                             std::vector<std::filesystem::path>& inputs) {
  const std::string kind = t.choice("profile", {"tangent", "eccentric", "table", "polynomial"});
  std::unique_ptr<CamProfile> profile;
  std::string what = "the " + kind + " cam profile";
  try {
    if (kind == "tangent") {
      profile = read_tangent_cam(t);
    } else if (kind == "eccentric") {
      profile = read_eccentric_cam(t);
    } else if (kind == "table") {
      profile = read_table_cam(t, base, inputs);
      if (t.has("file")) what += " of " + (base / t.string("file")).string();
    } else {
      profile = read_polynomial_cam(t);
    }
  } catch (const Error& e) {
    if (!e.where().file.empty()) throw;
    t.fail("profile", e.message());  // not expected: the readers locate their errors
  }
  try {
    check_roller_fits(*profile, what);
  } catch (const Error& e) {
    t.fail("roller_radius", e.message());
  }
  return profile;
}

}  // namespace nvh::solve::cam
