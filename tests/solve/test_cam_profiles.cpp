// The cam profiles (solve/cam): each lift against a reference that does not use the code under test.
//
//   eccentric  - the paper's eq. 1 (001, section 2.1) written out here; derivatives by central differences of
//   it; tangent    - the roller's centre found by brute-force geometry: bisection along the follower line for
//   the
//                point at distance Rr from the cam outline, the outline being the convex hull of the base and
//                nose discs (the union of the discs interpolated between them), its distance found by a
//                golden section search; derivatives by central differences of that lift;
//   pitch_point - radii of curvature of known circles (base, nose, the eccentric disc) and lines (flanks);
//   check_roller_fits - a cos^4 lift event whose nose radius of curvature is worked out here by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "common/error.hpp"
#include "common/input.hpp"
#include "solve/cam/cam_profile.hpp"

namespace nvh::solve::cam {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

std::unique_ptr<CamProfile> read(const std::string& text) {
  const auto doc = input::Document::parse(text, "cam.toml");
  std::vector<std::filesystem::path> inputs;
  return read_cam_profile(doc.root(), NVH_SOURCE_DIR, inputs);
}

std::string error_of(const std::string& text) {
  try {
    read(text);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

double wrap(double a) {
  const double w = std::fmod(a, 2 * kPi);
  return w < 0 ? w + 2 * kPi : w;
}

/// The number after `tag` in `msg` (NaN if absent).
double number_after(const std::string& msg, const std::string& tag) {
  const auto at = msg.find(tag);
  if (at == std::string::npos) return std::nan("");
  return std::stod(msg.substr(at + tag.size()));
}

/// Central differences of f at x: first and second derivative (step h), third (5-point stencil, step h3).
struct Differences {
  double d1, d2, d3;
};
Differences differences(const std::function<double(double)>& f, double x, double h, double h2, double h3) {
  return {(f(x + h) - f(x - h)) / (2 * h), (f(x + h2) - 2 * f(x) + f(x - h2)) / (h2 * h2),
          (f(x + 2 * h3) - 2 * f(x + h3) + 2 * f(x - h3) - f(x - 2 * h3)) / (2 * h3 * h3 * h3)};
}

// ============================================================================ eccentric: the paper's eq. 1

TEST(CamProfile, EccentricIsThePapersEquation1) {
  // base_radius is the cam's smallest radius; the paper's R_b (the disc's radius) is base_radius +
  // eccentricity.
  const double rb = 0.015, e = 0.004, rf = 0.008, nose = 30 * kDeg;
  const auto cam = read(
      "profile = \"eccentric\"\nbase_radius = 0.015\neccentricity = 0.004\nroller_radius = 0.008\n"
      "nose_angle_deg = 30\n");
  EXPECT_EQ(cam->kind(), "eccentric");
  const double paper_rb = rb + e;
  // 001 eq. 1: y_c(theta) = r cos(theta) + sqrt((R_b + R_f)^2 - (r sin(theta))^2), theta from the nose;
  // its minimum (theta = pi) is R_b + R_f - r: the lift is y_c minus that.
  const auto eq1 = [&](double theta) {
    const double th = theta - nose;
    return e * std::cos(th) + std::sqrt((paper_rb + rf) * (paper_rb + rf) - std::pow(e * std::sin(th), 2)) -
           (paper_rb + rf - e);
  };
  double err_s = 0, err_v = 0, err_a = 0, err_j = 0;
  for (int k = -360; k <= 720; ++k) {
    const double theta = k * kDeg;
    const Lift l = cam->lift(theta);
    const Differences fd = differences(eq1, theta, 1e-3, 1e-3, 1e-2);
    err_s = std::max(err_s, std::abs(l.s - eq1(theta)));
    err_v = std::max(err_v, std::abs(l.ds - fd.d1));
    err_a = std::max(err_a, std::abs(l.dds - fd.d2));
    err_j = std::max(err_j, std::abs(l.ddds - fd.d3));
  }
  // Lift: round-off (lifts of 8 mm). Derivatives: the differences' truncation, h^2/6 |s'''| ~ 7e-10 m/rad,
  // h^2/12 |s''''| ~ 3e-10 m/rad^2 (h = 1e-3), h^2/4 |s^(5)| ~ 1e-7 m/rad^3 (h = 1e-2); amplitude e = 4 mm.
  EXPECT_LT(err_s, 1e-15);
  EXPECT_LT(err_v, 2e-9);
  EXPECT_LT(err_a, 2e-9);
  EXPECT_LT(err_j, 5e-7);
  std::printf("eccentric: |ds| %.3g m, |dv| %.3g m/rad, |da| %.3g m/rad^2, |dj| %.3g m/rad^3\n", err_s, err_v,
              err_a, err_j);
  EXPECT_DOUBLE_EQ(cam->max_lift(), 2 * e);
  EXPECT_NEAR(cam->max_lift(), eq1(nose), 1e-15);
  EXPECT_NEAR(cam->lift(nose + kPi).s, 0.0, 1e-15);
  EXPECT_NEAR(cam->max_lift_angle(), nose, 1e-15);
  EXPECT_DOUBLE_EQ(cam->base_radius(), rb);
  EXPECT_DOUBLE_EQ(cam->roller_radius(), rf);
}

// ================================================================ tangent cam: brute-force roller centre

struct TangentGeometry {
  double rb = 0.020, rn = 0.008, d = 0.017, rr = 0.009, nose = 40 * kDeg;

  /// Distance (signed inside) from p to the convex hull of the base disc (0, rb) and the nose disc ((d, 0),
  /// rn), lobe frame: min over t in [0, 1] of |p - t (d, 0)| - ((1 - t) rb + t rn), a convex function of t.
  double outline_distance(double px, double py) const {
    const auto f = [&](double t) { return std::hypot(px - t * d, py) - ((1 - t) * rb + t * rn); };
    double a = 0, b = 1;
    const double g = (std::sqrt(5.0) - 1) / 2;
    double c = b - g * (b - a), e = a + g * (b - a), fc = f(c), fe = f(e);
    for (int k = 0; k < 200 && b - a > 1e-15; ++k) {
      if (fc < fe) {
        b = e, e = c, fe = fc, c = b - g * (b - a), fc = f(c);
      } else {
        a = c, c = e, fc = fe, e = a + g * (b - a), fe = f(e);
      }
    }
    return std::min({f(0.0), f(1.0), f(0.5 * (a + b))});
  }
  /// The roller's centre distance from the axis on the follower line at angle phi from the lobe axis: the
  /// point at distance rr from the outline (bisection, the distance increasing outwards along the ray).
  double centre(double phi) const {
    double lo = 0.5 * rb, hi = d + rn + rr + 0.01;
    for (int k = 0; k < 200 && hi - lo > 0; ++k) {
      const double mid = 0.5 * (lo + hi);
      if (mid == lo || mid == hi) break;
      (outline_distance(mid * std::cos(phi), mid * std::sin(phi)) < rr ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }
  double lift(double theta) const { return centre(theta - nose) - (rb + rr); }
  // Where the regions meet (to keep differences off the acceleration's jumps): the flank meets the base
  // circle at polar angle beta (its normal; the line n.p = rb touching the nose disc: d cos beta = rb - rn),
  // and the offset nose circle at the polar angle of (d, 0) + (rn + rr) n.
  double beta() const { return std::acos((rb - rn) / d); }
  double psi_t() const { return std::atan2((rn + rr) * std::sin(beta()), d + (rn + rr) * std::cos(beta())); }
};

const std::string kTangent =
    "profile = \"tangent\"\nbase_radius = 0.020\nnose_radius = 0.008\nlobe_distance = 0.017\n"
    "roller_radius = 0.009\nnose_angle_deg = 40\n";

TEST(CamProfile, TangentCamMatchesTheRollerCentreFoundByGeometry) {
  const TangentGeometry g;
  const auto cam = read(kTangent);
  EXPECT_EQ(cam->kind(), "tangent");
  const auto f = [&](double theta) { return g.lift(theta); };
  double err_s = 0, err_v = 0, err_a = 0, err_j = 0;
  int compared = 0;
  for (int k = 0; k < 3600; ++k) {
    const double theta = 0.1 * k * kDeg;
    const Lift l = cam->lift(theta);
    err_s = std::max(err_s, std::abs(l.s - g.lift(theta)));
    const double u = std::abs(std::remainder(theta - g.nose, 2 * kPi));
    const double h3 = 2e-3;
    if (std::abs(u - g.beta()) < 3 * h3 || std::abs(u - g.psi_t()) < 3 * h3) continue;  // the jumps of s''
    const Differences fd = differences(f, theta, 1e-4, 4e-4, h3);
    err_v = std::max(err_v, std::abs(l.ds - fd.d1));
    err_a = std::max(err_a, std::abs(l.dds - fd.d2));
    err_j = std::max(err_j, std::abs(l.ddds - fd.d3));
    ++compared;
  }
  std::printf("tangent (%d points): |ds| %.3g m, |dv| %.3g m/rad, |da| %.3g m/rad^2, |dj| %.3g m/rad^3\n",
              compared, err_s, err_v, err_a, err_j);
  // Lift: round-off of both constructions. Differences (|s'''| <= 0.5 m/rad^3, |s^(4)|, |s^(5)| of order 10):
  // truncation ~ 1e-9 m/rad, ~1e-7 m/rad^2, ~4e-5 m/rad^3, round-off 1e-17 m / h^k below those.
  EXPECT_LT(err_s, 1e-12);
  EXPECT_LT(err_v, 1e-8);
  EXPECT_LT(err_a, 1e-6);
  EXPECT_LT(err_j, 1e-3);
  EXPECT_GT(compared, 3000);
  EXPECT_NEAR(cam->max_lift(), g.d + g.rn - g.rb, 1e-15);
  EXPECT_NEAR(cam->max_lift(), g.lift(g.nose), 1e-12);
  EXPECT_NEAR(cam->max_lift_angle(), g.nose, 1e-15);
}

TEST(CamProfile, TangentCamAccelerationJumpsWhereTheFlankMeetsTheCircles) {
  // s'' just inside and outside the flank's ends: the base side has s'' = 0, the flank's end at the base
  // circle rho'' = (Rb + Rr) (from sec'' = sec (tan^2 + sec^2) at v = 0); the nose side jumps too.
  const TangentGeometry g;
  const auto cam = read(kTangent);
  const double eps = 1e-9;
  EXPECT_NEAR(cam->lift(g.nose + g.beta() + eps).dds, 0.0, 1e-15);
  EXPECT_NEAR(cam->lift(g.nose + g.beta() - eps).dds, g.rb + g.rr, 1e-6);
  const double jump = cam->lift(g.nose + g.psi_t() + eps).dds - cam->lift(g.nose + g.psi_t() - eps).dds;
  EXPECT_GT(std::abs(jump), 1e-3);
  // s and s' are continuous there (to the size of eps times the next derivative).
  for (double u : {g.beta(), g.psi_t()}) {
    EXPECT_NEAR(cam->lift(g.nose + u + eps).s, cam->lift(g.nose + u - eps).s, 1e-10);   // 2 eps |s'|
    EXPECT_NEAR(cam->lift(g.nose + u + eps).ds, cam->lift(g.nose + u - eps).ds, 1e-9);  // 2 eps |s''|
  }
}

// ============================================================================================ pitch_point

TEST(CamProfile, PitchCurveRadiiOfCurvatureOfTheTangentCam) {
  const TangentGeometry g;
  const auto cam = read(kTangent);
  // Cam-frame angle psi of cam angle theta: psi = -theta; the lobe axis lies at psi = -nose.
  const double lobe = -g.nose;
  const double base_r = g.rb + g.rr, nose_r = g.rn + g.rr;
  double err_base = 0, err_nose = 0, flank_min = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= 200; ++k) {
    const double f = k / 200.0;
    const double base_u = g.beta() + 1e-6 + f * (2 * kPi - 2 * g.beta() - 2e-6);
    const double nose_u = (2 * f - 1) * (g.psi_t() - 1e-6);
    const double flank_u = g.psi_t() + 1e-6 + f * (g.beta() - g.psi_t() - 2e-6);
    err_base = std::max(err_base, std::abs(pitch_point(*cam, lobe + base_u).radius_of_curvature - base_r));
    const PitchPoint pn = pitch_point(*cam, lobe + nose_u);
    err_nose = std::max(err_nose, std::abs(pn.radius_of_curvature - nose_r));
    // On the nose circle: distance nose_r from the nose centre, the normal along the radius.
    const double cx = g.d * std::cos(lobe), cy = g.d * std::sin(lobe);
    EXPECT_NEAR(std::hypot(pn.x - cx, pn.y - cy), nose_r, 1e-15);
    EXPECT_NEAR(pn.nx, (pn.x - cx) / nose_r, 1e-12);
    EXPECT_NEAR(pn.ny, (pn.y - cy) / nose_r, 1e-12);
    for (double s : {1.0, -1.0})
      flank_min = std::min(flank_min, std::abs(pitch_point(*cam, lobe + s * flank_u).radius_of_curvature));
  }
  std::printf("tangent pitch curve: |R - (Rb+Rr)| %.3g m, |R - (Rn+Rr)| %.3g m, flank min |R| %.3g m\n",
              err_base, err_nose, flank_min);
  EXPECT_LT(err_base, 1e-15);
  EXPECT_LT(err_nose, 1e-12);  // round-off of rho'' ~ 1e-17 / (rho^2 - rho rho'') ...
  EXPECT_GT(flank_min, 1e3);   // a line: inf, or the round-off of a vanishing denominator
  // The surface under the roller: the base circle Rb, the nose circle Rn.
  EXPECT_NEAR(surface_radius_of_curvature(*cam, lobe + kPi), g.rb, 1e-15);
  EXPECT_NEAR(surface_radius_of_curvature(*cam, lobe), g.rn, 1e-12);
}

TEST(CamProfile, PitchCurveOfTheEccentricCamIsACircleAboutTheDiscCentre) {
  const double rb = 0.015, e = 0.004, rr = 0.008, nose = 30 * kDeg;
  const auto cam = read(
      "profile = \"eccentric\"\nbase_radius = 0.015\neccentricity = 0.004\nroller_radius = 0.008\n"
      "nose_angle_deg = 30\n");
  // The disc's centre at distance e on the lobe axis (psi = -nose); the pitch curve: radius rb + e + rr about
  // it.
  const double cx = e * std::cos(-nose), cy = e * std::sin(-nose), radius = rb + e + rr;
  double err = 0;
  for (int k = 0; k < 360; ++k) {
    const double psi = k * kDeg;
    const PitchPoint p = pitch_point(*cam, psi);
    EXPECT_NEAR(std::hypot(p.x - cx, p.y - cy), radius, 1e-15);
    EXPECT_NEAR(std::atan2(p.y, p.x), std::remainder(psi, 2 * kPi), 1e-14);
    EXPECT_NEAR(p.nx, (p.x - cx) / radius, 1e-13);
    EXPECT_NEAR(p.ny, (p.y - cy) / radius, 1e-13);
    // First and second derivatives by psi against central differences of the point itself.
    const double h = 1e-4;
    const PitchPoint a = pitch_point(*cam, psi + h), b = pitch_point(*cam, psi - h);
    EXPECT_NEAR(p.dx, (a.x - b.x) / (2 * h), 1e-10);
    EXPECT_NEAR(p.dy, (a.y - b.y) / (2 * h), 1e-10);
    EXPECT_NEAR(p.ddx, (a.x - 2 * p.x + b.x) / (h * h), 1e-7);
    EXPECT_NEAR(p.ddy, (a.y - 2 * p.y + b.y) / (h * h), 1e-7);
    err = std::max(err, std::abs(p.radius_of_curvature - radius));
  }
  std::printf("eccentric pitch curve: |R - (Rb + e + Rr)| %.3g m\n", err);
  EXPECT_LT(err, 1e-15);
}

// ===================================================================================== check_roller_fits

/// s = L cos^4(pi phi / W) for |phi| < W/2 (phi from the nose), 0 elsewhere; C3. At the nose s = L,
/// s' = 0 and s'' = -4 L (pi/W)^2 (cos^4 x = 1 - 2 x^2 + ...).
class Cos4Cam final : public CamProfile {
 public:
  Cos4Cam(double lift, double width, double rb, double rr, double nose)
      : l_(lift), w_(width), rb_(rb), rr_(rr), nose_(nose) {}
  std::string kind() const override { return "cos4"; }
  Lift lift(double theta) const override {
    const double phi = std::remainder(theta - nose_, 2 * kPi);
    if (std::abs(phi) >= w_ / 2) return {};
    const double k = kPi / w_, c = std::cos(k * phi), s = std::sin(k * phi);
    return {l_ * c * c * c * c, -4 * l_ * k * c * c * c * s,
            l_ * k * k * (12 * c * c * s * s - 4 * c * c * c * c),
            l_ * k * k * k * (-24 * c * s * s * s + 40 * c * c * c * s)};
  }
  double base_radius() const override { return rb_; }
  double roller_radius() const override { return rr_; }
  double max_lift() const override { return l_; }
  double max_lift_angle() const override { return nose_; }

 private:
  double l_, w_, rb_, rr_, nose_;
};

TEST(CamProfile, RollerTooLargeForTheNoseIsAnUndercutNamingTheAngleAndRadii) {
  const double lift = 0.010, width = 140 * kDeg, rb = 0.005, rr = 0.010, nose = 90 * kDeg;
  // Nose of the pitch curve: rho = rb + rr + L, rho' = 0, rho'' = -4 L (pi/W)^2: R = rho^2 / (rho - rho'').
  const double rho = rb + rr + lift, rho2 = -4 * lift * std::pow(kPi / width, 2);
  const double r_nose = rho * rho / (rho - rho2);
  ASSERT_LT(r_nose, rr);  // 6.9 mm < 10 mm
  const Cos4Cam cam(lift, width, rb, rr, nose);
  EXPECT_NEAR(pitch_point(cam, -nose).radius_of_curvature, r_nose, 1e-15);
  try {
    check_roller_fits(cam, "the test cam");
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("the test cam"), std::string::npos) << msg;
    EXPECT_NEAR(number_after(msg, "at cam angle "), 90.0, 0.1) << msg;
    EXPECT_NEAR(number_after(msg, "radius of curvature there is "), r_nose * 1e3, 1e-4) << msg;
    EXPECT_NEAR(number_after(msg, "roller's radius "), 10.0, 1e-9) << msg;
  }
  // A smaller roller (R = 4.24 mm > 3 mm at the nose) or a larger base circle (13.9 mm > 10 mm) fits.
  EXPECT_NO_THROW(check_roller_fits(Cos4Cam(lift, width, rb, 0.003, nose), "the test cam"));
  EXPECT_NO_THROW(check_roller_fits(Cos4Cam(lift, width, 0.018, rr, nose), "the test cam"));
}

TEST(CamProfile, CircularArcCamsAlwaysFitTheirRoller) {
  EXPECT_NO_THROW(check_roller_fits(*read(kTangent), "tangent"));
  // A roller much larger than the cam still fits a convex circular-arc cam (its pitch radii exceed Rr).
  EXPECT_NO_THROW(
      read("profile = \"tangent\"\nbase_radius = 0.010\nnose_radius = 0.001\nlobe_distance = 0.012\n"
           "roller_radius = 0.05\n"));
}

// ============================================================================================ reader errors

TEST(CamProfile, ReaderErrorsNameTheKey) {
  std::string msg = error_of("profile = \"tangential\"\n");
  EXPECT_NE(msg.find("cam.toml:1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("tangent"), std::string::npos) << msg;
  msg = error_of(
      "profile = \"tangent\"\nbase_radius = 0.02\nnose_radius = 0.02\nlobe_distance = 0.01\n"
      "roller_radius = 0.009\n");
  EXPECT_NE(msg.find("cam.toml:3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("nose_radius"), std::string::npos) << msg;
  msg = error_of(
      "profile = \"tangent\"\nbase_radius = 0.02\nnose_radius = 0.008\nlobe_distance = 0.01\n"
      "roller_radius = 0.009\n");
  EXPECT_NE(msg.find("cam.toml:4"), std::string::npos) << msg;
  EXPECT_NE(msg.find("lobe_distance"), std::string::npos) << msg;
  EXPECT_NE(msg.find("stand out"), std::string::npos) << msg;
  msg =
      error_of("profile = \"eccentric\"\nbase_radius = 0.02\neccentricity = -0.001\nroller_radius = 0.009\n");
  EXPECT_NE(msg.find("eccentricity"), std::string::npos) << msg;
  msg = error_of("profile = \"eccentric\"\nbase_radius = nan\neccentricity = 0.001\nroller_radius = 0.009\n");
  EXPECT_NE(msg.find("base_radius"), std::string::npos) << msg;
  msg = error_of("profile = \"eccentric\"\nbase_radius = 0.02\neccentricity = 0.001\n");
  EXPECT_NE(msg.find("roller_radius"), std::string::npos) << msg;
}

TEST(CamProfile, ReaderLeavesUnknownKeysToTheCaller) {
  // The caller (an element) reads its own keys and calls finish(): the profile's keys are marked known.
  const auto doc = input::Document::parse(kTangent + "i = \"cam.m\"\n", "cam.toml");
  std::vector<std::filesystem::path> inputs;
  const auto t = doc.root();
  read_cam_profile(t, ".", inputs);
  try {
    t.finish();
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown key 'i'"), std::string::npos) << e.what();
  }
  t.accept("i");
  EXPECT_NO_THROW(t.finish());
}

// ============================================================================================ table profile

/// A TOML table cam of `f` (m) sampled every `step_deg` from 0 (inclusive) to 360 (exclusive), lifts in mm.
std::string table_text(const std::function<double(double)>& f, double step_deg, double rb, double rr) {
  std::string text = "profile = \"table\"\nlift_scale = 1e-3\nbase_radius = " + std::to_string(rb) +
                     "\nroller_radius = " + std::to_string(rr) + "\ntable = [\n";
  char buf[96];
  for (int k = 0; k * step_deg < 360 - 1e-9; ++k) {
    std::snprintf(buf, sizeof buf, "[%.17g, %.17g],\n", k * step_deg, f(k * step_deg * kDeg) * 1e3);
    text += buf;
  }
  return text + "]\n";
}

struct SplineErrors {
  double s = 0, v = 0, a = 0;
};
SplineErrors table_errors(const CamProfile& cam, const CamProfile& exact) {
  SplineErrors e;
  for (int k = 0; k < 7200; ++k) {
    const double theta = 0.05 * k * kDeg;
    const Lift l = cam.lift(theta), x = exact.lift(theta);
    e.s = std::max(e.s, std::abs(l.s - x.s));
    e.v = std::max(e.v, std::abs(l.ds - x.ds));
    e.a = std::max(e.a, std::abs(l.dds - x.dds));
  }
  return e;
}

TEST(CamProfile, TableOfASmoothLiftIsInterpolatedToTheSplinesErrorBounds) {
  const double lift = 0.010, width = 140 * kDeg, rb = 0.018, rr = 0.010, nose = 90 * kDeg;
  const Cos4Cam exact(lift, width, rb, rr, nose);
  const auto f = [&](double theta) { return exact.lift(theta).s; };
  const auto cam = read(table_text(f, 1.0, rb, rr));
  const auto coarse = read(table_text(f, 2.0, rb, rr));
  EXPECT_EQ(cam->kind(), "table");
  const SplineErrors e1 = table_errors(*cam, exact), e2 = table_errors(*coarse, exact);
  // Cubic spline error bounds (C. A. Hall, W. W. Meyer, J. Approx. Theory 16 (1976) 105-122), M4 = max
  // |s^(4)|: |s - S| <= 5/384 h^4 M4, |s' - S'| <= 1/24 h^3 M4, |s'' - S''| <= 3/8 h^2 M4; M4 = 40 L (pi/W)^4
  // for cos^4 (cos^4 x = (3 + 4 cos 2x + cos 4x) / 8). h = 1 deg: 1.3e-9 m, 2.4e-7 m/rad, 1.2e-4 m/rad^2.
  const double m4 = 40 * lift * std::pow(kPi / width, 4), h = kDeg;
  std::printf("table h = 1 deg: |ds| %.3g m (bound %.3g), |dv| %.3g m/rad (%.3g), |da| %.3g m/rad^2 (%.3g)\n",
              e1.s, 5.0 / 384 * std::pow(h, 4) * m4, e1.v, std::pow(h, 3) / 24 * m4, e1.a,
              3.0 / 8 * h * h * m4);
  std::printf("table h = 2 deg: |ds| %.3g m, |dv| %.3g m/rad, |da| %.3g m/rad^2; ratios %.1f %.1f %.1f\n",
              e2.s, e2.v, e2.a, e2.s / e1.s, e2.v / e1.v, e2.a / e1.a);
  EXPECT_LT(e1.s, 5.0 / 384 * std::pow(h, 4) * m4);
  EXPECT_LT(e1.v, std::pow(h, 3) / 24 * m4);
  EXPECT_LT(e1.a, 3.0 / 8 * h * h * m4);
  // Convergence: halving h divides the errors by about 16, 8 and 4.
  EXPECT_GT(e2.s / e1.s, 10.0);
  EXPECT_GT(e2.v / e1.v, 5.0);
  EXPECT_GT(e2.a / e1.a, 3.0);
  EXPECT_NEAR(cam->max_lift(), lift, 1e-9);
  EXPECT_NEAR(cam->max_lift_angle(), nose, 1e-3);  // s'' = -0.066 m/rad^2: 1e-9 m of error moves it ~2e-4 rad
  EXPECT_NEAR(cam->lift(nose + 2 * kPi).s, cam->lift(nose).s, 1e-15);
  EXPECT_NEAR(cam->lift(nose - 6 * kPi).s, cam->lift(nose).s, 1e-15);
}

TEST(CamProfile, TableFromACsvFileWithNamedColumnsAndAClosingRow) {
  const double lift = 0.010, width = 140 * kDeg, rb = 0.018, rr = 0.010, nose = 90 * kDeg;
  const Cos4Cam exact(lift, width, rb, rr, nose);
  const auto dir = std::filesystem::path(NVH_BINARY_DIR) / "tests" / "solve" / "cam_profile_files";
  std::filesystem::create_directories(dir);
  {
    std::FILE* out = std::fopen((dir / "lift.csv").string().c_str(), "w");
    ASSERT_NE(out, nullptr);
    std::fprintf(out, "step,lift_mm,angle_deg\n");
    for (int k = 0; k <= 360; ++k)  // 0 .. 360 deg: the last row closes the table
      std::fprintf(out, "%d,%.17g,%d\n", k, exact.lift(k * kDeg).s * 1e3, k);
    std::fclose(out);
  }
  const auto doc = input::Document::parse(
      "profile = \"table\"\nfile = \"lift.csv\"\ncolumns = [\"angle_deg\", \"lift_mm\"]\nlift_scale = 1e-3\n"
      "base_radius = 0.018\nroller_radius = 0.010\n",
      "cam.toml");
  std::vector<std::filesystem::path> inputs;
  const auto cam = read_cam_profile(doc.root(), dir, inputs);
  ASSERT_EQ(inputs.size(), 1u);
  EXPECT_EQ(inputs[0], dir / "lift.csv");
  const SplineErrors e = table_errors(*cam, exact);
  EXPECT_LT(e.s, 1.3e-9);  // the bounds of the test above
  EXPECT_LT(e.v, 2.4e-7);
  EXPECT_LT(e.a, 1.2e-4);
  // The closing row must repeat the first lift.
  {
    std::FILE* out = std::fopen((dir / "open.csv").string().c_str(), "w");
    ASSERT_NE(out, nullptr);
    for (int k = 0; k <= 360; ++k)
      std::fprintf(out, "%d,%.17g\n", k, (k == 360 ? 0.5 : 0) + exact.lift(k * kDeg).s * 1e3);
    std::fclose(out);
  }
  const auto bad = input::Document::parse(
      "profile = \"table\"\nfile = \"open.csv\"\nlift_scale = 1e-3\nbase_radius = 0.018\nroller_radius = "
      "0.010\n",
      "cam.toml");
  try {
    read_cam_profile(bad.root(), dir, inputs);
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("cam.toml:2"), std::string::npos) << msg;
    EXPECT_NE(msg.find("open.csv"), std::string::npos) << msg;
    EXPECT_NE(msg.find("cam angle 360 deg"), std::string::npos) << msg;
  }
}

TEST(CamProfile, TableWithAKinkOrAStepIsNotSmoothEnoughAtItsAngle) {
  const double lift = 0.008, rb = 0.020, rr = 0.008;
  // A velocity jump (from +3L/W to -3L/W) at 100 deg only: s = L (1 - |phi|/W)^3 for |phi| < W = 100 deg.
  const auto kink = [&](double theta) {
    const double u = std::abs(std::remainder(theta - 100 * kDeg, 2 * kPi)) / (100 * kDeg);
    return u < 1 ? lift * std::pow(1 - u, 3) : 0.0;
  };
  std::string msg = error_of(table_text(kink, 1.0, rb, rr));
  std::printf("kink: %s\n", msg.c_str());
  EXPECT_NE(msg.find("'table'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("not smooth enough"), std::string::npos) << msg;
  EXPECT_NEAR(number_after(msg, "at cam angle "), 100.0, 2.0) << msg;
  // A step of L at 90 deg (and back at 150 deg).
  const auto step = [&](double theta) {
    const double d = wrap(theta) / kDeg;
    return d >= 90 && d < 150 ? lift : 0.0;
  };
  msg = error_of(table_text(step, 1.0, rb, rr));
  std::printf("step: %s\n", msg.c_str());
  EXPECT_NE(msg.find("not smooth enough"), std::string::npos) << msg;
  const double at = number_after(msg, "at cam angle ");
  EXPECT_TRUE(std::abs(at - 90) < 2 || std::abs(at - 150) < 2) << msg;
}

TEST(CamProfile, TableRollerLargerThanTheNoseUndercutsAtTheNose) {
  const double lift = 0.010, width = 140 * kDeg, rb = 0.005, rr = 0.010, nose = 90 * kDeg;
  const Cos4Cam exact(lift, width, rb, rr, nose);
  const std::string msg = error_of(table_text([&](double th) { return exact.lift(th).s; }, 1.0, rb, rr));
  std::printf("undercut: %s\n", msg.c_str());
  EXPECT_NE(msg.find("'roller_radius'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("does not fit"), std::string::npos) << msg;
  EXPECT_NEAR(number_after(msg, "at cam angle "), 90.0, 0.2) << msg;
  // The nose's radius of curvature as worked out in RollerTooLargeForTheNose... (6.93 mm), the spline's to
  // 0.01 mm.
  const double rho = rb + rr + lift, rho2 = -4 * lift * std::pow(kPi / width, 2);
  EXPECT_NEAR(number_after(msg, "radius of curvature there is "), rho * rho / (rho - rho2) * 1e3, 0.01)
      << msg;
}

TEST(CamProfile, TableErrorsNameTheRowAndAngle) {
  const std::string head = "profile = \"table\"\nbase_radius = 0.02\nroller_radius = 0.008\n";
  std::string rows;
  for (int k = 0; k < 12; ++k) {  // appended piecewise: GCC 12's -Wrestrict misfires on "[" + to_string(...)
    rows += '[';
    rows += std::to_string(30 * k);
    rows += ", 0.0],";
  }
  std::string msg = error_of(head + "table = [" + rows + "[300, 0.0]]\n");
  EXPECT_NE(msg.find("increase strictly"), std::string::npos) << msg;
  EXPECT_NE(msg.find("row 13 (300 deg)"), std::string::npos) << msg;
  msg = error_of(head + "table = [" + rows + "[361, 0.0]]\n");
  EXPECT_NE(msg.find("more than one turn"), std::string::npos) << msg;
  msg = error_of(head + "table = [" + std::string(rows).replace(rows.find("[60, 0.0]"), 9, "[60, -1e-4]") +
                 "]\n");
  EXPECT_NE(msg.find("negative lift -0.0001 m at cam angle 60 deg"), std::string::npos) << msg;
  msg = error_of(head + "table = [[0, 0], [10, 0], [20, 0]]\n");
  EXPECT_NE(msg.find("at least 8 points"), std::string::npos) << msg;
  msg = error_of(head);
  EXPECT_NE(msg.find("'table'"), std::string::npos) << msg;
  msg = error_of(head + "table = [" + rows + "]\nlift_scale = 0\n");
  EXPECT_NE(msg.find("lift_scale"), std::string::npos) << msg;
}

// ======================================================================================= polynomial profile

const std::string kPolynomial =
    "profile = \"polynomial\"\nlift = 0.010\nrise_deg = 55\nramp_deg = 20\nramp_height = 0.0003\n"
    "base_radius = 0.018\nroller_radius = 0.009\nnose_angle_deg = 120\n";

/// The quintic through (p0, d0, a0) at v0 and (p1, d1, a1) at v1, by solving its 6 x 6 conditions here.
Eigen::Matrix<double, 6, 1> quintic(double v0, double v1, double p0, double d0, double a0, double p1,
                                    double d1, double a1) {
  Eigen::Matrix<double, 6, 6> m = Eigen::Matrix<double, 6, 6>::Zero();
  for (int j = 0; j < 6; ++j) {
    for (int side = 0; side < 2; ++side) {
      const double v = side ? v1 : v0;
      m(3 * side, j) = std::pow(v, j);
      if (j >= 1) m(3 * side + 1, j) = j * std::pow(v, j - 1);
      if (j >= 2) m(3 * side + 2, j) = j * (j - 1) * std::pow(v, j - 2);
    }
  }
  Eigen::Matrix<double, 6, 1> rhs;
  rhs << p0, d0, a0, p1, d1, a1;
  return m.fullPivLu().solve(rhs);
}

TEST(CamProfile, PolynomialEventMeetsItsBoundaryConditionsAndIsSymmetric) {
  const auto cam = read(kPolynomial);
  EXPECT_EQ(cam->kind(), "polynomial");
  const double L = 0.010, H = 0.0003, a = 20 * kDeg, b = 55 * kDeg, nose = 120 * kDeg;
  const double V = 2 * H / a;  // the default ramp velocity
  // Opening side: v = angle since the ramp's start, theta = nose - (a + b) + v.
  const auto at = [&](double v) { return nose - (a + b) + v; };
  const auto ramp = quintic(0, a, 0, 0, 0, H, V, 0), rise = quintic(a, a + b, H, V, 0, L, 0, 0);
  double err = 0, err_d = 0, err_dd = 0;
  for (int k = 0; k <= 400; ++k) {
    const double v = (a + b) * k / 400.0;
    const auto& c = v <= a ? ramp : rise;
    double s = 0, ds = 0, dds = 0;
    for (int j = 0; j < 6; ++j) {
      s += c[j] * std::pow(v, j);
      if (j >= 1) ds += j * c[j] * std::pow(v, j - 1);
      if (j >= 2) dds += j * (j - 1) * c[j] * std::pow(v, j - 2);
    }
    const Lift l = cam->lift(at(v));
    err = std::max(err, std::abs(l.s - s));
    err_d = std::max(err_d, std::abs(l.ds - ds));
    err_dd = std::max(err_dd, std::abs(l.dds - dds));
    // Symmetry about the nose: s even, s' odd, s'' even.
    const Lift m = cam->lift(2 * nose - at(v));
    EXPECT_NEAR(m.s, l.s, 1e-15);
    EXPECT_NEAR(m.ds, -l.ds, 1e-14);
    EXPECT_NEAR(m.dds, l.dds, 1e-13);
    EXPECT_GE(l.ds, 0.0);  // monotonic opening
  }
  std::printf("polynomial vs 6x6 solve: |ds| %.3g m, |dv| %.3g m/rad, |da| %.3g m/rad^2\n", err, err_d,
              err_dd);
  EXPECT_LT(err, 1e-15);  // round-off of both (lifts of 10 mm; the 6 x 6 solve in powers of v up to 1.3^5)
  EXPECT_LT(err_d, 1e-14);
  EXPECT_LT(err_dd, 1e-12);
  // The default ramp: H (2 x^3 - x^4), x = v / a.
  for (double x : {0.1, 0.5, 0.9})
    EXPECT_NEAR(cam->lift(at(x * a)).s, H * (2 * x * x * x - x * x * x * x), 1e-17);
  // The junctions: base | ramp start (v = 0), ramp | rise (v = a), the top (v = a + b), and the closing side.
  const double eps = 1e-12;
  struct Junction {
    double theta, s, ds, dds;
  };
  const Junction junctions[] = {{at(0), 0, 0, 0},
                                {at(a), H, V, 0},
                                {nose, L, 0, 0},
                                {2 * nose - at(a), H, -V, 0},
                                {2 * nose - at(0), 0, 0, 0}};
  double jump_s = 0, jump_v = 0, jump_a = 0;
  for (const Junction& j : junctions) {
    for (double side : {-eps, 0.0, eps}) {
      const Lift l = cam->lift(j.theta + side);
      jump_s = std::max(jump_s, std::abs(l.s - j.s) - eps * std::abs(j.ds));
      jump_v = std::max(jump_v, std::abs(l.ds - j.ds));
      jump_a = std::max(jump_a, std::abs(l.dds - j.dds));
    }
  }
  std::printf("polynomial junctions: |ds| %.3g m, |dv| %.3g m/rad, |da| %.3g m/rad^2\n", jump_s, jump_v,
              jump_a);
  EXPECT_LT(jump_s, 1e-16);
  EXPECT_LT(jump_v, 1e-14);
  EXPECT_LT(jump_a, 1e-11);
  // Max lift L at the nose and nowhere more; base circle outside the event.
  EXPECT_DOUBLE_EQ(cam->max_lift(), L);
  EXPECT_NEAR(cam->max_lift_angle(), nose, 1e-15);
  double top = 0;
  for (int k = 0; k < 36000; ++k) top = std::max(top, cam->lift(0.01 * k * kDeg).s);
  EXPECT_LE(top, L);
  EXPECT_GT(top, L - 1e-12);
  EXPECT_EQ(cam->lift(nose + 180 * kDeg).s, 0.0);
  EXPECT_EQ(cam->lift(at(-1e-9)).s, 0.0);
  EXPECT_EQ(cam->lift(at(-1e-9)).dds, 0.0);
}

TEST(CamProfile, PolynomialEventChecks) {
  const std::string base =
      "profile = \"polynomial\"\nlift = 0.010\nbase_radius = 0.018\nroller_radius = 0.009\n";
  std::string msg = error_of(base + "rise_deg = 150\nramp_deg = 40\nramp_height = 0.0003\n");
  EXPECT_NE(msg.find("does not fit in 360 deg"), std::string::npos) << msg;
  msg = error_of(base + "rise_deg = 50\nramp_deg = 20\nramp_height = 0.010\n");
  EXPECT_NE(msg.find("'ramp_height'"), std::string::npos) << msg;
  msg = error_of(base + "rise_deg = 50\nramp_deg = 20\nramp_height = 0.0003\nramp_velocity = 0.5\n");
  EXPECT_NE(msg.find("'ramp_velocity'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("falls"), std::string::npos) << msg;
  msg = error_of(base + "rise_deg = 0\nramp_deg = 20\nramp_height = 0.0003\n");
  EXPECT_NE(msg.find("'rise_deg'"), std::string::npos) << msg;
  // A sharp event with a large roller undercuts.
  msg = error_of(
      "profile = \"polynomial\"\nlift = 0.012\nbase_radius = 0.006\nroller_radius = 0.015\n"
      "rise_deg = 30\nramp_deg = 10\nramp_height = 0.0002\n");
  EXPECT_NE(msg.find("does not fit"), std::string::npos) << msg;
}

}  // namespace
}  // namespace nvh::solve::cam
