// The flat-faced (mushroom) follower on a cam (`flat-face-cam`, issue 13 item 1) against references written
// out here, independently of solve/cam's support function:
// - the eccentric cam (a disc of radius Rb + e whose centre is e off the axis): the face touches the disc
// where
//   the disc's centre projects on it, so the lift is s = e (1 - cos theta) (nose at 180 deg) and the contact
//   point lies at the disc centre's coordinate along the face (Norton, Cam Design and Manufacturing Handbook,
//   2nd ed. 2009, section 7.4: the flat follower's lift is the cam's support function);
// - any profile: the support function h(phi) = max over the cam surface of X . u(phi) by brute force over the
//   pitch curve's points (the surface is its inner offset by Rr), refined until it converges; the follower's
//   velocity and acceleration by central differences of that;
// - a tappet of mass m on a spring (rate k, preload F0) at low speed: contact force F0 + k s + m s'' omega^2;
//   at high speed contact is lost where that reaches zero, on the eccentric cam at
//   omega^2 = (F0 + 2 k e) / (m e) (at the nose, s = 2 e, s'' = -e);
// - friction: ft = mu fn, its power mu fn v_s with v_s = omega d (the face's distance d from the axis: the
//   cam's surface speed along the face, the tappet does not move along it), the energy balance of /energy;
// - Hertz: a cylinder of the cam's radius R on a flat, p0 = sqrt(F E* / (pi L R)) (Johnson, Contact
//   Mechanics 1985, eq. 4.45); on the eccentric cam R = Rb + e everywhere.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "common/error.hpp"
#include "common/input.hpp"
#include "solve/cam/cam_profile.hpp"
#include "solve/cam/profiles.hpp"
#include "solve/cam/support_function.hpp"
#include "solve/element_registry.hpp"
#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::num;
using testing::run_text;
using testing::signal;
constexpr double kPi = std::numbers::pi;
constexpr double kRb = 0.02, kE = 0.005, kRr = 0.012, kWidth = 0.015;

/// h(phi) of the cam surface by brute force: the largest projection of the pitch curve's points on u(phi)
/// over 36000 samples, then two refinements of 2000 samples around the best one (each 1/1000 of the last
/// spacing), less Rr. Returns h and the contact point's coordinate along t = [-sin phi, cos phi].
std::pair<double, double> brute_support(const cam::CamProfile& profile, double phi) {
  const double c = std::cos(phi), s = std::sin(phi);
  double best = -1e300, best_psi = 0, spacing = 2 * kPi / 36000;
  auto scan = [&](double centre, int n, double step) {
    for (int k = -n; k <= n; ++k) {
      const double psi = centre + k * step;
      const cam::PitchPoint p = cam::pitch_point(profile, psi);
      const double v = p.x * c + p.y * s;
      if (v > best) best = v, best_psi = psi;
    }
  };
  scan(0.0, 18000, spacing);
  for (int level = 0; level < 2; ++level) {
    const double centre = best_psi;
    scan(centre, 1000, spacing / 1000), spacing /= 1000;
  }
  const cam::PitchPoint p = cam::pitch_point(profile, best_psi);
  return {best - profile.roller_radius(), -p.x * s + p.y * c};
}

std::unique_ptr<cam::CamProfile> profile_of(const std::string& keys) {
  const input::Document doc = input::Document::parse(keys, "cam.toml");
  std::vector<std::filesystem::path> files;
  return cam::read_cam_profile(doc.root(), ".", files);
}

const std::string kEccentric = "profile = \"eccentric\"\nbase_radius = " + num(kRb) +
                               "\neccentricity = " + num(kE) + "\nroller_radius = " + num(kRr) +
                               "\nnose_angle_deg = 180\n";
// A valve-lift event: 8 mm over 2 x (20 + 60) deg, nose at 0.
const std::string kPolynomial =
    "profile = \"polynomial\"\nbase_radius = 0.02\nlift = 0.008\nrise_deg = 60\nramp_deg = 20\n"
    "ramp_height = 0.0003\nroller_radius = 0.012\n";

// The element built by the registry from TOML keys (markers on bodies "tappet" and "cam").
struct Built {
  input::Document doc;
  std::unique_ptr<ForceElement> element;
};
Built build(const std::string& keys) {
  const ElementType* et = builtin_elements().find("force", "flat-face-cam");
  Built b{input::Document::parse(keys, "flat.toml"), nullptr};
  std::vector<std::filesystem::path> files;
  std::vector<MarkerMotion> initial(2);
  std::vector<std::string> bodies = {"tappet", "cam"};
  ElementContext c{b.doc.root(), ".", files, initial, bodies};
  b.element = et->make(c);
  return b;
}

// The eccentric cam: the support function is the disc's, h = Rb + e + e cos(phi - phi_n), so the lift is
// e (1 - cos theta) and the contact point is the disc centre's foot on the face; the element's channels
// (gap, contact_offset) with the cam turned to theta and the face 0.1 mm above the cam, also off-centre.
TEST(FlatFaceCam, EccentricCamLiftAndOffsetToRoundOff) {
  const auto profile = profile_of(kEccentric);
  const Built b = build(kEccentric + "face_width = " + num(kWidth) + "\n");
  double lift_err = 0, offset_err = 0, gap_err = 0, ch_offset_err = 0, radius_err = 0;
  for (int k = 0; k < 360; ++k) {
    const double theta = 2 * kPi * k / 360 + 0.1;
    // the follower on the cam's +x axis at cam angle 0 sees the cam frame's direction phi = -theta
    const cam::Support s = cam::support(*profile, -theta);
    lift_err = std::max(lift_err, std::abs(s.h - kRb - kE * (1 - std::cos(theta))));
    // the disc's centre in the cam frame at polar angle -180 deg; turned by theta it is at -e [cos, sin]
    // theta; its coordinate along t = z x u = +y is -e sin theta
    offset_err = std::max(offset_err, std::abs(s.dh + kE * std::sin(theta)));
    radius_err = std::max(radius_err, std::abs(s.radius - (kRb + kE)));
    // the element: cam marker at the origin turned by theta, the face (z_i = -x) at x = Rb + s + 0.1 mm, its
    // origin 3 mm off the cam's axis line along y
    std::vector<MarkerMotion> m(2);
    m[1].axes = Eigen::AngleAxisd(theta, Vec3::UnitZ()).toRotationMatrix();
    m[0].position = Vec3(kRb + kE * (1 - std::cos(theta)) + 1e-4, 0.003, 0.0);
    m[0].axes << 0, 0, -1, 1, 0, 0, 0, -1, 0;  // x_i = y, y_i = -z, z_i = -x
    std::vector<double> values(b.element->channels().size());
    const ElementInput in{0.0, 0.0, m, {}, {}};
    b.element->channel_values(in, values);
    gap_err = std::max(gap_err, std::abs(values[3] - 1e-4));
    ch_offset_err = std::max(ch_offset_err, std::abs(values[2] - (-kE * std::sin(theta) - 0.003)));
  }
  std::printf(
      "measured: eccentric cam lift %.2g m, offset %.2g m, radius %.2g m; element gap %.2g m, "
      "contact_offset %.2g m\n",
      lift_err, offset_err, radius_err, gap_err, ch_offset_err);
  // round-off; the offset (first order in the contact point's polar angle) also Newton's last step, 1e-14
  // rad, times the pitch radius 0.03 m
  EXPECT_LT(lift_err, 1e-16);
  EXPECT_LT(offset_err, 1e-15);
  EXPECT_LT(radius_err, 1e-15);
  EXPECT_LT(gap_err, 1e-16);
  EXPECT_LT(ch_offset_err, 1e-15);
}

// The polynomial event: h against the brute-force support function; the follower's velocity -h'(-theta) and
// acceleration h''(-theta) against central differences (step 1e-4 rad) of the brute-force h; the offset
// against the brute-force contact point. The event's jerk jumps where ramp and rise meet, so h''' jumps and
// the differences straddling such a point lose an order there.
TEST(FlatFaceCam, PolynomialCamLiftIsTheSupportFunction) {
  const auto profile = profile_of(kPolynomial);
  const double step = 1e-4;
  double lift_err = 0, offset_err = 0, vel_err = 0, acc_err = 0, acc_peak = 0;
  for (int k = 0; k < 360; k += 3) {
    const double theta = 2 * kPi * k / 360 + 0.01;
    const auto lift = [&](double th) { return brute_support(*profile, -th).first - kRb; };
    const cam::Support s = cam::support(*profile, -theta);
    const auto [h, along] = brute_support(*profile, -theta);
    lift_err = std::max(lift_err, std::abs(s.h - h));
    offset_err = std::max(offset_err, std::abs(s.dh - along));
    const double l0 = lift(theta), lp = lift(theta + step), lm = lift(theta - step);
    vel_err = std::max(vel_err, std::abs(-s.dh - (lp - lm) / (2 * step)));
    acc_err = std::max(acc_err, std::abs(s.ddh - (lp - 2 * l0 + lm) / (step * step)));
    acc_peak = std::max(acc_peak, std::abs(s.ddh));
  }
  std::printf(
      "measured: polynomial cam lift %.2g m, offset %.2g m, velocity %.2g m/rad, acceleration %.2g "
      "m/rad^2 (peak %.3g)\n",
      lift_err, offset_err, vel_err, acc_err, acc_peak);
  // (at step 1e-3 rad the velocity and acceleration errors were 9.8e-6 and 2.2e-3: both fall as step^2)
  EXPECT_LT(lift_err, 1e-13);   // the brute force's sampling (spacing 1.7e-10 rad: 1e-20 m) and round-off
  EXPECT_LT(offset_err, 2e-9);  // the brute force's argmax where the cam is nearly straight (R_c ~ 0.3 m):
                                // round-off 1e-18 m on a maximum that flat moves it by ~1e-7 rad
  EXPECT_LT(vel_err, 2e-7);     // the differences' truncation h''' step^2 / 6 (h''' up to ~60 m/rad^3)
  EXPECT_LT(acc_err, 5e-5);     // truncation h'''' step^2 / 12; the brute force's noise / step^2 ~ 1e-9
  EXPECT_GT(acc_peak, 0.01);
}

// A concave cam: a steep event on a small base circle. The error is located at the key `profile` and names
// the cam angle of the most concave point, found here from the polar curvature formula of the pitch curve
// (kappa = (rho^2 + 2 rho'^2 - rho rho'') / (rho^2 + rho'^2)^1.5, rho' and rho'' by differences of the lift).
TEST(FlatFaceCam, ConcaveCamIsAnErrorNamingTheAngle) {
  const std::string keys =
      "profile = \"polynomial\"\nbase_radius = 0.012\nlift = 0.010\nrise_deg = 35\n"
      "ramp_deg = 10\nramp_height = 0.0002\nroller_radius = 0.004\nnose_angle_deg = 90\n";
  const auto profile = profile_of(keys);  // a roller of 4 mm fits (the roller check passes)
  double worst = 0, worst_theta = 0;
  for (int k = 0; k < 36000; ++k) {
    const double theta = 2 * kPi * k / 36000, d = 1e-5;
    const double rho = 0.012 + 0.004 + profile->lift(theta).s;  // Rb + Rr + s
    const double r1 = (profile->lift(theta + d).s - profile->lift(theta - d).s) / (2 * d);
    const double r2 =
        (profile->lift(theta + d).s - 2 * profile->lift(theta).s + profile->lift(theta - d).s) / (d * d);
    const double kappa = (rho * rho + 2 * r1 * r1 - rho * r2) / std::pow(rho * rho + r1 * r1, 1.5);
    if (kappa < worst) worst = kappa, worst_theta = theta * 180 / kPi;
  }
  ASSERT_LT(worst, 0.0) << "the test's cam is not concave";
  std::string message = "no error";
  try {
    build(keys + "face_width = 0.01\n");
  } catch (const Error& e) {
    message = e.what();
  }
  std::printf("measured: %s\n  (reference: most concave at %.2f deg)\n", message.c_str(), worst_theta);
  EXPECT_NE(message.find("flat.toml:"), std::string::npos) << message;
  EXPECT_NE(message.find("profile"), std::string::npos) << message;
  const auto at = message.find("cam angle ");
  ASSERT_NE(at, std::string::npos) << message;
  const double named = std::stod(message.substr(at + 10));
  EXPECT_NEAR(named, worst_theta, 0.15);  // the check's grid is 0.1 deg
  // the same event on a gentle cam (20 mm base circle, 60 deg rise) is accepted
  EXPECT_NO_THROW(build(kPolynomial + "face_width = 0.01\n"));
}

// ------------------------------------------------------------------------------------------------ scenes
// A cam on a revolute joint turned by a speed driver; a tappet on a prismatic joint along global x (the cam's
// +x at cam angle 0), its face (z_i = -x) on the eccentric cam, held by a preloaded spring.
std::string scene(double rpm, double mass, double k, double preload, const std::string& keys,
                  double revolutions, double rate_hz) {
  const double x0 = kRb, seat = 0.2;
  const double free_length = (seat - x0) + preload / k;
  std::string s = R"(
[scene]
name = "flat-face-cam"
gravity = [0, 0, 0]
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "axis"
  [[body.marker]]
  name = "bore"
  at = [)" + num(x0) +
                  R"(, 0, 0]
  z = [1, 0, 0]
  x = [0, 1, 0]
  [[body.marker]]
  name = "seat"
  at = [)" + num(seat) +
                  R"(, 0, 0]
[[body]]
name = "cam"
type = "rigid"
mass = 2.0
inertia = [1e-3, 1e-3, 1e-3]
position = [0, 0, 0]
  [[body.marker]]
  name = "lobe"
[[body]]
name = "tappet"
type = "rigid"
mass = )" + num(mass) +
                  R"(
inertia = [1e-4, 1e-4, 1e-4]
position = [)" + num(x0) +
                  R"(, 0, 0]
  [[body.marker]]
  name = "face"
  z = [-1, 0, 0]
  x = [0, 1, 0]
  [[body.marker]]
  name = "slide"
  z = [1, 0, 0]
  x = [0, 1, 0]
[[joint]]
name = "camshaft"
type = "revolute"
i = "cam.lobe"
j = "ground.axis"
[[joint]]
name = "bore"
type = "prismatic"
i = "tappet.slide"
j = "ground.bore"
[[driver]]
name = "cam-speed"
type = "speed"
i = "cam.lobe"
j = "ground.axis"
rpm = )" + num(rpm) +
                  R"(
[[force]]
name = "valve-spring"
type = "spring-damper"
i = "tappet.face"
j = "ground.seat"
k = )" + num(k) + R"(
free_length = )" + num(free_length) +
                  R"(
[[force]]
name = "cam"
type = "flat-face-cam"
i = "tappet.face"
j = "cam.lobe"
face_width = )" + num(kWidth) +
                  "\n" + kEccentric + keys;
  s += "[clock]\nend_time = " + num(revolutions * 60.0 / rpm) +
       "\n[integrator]\nrtol = 1e-8\natol = 1e-11\nmax_step = " + num(0.5 / 360 * 60.0 / rpm) +
       "\n[output]\nsample_rate_hz = " + num(rate_hz) + "\n";
  return s;
}

// Low speed: the contact force is the spring's force plus the tappet's m a on the closed-form lift; Hertz
// pressure with R = Rb + e; with friction mu = 0.1 the friction force is mu fn, the sliding speed the cam's
// surface speed omega d at the face (d the tappet's position: the face's distance from the axis), the
// dissipated energy the friction's work (damping is negligible once the start has rung out), and the energy
// balance closes.
TEST(FlatFaceCam, LowSpeedForceHertzFrictionAndEnergy) {
  const double rpm = 600, m = 0.5, k = 2e4, f0 = 100, mu = 0.1;
  const auto file = run_text(scene(rpm, m, k, f0,
                                   "restitution = 0.5\nreference_speed = 0.01\nmu_static = " + num(mu) +
                                       "\nregularization_speed = 1e-5\n",
                                   1.0, 36000),
                             "flat_face_slow");
  const Eigen::VectorXd t = signal(file, "time"), fn = signal(file, "forces/cam/normal_force"),
                        p0 = signal(file, "forces/cam/hertz_pressure"),
                        ft = signal(file, "forces/cam/friction_force"),
                        vs = signal(file, "forces/cam/sliding_speed"),
                        diss = signal(file, "energy/dissipated"), balance = signal(file, "energy/balance"),
                        input = signal(file, "energy/input"), x = signal(file, "bodies/tappet/position", 0);
  const double w = rpm * 2 * kPi / 60, e_star = 1.0 / (2 * (1 - 0.3 * 0.3) / 207e9);
  double f_err = 0, p_err = 0, ft_err = 0, vs_err = 0, work = 0;
  Eigen::Index first = -1;
  for (Eigen::Index i = 0; i < t.size(); ++i) {
    const double theta = w * t[i];
    if (theta < 20 * kPi / 180) continue;  // the start from zero approach rings out first
    if (first < 0) first = i;
    const double s = kE * (1 - std::cos(theta)), a = kE * std::cos(theta) * w * w;
    f_err = std::max(f_err, std::abs(fn[i] - (f0 + k * s + m * a)));
    p_err = std::max(p_err, std::abs(p0[i] / std::sqrt(fn[i] * e_star / (kPi * kWidth * (kRb + kE))) - 1));
    ft_err = std::max(ft_err, std::abs(ft[i] - mu * fn[i]));
    vs_err = std::max(vs_err, std::abs(vs[i] - w * x[i]));  // the face (at the tappet's origin) at d = x
    if (i > first) work += 0.5 * (t[i] - t[i - 1]) * (ft[i] * vs[i] + ft[i - 1] * vs[i - 1]);
  }
  const double dissipated = diss[t.size() - 1] - diss[first];
  std::printf(
      "measured: contact force error %.3g N (forces %.1f..%.1f N), Hertz p0 %.2g rel (%.1f MPa at the end), "
      "friction %.2g N, sliding speed %.2g m/s, dissipated %.6g J against the friction work %.6g J (%.2g "
      "rel), energy balance %.2g J of input %.3g J\n",
      f_err, fn.minCoeff(), fn.maxCoeff(), p_err, p0[p0.size() - 1] * 1e-6, ft_err, vs_err, dissipated, work,
      std::abs(dissipated / work - 1), balance.cwiseAbs().maxCoeff(), input.cwiseAbs().maxCoeff());
  EXPECT_LT(f_err, 0.05);  // N: k times Palmgren's approach (up to 0.03 N) and the contact's vibration
  EXPECT_LT(p_err, 1e-9);
  EXPECT_LT(ft_err, 1e-6 * f0);  // tanh(v_s / 1e-5 m/s) = 1 at v_s >= 0.2 m/s
  EXPECT_LT(vs_err, 1e-7);       // m/s: the speed driver's and the joints' constraint accuracy
  EXPECT_LT(std::abs(dissipated / work - 1), 1e-4);  // the trapezoid over 0.01 deg samples
  EXPECT_LT(balance.cwiseAbs().maxCoeff(), 1e-5 * input.cwiseAbs().maxCoeff());  // rtol 1e-8 per step
}

// Separation: below the closed-form speed the face stays on the cam (smallest force = F0 + 2 k e - m e w^2 at
// the nose), above it the face lifts off.
TEST(FlatFaceCam, SeparationSpeedOfTheEccentricCam) {
  const double m = 0.5, k = 2e4, f0 = 100;
  const double w_sep = std::sqrt((f0 + 2 * k * kE) / (m * kE)), rpm_sep = w_sep * 60 / (2 * kPi);
  auto smallest = [&](double rpm, double* separated) {
    const auto file =
        run_text(scene(rpm, m, k, f0, "restitution = 0.3\n", 2.0, rpm * 6 * 10), "flat_face_sep");
    const Eigen::VectorXd fn = signal(file, "forces/cam/normal_force"),
                          sep = signal(file, "forces/cam/separated");
    const Eigen::Index half = fn.size() / 2;  // the second revolution
    *separated = sep.tail(fn.size() - half).maxCoeff();
    return fn.tail(fn.size() - half).minCoeff();
  };
  double below = 0, above = 0;
  const double f_min = smallest(0.9 * rpm_sep, &below);
  smallest(1.1 * rpm_sep, &above);
  const double w = 0.9 * w_sep, expected = f0 + 2 * k * kE - m * kE * w * w;
  std::printf(
      "measured: separation speed (closed form) %.1f rpm; smallest force at 0.9 of it %.3f N (closed "
      "form %.3f N); separated below / above: %g / %g\n",
      rpm_sep, f_min, expected, below, above);
  EXPECT_EQ(below, 0.0);
  EXPECT_EQ(above, 1.0);
  EXPECT_NEAR(f_min, expected, 0.02 * f0);  // the contact's own vibration about the rigid-body force
}

}  // namespace
}  // namespace nvh::solve
