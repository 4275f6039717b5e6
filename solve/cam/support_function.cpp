// The support function of a cam surface and the convexity check (support_function.hpp: the equations).
#include "solve/cam/support_function.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "common/error.hpp"
#include "solve/cam/profiles.hpp"

namespace nvh::solve::cam {

Support support(const CamProfile& profile, double phi) {
  const double base = profile.base_radius() + profile.roller_radius();
  // G(psi) and G'(psi) of the header; rho' = -s'(-psi), rho'' = s''(-psi) (cam_profile.cpp).
  const auto g_of = [&](double psi, double& slope) {
    const Lift l = profile.lift(-psi);
    const double rho = base + l.s, d1 = -l.ds, d2 = l.dds;
    slope = (rho * rho + 2 * d1 * d1 - rho * d2) / (rho * rho + d1 * d1);
    return psi - std::atan2(d1, rho) - phi;
  };
  double lo = phi - 0.5 * std::numbers::pi, hi = phi + 0.5 * std::numbers::pi, psi = phi;
  for (int it = 0; it < 200; ++it) {
    double slope = 0;
    const double g = g_of(psi, slope);
    if (g == 0) break;
    (g < 0 ? lo : hi) = psi;
    double next = slope > 0 ? psi - g / slope : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // Newton left the bracket: bisect
    const double step = next - psi;
    psi = next;
    if (std::abs(step) < 1e-14 || hi - lo < 1e-15) break;
  }
  const PitchPoint p = pitch_point(profile, psi);
  const double c = std::cos(phi), s = std::sin(phi);
  Support out;
  out.psi = psi;
  out.h = p.x * c + p.y * s - profile.roller_radius();
  out.dh = -p.x * s + p.y * c;
  out.radius = p.radius_of_curvature - profile.roller_radius();
  out.ddh = out.radius - out.h;
  return out;
}

void check_flat_follower_fits(const CamProfile& profile, const std::string& what, int samples) {
  if (samples < 1) throw Error(what + ": check_flat_follower_fits needs at least one sample");
  // The pitch curve's curvature kappa = (rho^2 + 2 rho'^2 - rho rho'') / (rho^2 + rho'^2)^(3/2)
  // (cam_profile.cpp); the surface, its inner offset by Rr, is convex where kappa >= 0 (and kappa < 1 / Rr,
  // the undercut check_roller_fits makes). Round-off on a straight flank leaves |kappa| ~ 1e-16 / Rb.
  const double base = profile.base_radius() + profile.roller_radius();
  double worst = 0, worst_psi = 0;
  for (int k = 0; k < samples; ++k) {
    const double psi = 2 * std::numbers::pi * k / samples;
    const Lift l = profile.lift(-psi);
    const double rho = base + l.s, d1 = -l.ds, d2 = l.dds;
    const double kappa = (rho * rho + 2 * d1 * d1 - rho * d2) / std::pow(rho * rho + d1 * d1, 1.5);
    if (kappa < worst) {
      worst = kappa;
      worst_psi = psi;
    }
  }
  if (worst * base > -1e-9) return;
  const double theta_deg = wrap_2pi(-worst_psi) * 180.0 / std::numbers::pi;
  const double radius = 1.0 / worst - profile.roller_radius();
  throw Error(what +
              ": a flat-faced follower needs a convex cam, but the cam surface is concave at cam angle " +
              format_number(theta_deg, 5) + " deg: its radius of curvature h + h'' there is " +
              format_number(radius * 1e3) +
              " mm (must stay positive; the face would bridge the hollow). Use a roller follower, a larger "
              "base circle or a gentler lift");
}

}  // namespace nvh::solve::cam
