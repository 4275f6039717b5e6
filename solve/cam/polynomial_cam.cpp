// The polynomial cam profile: a symmetric valve-lift event of quintic pieces, C2 everywhere (lift, velocity
// and acceleration continuous; the jerk jumps at the junctions), base circle (s = 0) elsewhere.
//
// With phi = theta - theta_n (the event's centre, peak lift L), a = ramp angle, b = rise angle, and
// v = a + b - |phi| the angle since the opening ramp's start (by symmetry, until the closing ramp's end):
//   v <= 0          base circle:   s = 0
//   0 <= v <= a     opening ramp:  s = g_r(v) from (s, s', s'') = (0, 0, 0) to (H, V, 0)
//   a <= v <= a + b rise:          s = g_u(v) from (H, V, 0) to (L, 0, 0)
// H = ramp height, V = ramp velocity (m/rad). Each piece is the quintic of its end values (p0, p0', p0'') ->
// (p1, p1', p1'') over a width w (quintic Hermite interpolation; e.g. R. L. Norton, Cam Design and
// Manufacturing Handbook, 2nd ed., Industrial Press 2009, on polynomial cam functions): with x = (v - v0) /
// w, dp = p1 - p0, V0 = p0' w, V1 = p1' w, A0 = p0'' w^2, A1 = p1'' w^2,
//   g = p0 + V0 x + A0/2 x^2 + c3 x^3 + c4 x^4 + c5 x^5,
//   c3 = 10 dp - 6 V0 - 4 V1 - (3 A0 - A1)/2,  c4 = -15 dp + 8 V0 + 7 V1 + (3 A0 - 2 A1)/2,
//   c5 = 6 dp - 3 V0 - 3 V1 - (A0 - A1)/2.
// The default ramp velocity is V = 2 H / a: the ramp is then g_r = H (2 x^3 - x^4) (c5 = 0), whose
// acceleration H (12 x - 12 x^2) / a^2 is a single positive pulse ending at 0 - the ramp takes up the lash
// with the velocity rising monotonically to its end value (the mean velocity H / a would need a negative
// acceleration at the ramp's end). The top of the rise has s' = s'' = 0 (as asked in issue 13): the pitch
// curve's radius of curvature there is rho = Rb + Rr + L, like a circle about the axis. A closing event is
// the mirror image, so the closing ramp ends at the seat with velocity V as the opening one starts.
//
// Checks: the event 2 (a + b) fits in 360 deg; H < L; the lift increases on the opening side (s' >= 0 on a
// fine grid: a ramp velocity far from the rise's mean slope makes the quintic overshoot); read_cam_profile
// then runs check_roller_fits.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "common/error.hpp"
#include "solve/cam/profiles.hpp"

namespace nvh::solve::cam {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;


/// The quintic of the header comment over [v0, v0 + w].
class Quintic {
 public:
  Quintic() = default;
  Quintic(double v0, double w, double p0, double d0, double a0, double p1, double d1, double a1)
      : v0_(v0), w_(w) {
    const double dp = p1 - p0, V0 = d0 * w, V1 = d1 * w, A0 = a0 * w * w, A1 = a1 * w * w;
    c_ = {p0,
          V0,
          A0 / 2,
          10 * dp - 6 * V0 - 4 * V1 - (3 * A0 - A1) / 2,
          -15 * dp + 8 * V0 + 7 * V1 + (3 * A0 - 2 * A1) / 2,
          6 * dp - 3 * V0 - 3 * V1 - (A0 - A1) / 2};
  }
  /// g and its derivatives by v.
  Lift operator()(double v) const {
    const double x = (v - v0_) / w_;
    const auto& c = c_;
    const double g = c[0] + x * (c[1] + x * (c[2] + x * (c[3] + x * (c[4] + x * c[5]))));
    const double g1 = c[1] + x * (2 * c[2] + x * (3 * c[3] + x * (4 * c[4] + x * 5 * c[5])));
    const double g2 = 2 * c[2] + x * (6 * c[3] + x * (12 * c[4] + x * 20 * c[5]));
    const double g3 = 6 * c[3] + x * (24 * c[4] + x * 60 * c[5]);
    return {g, g1 / w_, g2 / (w_ * w_), g3 / (w_ * w_ * w_)};
  }

 private:
  double v0_ = 0, w_ = 1;
  std::array<double, 6> c_{};
};

class PolynomialCam final : public CamProfile {
 public:
  explicit PolynomialCam(const PolynomialEvent& e) : e_(e), nose_(wrap_2pi(e.nose_angle)) {
    const double a = e.ramp_angle, b = e.rise_angle;
    ramp_ = Quintic(0.0, a, 0, 0, 0, e.ramp_height, e.ramp_velocity, 0);
    rise_ = Quintic(a, b, e.ramp_height, e.ramp_velocity, 0, e.lift, 0, 0);
  }
  std::string kind() const override { return "polynomial"; }
  Lift lift(double theta) const override {
    const double phi = wrap_pi(theta - nose_);
    const double v = e_.ramp_angle + e_.rise_angle - std::abs(phi);
    if (v <= 0) return {};
    const Lift g = v <= e_.ramp_angle ? ramp_(v) : rise_(v);
    const double sign = phi < 0 ? -1.0 : 1.0;  // dv/dtheta = -sign
    return {g.s, -sign * g.ds, g.dds, -sign * g.ddds};
  }
  double base_radius() const override { return e_.base_radius; }
  double roller_radius() const override { return e_.roller_radius; }
  double max_lift() const override { return e_.lift; }
  double max_lift_angle() const override { return nose_; }

  /// The opening side's smallest velocity dg/dv (m/rad) and where (v, rad).
  std::pair<double, double> min_opening_velocity() const {
    double worst = std::numeric_limits<double>::infinity(), at = 0;
    const int n = 2000;
    const double span = e_.ramp_angle + e_.rise_angle;
    for (int k = 1; k < n; ++k) {
      const double v = span * k / n;
      const double d = (v <= e_.ramp_angle ? ramp_(v) : rise_(v)).ds;
      if (d < worst) worst = d, at = v;
    }
    return {worst, at};
  }

 private:
  PolynomialEvent e_;
  double nose_;
  Quintic ramp_, rise_;
};

const input::Range kRadius{0.0, 10.0, true, false};  // m
const input::Range kNoseAngle = input::Range::closed(-360.0, 360.0);
const input::Range kEventAngle = input::Range::open(0.0, 180.0);

}  // namespace

std::unique_ptr<CamProfile> polynomial_cam(const PolynomialEvent& given) {
  PolynomialEvent e = given;
  if (!(e.lift > 0 && e.rise_angle > 0 && e.ramp_angle > 0 && e.ramp_height >= 0 && e.base_radius > 0 &&
        e.roller_radius > 0))
    throw Error("polynomial cam: lift, rise and ramp angles and the radii must be > 0, ramp_height >= 0");
  if (2 * (e.ramp_angle + e.rise_angle) > 2 * kPi)
    throw Error("polynomial cam: the event, 2 (ramp_deg + rise_deg) = " +
                format_number(2 * (e.ramp_angle + e.rise_angle) / kDeg) + " deg, does not fit in 360 deg");
  if (!(e.ramp_height < e.lift))
    throw Error("polynomial cam: the ramp height (" + format_number(e.ramp_height * 1e3) +
                " mm) must be smaller than the lift (" + format_number(e.lift * 1e3) + " mm)");
  if (e.ramp_velocity < 0) e.ramp_velocity = 2 * e.ramp_height / e.ramp_angle;
  auto cam = std::make_unique<PolynomialCam>(e);
  const auto [velocity, v] = cam->min_opening_velocity();
  if (velocity < -1e-12 * e.lift / (e.ramp_angle + e.rise_angle))
    throw Error("polynomial cam: with the ramp velocity " + format_number(e.ramp_velocity) +
                " m/rad the lift falls on the opening side (velocity " + format_number(velocity) + " m/rad at " +
                format_number(v / kDeg) + " deg after the ramp's start): choose a ramp velocity nearer the " +
                "ramp's and the rise's mean slopes (default 2 ramp_height / ramp_deg)");
  return cam;
}

std::unique_ptr<CamProfile> read_polynomial_cam(const input::Table& t) {
  PolynomialEvent e;
  e.lift = t.number("lift", input::Range{0.0, 1.0, true, false});
  e.rise_angle = t.number("rise_deg", kEventAngle) * kDeg;
  e.ramp_angle = t.number("ramp_deg", kEventAngle) * kDeg;
  e.ramp_height = t.number("ramp_height", input::Range::closed(0.0, 1.0));
  e.ramp_velocity = t.optional_number("ramp_velocity", input::Range::closed(0.0, 10.0)).value_or(-1.0);
  e.base_radius = t.number("base_radius", kRadius);
  e.roller_radius = t.number("roller_radius", kRadius);
  e.nose_angle = t.number_or("nose_angle_deg", 0.0, kNoseAngle) * kDeg;
  if (2 * (e.ramp_angle + e.rise_angle) > 2 * kPi)
    t.fail("rise_deg",
           "the event, 2 (ramp_deg + rise_deg) = " + format_number(2 * (e.ramp_angle + e.rise_angle) / kDeg) +
               " deg, does not fit in 360 deg");
  if (!(e.ramp_height < e.lift))
    t.fail("ramp_height", "expected a ramp height (" + format_number(e.ramp_height * 1e3) +
                              " mm) smaller than the lift (" + format_number(e.lift * 1e3) + " mm)");
  try {
    return polynomial_cam(e);
  } catch (const Error& err) {
    t.fail("ramp_velocity", err.message());
  }
}

}  // namespace nvh::solve::cam
