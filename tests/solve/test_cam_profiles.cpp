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

}  // namespace
}  // namespace nvh::solve::cam
