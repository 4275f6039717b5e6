// Circular-arc cams with a radial, in-line roller follower of radius Rr (cam_profile.hpp's convention): the
// paper's eccentric cam and the tangent cam. phi = theta - theta_n is the cam angle from the nose (peak
// lift); both lifts are even in phi.
//
// Eccentric cam (Jafari et al., paper 001, section 2.1, eq. 1): a disc of radius Rd centred at distance e
// (the "lift of the cam lobe" r of eq. 1) from the camshaft axis. The roller's centre (on the follower line)
// is at distance
//   y(phi) = e cos phi + sqrt((Rd + Rr)^2 - (e sin phi)^2)                                    (001 eq. 1)
// from the axis. Its minimum, at phi = pi, is Rd + Rr - e: the base circle of the cam is Rb = Rd - e. The key
// `base_radius` is this Rb (the smallest radius of the cam, as for every profile: rho = Rb + Rr + s); the
// paper's R_b (the disc's radius) is base_radius + eccentricity. Lift s = y - (Rb + Rr), peak 2 e at phi = 0.
//
// Tangent cam (the classic circular-arc cam with straight flanks, as in H. A. Rothbart, Cams: Design,
// Dynamics and Accuracy, Wiley 1956; the formulas below are derived here from the geometry and checked in
// tests/solve/test_cam_profiles.cpp against a construction of the roller's centre that does not use them):
// base circle Rb about the axis, nose circle Rn whose centre lies at distance d on the lobe axis, straight
// flanks tangent to both. The
// roller's centre runs on the outer offset by Rr of this outline: circles of radii Rb + Rr and Rn + Rr joined
// by the flank lines moved out by Rr. The flank's normal makes the angle beta with the lobe axis, d cos beta
// = Rb - Rn (the line n.p = Rb touches both circles). On the ray at angle u = |phi| from the lobe axis, the
// pitch radius rho (lift s = rho - Rb - Rr) is
//   nose   u <= psi_t:       rho = d cos u + sqrt((Rn + Rr)^2 - d^2 sin^2 u)    (the eq. 1 form, e = d)
//   flank  psi_t < u < beta: rho = (Rb + Rr) / cos(beta - u)                    (the line n.p = Rb + Rr)
//   base   u >= beta:        rho = Rb + Rr
// psi_t = atan2((Rn + Rr) sin beta, d + (Rn + Rr) cos beta) is the polar angle of the point where the offset
// flank touches the offset nose circle; beta is where it touches the offset base circle. rho is C1 at both
// junctions (the outline's tangent is continuous); its second derivative jumps there: the acceleration of a
// tangent cam is discontinuous at the flank's ends (the radius of curvature jumps from Rb + Rr or Rn + Rr to
// the flank's infinity), which is physical, not a defect of the formulas. The derivatives below are those of
// each region (the flank's from d/dv sec v = sec v tan v).
#include <cmath>
#include <numbers>
#include <sstream>

#include "common/error.hpp"
#include "solve/cam/profiles.hpp"

namespace nvh::solve::cam {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

std::string mm(double x) {
  std::ostringstream out;
  out.precision(6);
  out << x * 1e3 << " mm";
  return out.str();
}

/// y(phi) = e cos phi + sqrt(a^2 - e^2 sin^2 phi) and its derivatives by phi (001 eq. 1 with a = Rd + Rr).
/// With g = e^2 sin phi cos phi, w = sqrt(a^2 - e^2 sin^2 phi): w' = -g / w, so
///   y' = -e sin phi - g/w,  y'' = -e cos phi - (g'/w + g^2/w^3),
///   y''' = e sin phi - (g''/w + 3 g g'/w^3 + 3 g^3/w^5),  g' = e^2 cos 2 phi, g'' = -2 e^2 sin 2 phi.
Lift circle_offset(double e, double a, double phi) {
  const double sn = std::sin(phi), cs = std::cos(phi);
  const double w = std::sqrt(std::max(a * a - e * e * sn * sn, 0.0));
  const double g = e * e * sn * cs, g1 = e * e * std::cos(2 * phi), g2 = -2 * e * e * std::sin(2 * phi);
  const double w3 = w * w * w;
  Lift y;
  y.s = e * cs + w;
  y.ds = -e * sn - g / w;
  y.dds = -e * cs - (g1 / w + g * g / w3);
  y.ddds = e * sn - (g2 / w + 3 * g * g1 / w3 + 3 * g * g * g / (w3 * w * w));
  return y;
}

/// The lift of an even profile from the pitch radius rho(u), u = |phi| >= 0, and its derivatives by u.
Lift even_lift(const Lift& rho_u, double phi, double pitch_base) {
  const double sign = phi < 0 ? -1.0 : 1.0;
  return {rho_u.s - pitch_base, sign * rho_u.ds, rho_u.dds, sign * rho_u.ddds};
}

class EccentricCam final : public CamProfile {
 public:
  EccentricCam(double rb, double e, double rr, double nose)
      : rb_(rb), e_(e), rr_(rr), nose_(wrap_2pi(nose)) {}
  std::string kind() const override { return "eccentric"; }
  Lift lift(double theta) const override {
    Lift y = circle_offset(e_, rb_ + e_ + rr_, wrap_pi(theta - nose_));
    y.s -= rb_ + rr_;
    return y;
  }
  double base_radius() const override { return rb_; }
  double roller_radius() const override { return rr_; }
  double max_lift() const override { return 2 * e_; }
  double max_lift_angle() const override { return nose_; }

 private:
  double rb_, e_, rr_, nose_;
};

class TangentCam final : public CamProfile {
 public:
  TangentCam(double rb, double rn, double d, double rr, double nose)
      : rb_(rb), rn_(rn), d_(d), rr_(rr), nose_(wrap_2pi(nose)) {
    beta_ = std::acos((rb - rn) / d);
    psi_t_ = std::atan2((rn + rr) * std::sin(beta_), d + (rn + rr) * std::cos(beta_));
  }
  std::string kind() const override { return "tangent"; }
  Lift lift(double theta) const override {
    const double phi = wrap_pi(theta - nose_), u = std::abs(phi);
    const double base = rb_ + rr_;
    Lift rho;
    if (u <= psi_t_) {
      rho = circle_offset(d_, rn_ + rr_, u);
    } else if (u < beta_) {
      const double v = beta_ - u, sec = 1.0 / std::cos(v), tn = std::tan(v);  // d/du = -d/dv
      rho.s = base * sec;
      rho.ds = -base * sec * tn;
      rho.dds = base * sec * (tn * tn + sec * sec);
      rho.ddds = -base * sec * tn * (tn * tn + 5 * sec * sec);
    } else {
      rho.s = base;
    }
    return even_lift(rho, phi, base);
  }
  double base_radius() const override { return rb_; }
  double roller_radius() const override { return rr_; }
  double max_lift() const override { return d_ + rn_ - rb_; }
  double max_lift_angle() const override { return nose_; }

 private:
  double rb_, rn_, d_, rr_, nose_;
  double beta_ = 0, psi_t_ = 0;
};

const input::Range kRadius{0.0, 10.0, true, false};  // m: (0, 10]; no cam or roller is larger
const input::Range kNoseAngle = input::Range::closed(-360.0, 360.0);

}  // namespace

double wrap_pi(double a) {
  return std::remainder(a, 2 * kPi);
}
double wrap_2pi(double a) {
  const double w = std::fmod(a, 2 * kPi);
  return w < 0 ? w + 2 * kPi : w;
}

std::unique_ptr<CamProfile> eccentric_cam(double base_radius, double eccentricity, double roller_radius,
                                          double nose_angle) {
  if (!(base_radius > 0 && eccentricity > 0 && roller_radius > 0))
    throw Error("eccentric cam: base_radius, eccentricity and roller_radius must be > 0");
  return std::make_unique<EccentricCam>(base_radius, eccentricity, roller_radius, nose_angle);
}

std::unique_ptr<CamProfile> tangent_cam(double rb, double rn, double d, double rr, double nose_angle) {
  if (!(rb > 0 && rn > 0 && d > 0 && rr > 0))
    throw Error("tangent cam: base_radius, nose_radius, lobe_distance and roller_radius must be > 0");
  if (!(rn < rb))
    throw Error("tangent cam: the nose radius (" + mm(rn) + ") must be smaller than the base radius (" +
                mm(rb) + ")");
  if (!(d > rb - rn))
    throw Error("tangent cam: the lobe distance (" + mm(d) +
                ") must exceed base_radius - nose_radius = " + mm(rb - rn) +
                " (else the nose does not stand out of the base circle and no flank touches both)");
  return std::make_unique<TangentCam>(rb, rn, d, rr, nose_angle);
}

std::unique_ptr<CamProfile> read_eccentric_cam(const input::Table& t) {
  const double rb = t.number("base_radius", kRadius);
  const double e = t.number("eccentricity", kRadius);
  const double rr = t.number("roller_radius", kRadius);
  const double nose = t.number_or("nose_angle_deg", 0.0, kNoseAngle) * kDeg;
  return eccentric_cam(rb, e, rr, nose);
}

std::unique_ptr<CamProfile> read_tangent_cam(const input::Table& t) {
  const double rb = t.number("base_radius", kRadius);
  const double rn = t.number("nose_radius", kRadius);
  const double d = t.number("lobe_distance", kRadius);
  const double rr = t.number("roller_radius", kRadius);
  const double nose = t.number_or("nose_angle_deg", 0.0, kNoseAngle) * kDeg;
  if (!(rn < rb))
    t.fail("nose_radius",
           "expected a nose radius (" + mm(rn) + ") smaller than the base radius (" + mm(rb) + ")");
  if (!(d > rb - rn))
    t.fail("lobe_distance",
           "expected a lobe distance (" + mm(d) + ") larger than base_radius - nose_radius = " + mm(rb - rn) +
               " (else the nose does not stand out of the base circle and no flank touches both)");
  return tangent_cam(rb, rn, d, rr, nose);
}

}  // namespace nvh::solve::cam
