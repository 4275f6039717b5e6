// roller-cam's crowned roller and the roller's friction (docs/valvetrain.md section 2) against references
// written out here, independently of solve/elements/hertz_point.hpp and roller_cam.cpp:
// - the crowned roller's elliptical contact against Hertz's exact solution (K. L. Johnson, Contact Mechanics,
//   1985, section 4.2, eqs. 4.39-4.41 with the complete elliptic integrals K(e), E(e) of
//   std::comp_ellint_1/2): for relative curvatures A = 1/(2 R_max) < B = 1/(2 R_min), the ellipse's
//   eccentricity e solves B/A = ((a/b)^2 E - K) / (K - E), a/b = 1/sqrt(1 - e^2); then a^3 = 3 P (K - E) / (2
//   pi E* e^2 A), b = a sqrt(1 - e^2), p0 = 3 P / (2 pi a b), approach delta = p0 b K / E*; and its circular
//   limit, Hertz's sphere on a flat: delta = (9 F^2 / (16 E*^2 R))^(1/3), a = (3 F R / (4 E*))^(1/3), p0 = 3
//   F / (2 pi a^2);
// - rolling resistance: over a cam revolution the drive's work and the dissipated energy equal the integral
// of
//   the resistance moment c fn times the roller's rolling speed; on the base circle the roller turns at
//   omega Rb / Rr (pure rolling);
// - slip: a roller of inertia J on the base circle of a cam accelerated from rest at alpha needs the traction
//   J Rb alpha / Rr^2; below mu fn it rolls with the creep of the regularized Coulomb, v = v_eps atanh(J Rb
//   alpha / (Rr^2 mu fn)); above it slips, the roller's spin rising at mu fn Rr / J and the slip speed at
//   Rb alpha - mu fn Rr^2 / J.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>
#include <utility>

#include "common/input.hpp"
#include "solve/cam/cam_profile.hpp"
#include "solve/element_registry.hpp"
#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::num;
using testing::run_text;
using testing::signal;
constexpr double kPi = std::numbers::pi;

// ------------------------------------------------------------------------------------------------------
// The crowned roller: one evaluation of the element, built by the registry, on the eccentric cam (its surface
// a disc of radius Rb + e: the rolling plane's radius is the same everywhere).

constexpr double kRb = 0.02, kEcc = 0.005, kRr = 0.012, kWidth = 0.015;
const double kEStar = 1.0 / (2 * (1 - 0.3 * 0.3) / 207e9);

struct Evaluated {
  double force = 0, p0 = 0, half_width = 0, half_length = 0;
};

/// The element with `crown` (m) at approach `delta` (m), at rest, on the cam's base side (psi = 0).
Evaluated crowned_at(double crown, double delta) {
  const std::string keys = "roller_width = " + num(kWidth) +
                           "\nprofile = \"eccentric\"\nbase_radius = " + num(kRb) +
                           "\neccentricity = " + num(kEcc) + "\nroller_radius = " + num(kRr) +
                           "\nnose_angle_deg = 180\ncrown_radius = " + num(crown) + "\n";
  const input::Document doc = input::Document::parse(keys, "crowned.toml");
  std::vector<std::filesystem::path> files;
  std::vector<MarkerMotion> markers(2);
  ElementContext c{doc.root(), ".", files, markers, {"follower", "cam"}};
  const auto element = builtin_elements().find("force", "roller-cam")->make(c);
  const auto profile = cam::read_cam_profile(doc.root(), ".", files);
  const cam::PitchPoint pp = cam::pitch_point(*profile, 0.0);
  markers[0].position = Vec3(pp.x - delta * pp.nx, pp.y - delta * pp.ny, 0.0);
  std::vector<Wrench> w(2);
  const ElementInput in{0.0, 0.0, markers, {}, {}};
  ElementOutput out{w, {}};
  element->evaluate(in, out);
  const auto channels = element->channels();
  std::vector<double> values(channels.size());
  element->channel_values(in, values);
  Evaluated e;
  e.force = w[0].force.norm();
  for (std::size_t k = 0; k < channels.size(); ++k) {
    if (channels[k].name == "hertz_pressure") e.p0 = values[k];
    if (channels[k].name == "half_width") e.half_width = values[k];
    if (channels[k].name == "half_length") e.half_length = values[k];
  }
  return e;
}

/// Hertz's exact elliptical contact (Johnson section 4.2) of radii r_min < r_max under load p: the semi-axes
/// (along r_max's direction, the major one, and along r_min's), the maximum pressure and the approach.
struct Exact {
  double major = 0, minor = 0, p0 = 0, delta = 0;
};
Exact exact_hertz(double r_min, double r_max, double p) {
  const double ratio = r_max / r_min;  // B / A
  double lo = 1e-9, hi = 1 - 1e-15;    // the eccentricity, by bisection (B/A increases with e)
  for (int it = 0; it < 200; ++it) {
    const double e = 0.5 * (lo + hi), kk = std::comp_ellint_1(e), ee = std::comp_ellint_2(e);
    const double f = (ee / (1 - e * e) - kk) / (kk - ee);
    (f < ratio ? lo : hi) = e;
  }
  const double e = 0.5 * (lo + hi), kk = std::comp_ellint_1(e), ee = std::comp_ellint_2(e);
  const double a_curv = 1 / (2 * r_max);
  Exact x;
  x.major = std::cbrt(3 * p * (kk - ee) / (2 * kPi * kEStar * e * e * a_curv));
  x.minor = x.major * std::sqrt(1 - e * e);
  x.p0 = 3 * p / (2 * kPi * x.major * x.minor);
  x.delta = x.p0 * x.minor * kk / kEStar;
  return x;
}

// The circular limit: a crown radius equal to the rolling plane's relative radius Rx (1/Rx = 1/Rr + 1/(Rb +
// e)) makes the contact a sphere of radius Rx on a flat: Hertz's closed form to round-off.
TEST(CrownedRoller, CircularLimitIsHertzSphereOnFlat) {
  const double rx = 1 / (1 / kRr + 1 / (kRb + kEcc));
  double worst = 0;
  for (const double delta : {1e-6, 5e-6, 2e-5}) {
    const Evaluated e = crowned_at(rx, delta);
    const double f = e.force;
    const double d_ref = std::cbrt(9 * f * f / (16 * kEStar * kEStar * rx));
    const double a_ref = std::cbrt(3 * f * rx / (4 * kEStar));
    const double p_ref = 3 * f / (2 * kPi * a_ref * a_ref);
    const double f_ref = 4.0 / 3.0 * kEStar * std::sqrt(rx) * std::pow(delta, 1.5);
    for (const double err : {d_ref / delta - 1, e.half_width / a_ref - 1, e.half_length / a_ref - 1,
                             e.p0 / p_ref - 1, f / f_ref - 1})
      worst = std::max(worst, std::abs(err));
    std::printf("measured: circular limit, delta %.0e m: F %.4g N, a %.4g um, p0 %.4g MPa\n", delta, f,
                e.half_width * 1e6, e.p0 * 1e-6);
  }
  std::printf("measured: circular limit, worst relative error %.2e\n", worst);
  EXPECT_LT(worst, 1e-11);  // round-off of cbrt and pow
}

// A crowned roller (Rx about 8.1 mm in the rolling plane) with crown radii from 20 mm to 2.43 m (radius ratio
// 2.5 to 300): the element's force at a given approach, its semi-axes and p0 against Hertz's exact solution
// at the same force (exact_hertz above, written out here independently of hertz_point.cpp: bisection on the
// eccentricity). Tolerance 1e-6: the element interpolates the ellipse's shape in ln r (2e-10 measured in
// test_hertz_ellipse.cpp). Hamrock and Brewe's approximations, which the element used before, were off here
// by F -3.8, -1.9, +4.0, +12.0 % at ratios 2.5, 12, 62, 247 (their ellipticity alpha^(2/pi) 2.5 % low at 2.5,
// 8.6 % high at 247).
TEST(CrownedRoller, EllipticalContactAgainstExactHertz) {
  const double rx = 1 / (1 / kRr + 1 / (kRb + kEcc));
  double worst = 0;
  for (const double crown : {0.02, 0.1, 0.5, 2.0, 300 * rx}) {
    const double delta = 5e-6;
    const Evaluated e = crowned_at(crown, delta);
    const Exact x = exact_hertz(rx, crown, e.force);
    // the force the exact theory gives at this approach: delta scales as P^(2/3)
    const double f_exact = e.force * std::pow(delta / x.delta, 1.5);
    const double err_f = e.force / f_exact - 1, err_a = e.half_length / x.major - 1,
                 err_b = e.half_width / x.minor - 1, err_p = e.p0 / x.p0 - 1;
    std::printf(
        "measured: crown %.3g m (ratio %.3g): F %.6g N (exact %.6g, %+.1e), a %.5g mm (%+.1e), b %.5g um "
        "(%+.1e), p0 %.6g MPa (%+.1e)\n",
        crown, crown / rx, e.force, f_exact, err_f, e.half_length * 1e3, err_a, e.half_width * 1e6, err_b,
        e.p0 * 1e-6, err_p);
    for (const double err : {err_f, err_a, err_b, err_p}) {
      EXPECT_LT(std::abs(err), 1e-6) << "crown radius " << crown;
      worst = std::max(worst, std::abs(err));
    }
    EXPECT_NEAR(e.p0, 3 * e.force / (2 * kPi * e.half_width * e.half_length), 1e-9 * e.p0);
  }
  std::printf("measured: the element against exact Hertz at ratios 2.5 .. 300, worst relative error %.2e\n",
              worst);
}

// ------------------------------------------------------------------------------------------------------
// Scenes: a cam on a revolute joint turned by a speed driver (`speed` is the driver's keys: rpm or table),
// a radial roller lifter on a prismatic joint along x held on the tangent cam (Rb 20 mm, Rn 10 mm, d 20 mm,
// Rr 12 mm, nose at 180 deg) by a preloaded spring.
std::string scene(const std::string& speed, double preload, const std::string& contact_keys, double end_time,
                  double max_step, double rate_hz) {
  const double x0 = kRb + kRr, seat = 0.2, k = 5e4;
  const double free_length = (seat - x0) + preload / k;
  return R"([scene]
name = "roller-friction"
gravity = [0, 0, 0]
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "axis"
  [[body.marker]]
  name = "bore"
  at = [)" +
         num(x0) + R"(, 0, 0]
  z = [1, 0, 0]
  x = [0, 1, 0]
  [[body.marker]]
  name = "seat"
  at = [)" +
         num(seat) + R"(, 0, 0]
[[body]]
name = "cam"
type = "rigid"
mass = 2.0
inertia = [1e-3, 1e-3, 1e-3]
position = [0, 0, 0]
  [[body.marker]]
  name = "lobe"
[[body]]
name = "lifter"
type = "rigid"
mass = 0.5
inertia = [1e-4, 1e-4, 1e-4]
position = [)" +
         num(x0) + R"(, 0, 0]
  [[body.marker]]
  name = "roller"
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
i = "lifter.slide"
j = "ground.bore"
[[driver]]
name = "cam-speed"
type = "speed"
i = "cam.lobe"
j = "ground.axis"
)" + speed +
         R"(
[[force]]
name = "valve-spring"
type = "spring-damper"
i = "lifter.roller"
j = "ground.seat"
k = )" + num(k) +
         R"(
free_length = )" +
         num(free_length) + R"(
[[force]]
name = "cam"
type = "roller-cam"
i = "lifter.roller"
j = "cam.lobe"
roller_width = )" +
         num(kWidth) + R"(
profile = "tangent"
base_radius = 0.02
nose_radius = 0.01
lobe_distance = 0.02
roller_radius = 0.012
nose_angle_deg = 180
)" + contact_keys +
         "[clock]\nend_time = " + num(end_time) +
         "\n[integrator]\nrtol = 1e-8\natol = 1e-11\nmax_step = " + num(max_step) +
         "\n[output]\nsample_rate_hz = " + num(rate_hz) + "\n";
}

/// Trapezoidal integral of y over t.
double integral(const Eigen::VectorXd& t, const Eigen::VectorXd& y) {
  double s = 0;
  for (Eigen::Index k = 1; k < t.size(); ++k) s += 0.5 * (y[k] + y[k - 1]) * (t[k] - t[k - 1]);
  return s;
}

// One revolution at 300 rpm with a pin (mu_pin 0.1 on a 4 mm pin) and a rolling-resistance arm of 50 um: the
// resistance moment c fn, c = 0.1 * 0.004 + 5e-5 m, times the roller's spin (pure rolling, the lifter does
// not turn) integrates to the dissipated energy and to the drive's work (restitution 1: no other loss; the
// spring returns to its start).
TEST(RollerFriction, RollingResistanceDissipatesTheMomentTimesTheRollingSpeed) {
  const double rpm = 300, c = 0.1 * 0.004 + 5e-5, period = 60 / rpm;
  const std::string keys =
      "pin_friction = 0.1\npin_radius = 0.004\nrolling_resistance = 5e-5\nreference_speed = 0.01\n";
  const auto file = run_text(scene("rpm = " + num(rpm), 500, keys, period, period / 720, 3600 / period),
                             "roller_resistance");
  const Eigen::VectorXd t = signal(file, "time"), fn = signal(file, "forces/cam/normal_force"),
                        spin = signal(file, "forces/cam/roller_speed"),
                        ft = signal(file, "forces/cam/friction_force"),
                        power = signal(file, "forces/cam/friction_power");
  const Eigen::VectorXd dissipated = signal(file, "energy/dissipated"), input = signal(file, "energy/input"),
                        balance = signal(file, "energy/balance");
  Eigen::VectorXd moment_power(t.size());
  double spin_err = 0, ft_err = 0;
  const double w = rpm * 2 * kPi / 60;
  for (Eigen::Index k = 0; k < t.size(); ++k) {
    moment_power[k] = c * fn[k] * std::abs(spin[k]);
    const double theta = w * t[k], from_nose = std::abs(std::remainder(theta - kPi, 2 * kPi));
    if (from_nose > kPi / 3 + 0.05)
      spin_err = std::max(spin_err, std::abs(std::abs(spin[k]) - w * kRb / kRr));
    ft_err = std::max(ft_err, std::abs(std::abs(ft[k]) - c * fn[k] / kRr));
  }
  const double expected = integral(t, moment_power);
  const double from_channel = integral(t, power);
  const double lost = dissipated[dissipated.size() - 1] - dissipated[0];
  const double work = input[input.size() - 1] - input[0];
  std::printf(
      "measured: integral of c fn |Omega| %.6g J, of friction_power %.6g J; /energy/dissipated %.6g J; drive "
      "work "
      "%.6g J; balance %.3g J; base-circle spin error %.3g rad/s of %.4g; |ft| - c fn / Rr %.3g N\n",
      expected, from_channel, lost, work, balance.cwiseAbs().maxCoeff(), spin_err, w * kRb / kRr, ft_err);
  EXPECT_GT(expected, 0.1);
  EXPECT_NEAR(lost, expected, 1e-3 * expected);  // the trapezoid on 0.1 deg samples
  EXPECT_NEAR(from_channel, expected, 1e-3 * expected);
  EXPECT_NEAR(work, expected, 2e-3 * expected);  // the spring's and the lifter's energy return to their start
  EXPECT_LT(balance.cwiseAbs().maxCoeff(), 1e-4 * expected);
  // the element's contact point p_i - Rr n lies the approach (about 2 um) inside the base circle: 2e-4 of it
  EXPECT_LT(spin_err, 2e-4 * w * kRb / kRr);
  EXPECT_LT(ft_err, 1e-3 * c * 500 / kRr);  // tanh(v / v_eps) = 1 but near v = 0 (none here: the cam turns)
}

// The roller (J = 3.8e-6 kg m^2, a steel disc 24 x 15 mm) on the base circle, preload 20 N, mu 0.05 (no
// Stribeck hump), v_eps 1 mm/s, the contact damped (e = 0.3 at 0.01 m/s); the cam at rest for 0.01 s (the
// contact settles from zero approach), then accelerated at alpha for 0.02 s (under 60 deg: the base circle).
// The traction limit alpha* = mu fn Rr^2 / (J Rb) = 1895 rad/s^2.
TEST(RollerSlip, PureRollingBelowAndSlipAboveTheTractionLimit) {
  const double j = 3.8e-6, f0 = 20, mu = 0.05, eps = 1e-3, end = 0.02, settle = 0.01;
  const double alpha_star = mu * f0 * kRr * kRr / (j * kRb);
  const std::string keys = "roller_inertia = " + num(j) + "\nmu_static = " + num(mu) +
                           "\nregularization_speed = " + num(eps) +
                           "\nrestitution = 0.3\nreference_speed = 0.01\n";
  auto run = [&](double ratio, const std::string& name, double* slip, double* spin_rate, double* balance,
                 double* dissipated) {
    const double alpha = ratio * alpha_star, rpm_end = alpha * end * 60 / (2 * kPi);
    const auto file = run_text(scene("table = [[0.0, 0.0], [" + num(settle) + ", 0.0], [" +
                                         num(settle + end) + ", " + num(rpm_end) + "]]",
                                     f0, keys, settle + end, end / 2000, 2000 / end),
                               name);
    const Eigen::VectorXd t = signal(file, "time"), v = signal(file, "forces/cam/slip_speed"),
                          spin = signal(file, "forces/cam/roller_speed"),
                          fn = signal(file, "forces/cam/normal_force");
    const Eigen::Index last = t.size() - 1,
                       mid = (t.size() * 2) / 3;  // mid: half-way through the acceleration
    *slip = v[last];
    *spin_rate = (spin[last] - spin[mid]) / (t[last] - t[mid]);
    *balance = signal(file, "energy/balance").cwiseAbs().maxCoeff();
    // the scale of the balance: the energy lost plus the roller's spin energy J Omega^2 / 2 at the end
    *dissipated = signal(file, "energy/dissipated")[last] + 0.5 * j * spin[last] * spin[last];
    std::printf("measured: alpha %.3g alpha*: normal force %.4g..%.4g N\n", ratio, fn.tail(mid).minCoeff(),
                fn.tail(mid).maxCoeff());
    return file;
  };
  double slip = 0, rate = 0, balance = 0, lost = 0;
  run(0.5, "roller_rolls", &slip, &rate, &balance, &lost);
  const double creep = eps * std::atanh(0.5), rolling_rate = 0.5 * alpha_star * kRb / kRr;
  std::printf(
      "measured: alpha = 0.5 alpha*: slip speed %.4g m/s (creep %.4g), spin rate %.6g rad/s^2 (pure rolling "
      "%.6g); balance %.3g J of (dissipated + roller's energy) %.3g J\n",
      slip, creep, std::abs(rate), rolling_rate, balance, lost);
  EXPECT_NEAR(std::abs(slip), creep, 0.02 * creep);
  EXPECT_NEAR(std::abs(rate), rolling_rate, 1e-3 * rolling_rate);
  EXPECT_LT(balance, 1e-4 * lost);
  run(2.0, "roller_slips", &slip, &rate, &balance, &lost);
  const double slip_ref = (2.0 * alpha_star * kRb - mu * f0 * kRr * kRr / j) * end;
  const double rate_ref = mu * f0 * kRr / j;
  std::printf(
      "measured: alpha = 2 alpha*: slip speed %.6g m/s (closed form %.6g), spin rate %.6g rad/s^2 (mu fn Rr "
      "/ J "
      "%.6g); balance %.3g J of (dissipated + roller's energy) %.3g J\n",
      std::abs(slip), slip_ref, std::abs(rate), rate_ref, balance, lost);
  EXPECT_NEAR(std::abs(slip), slip_ref, 0.01 * slip_ref);
  EXPECT_NEAR(std::abs(rate), rate_ref, 1e-3 * rate_ref);
  EXPECT_LT(balance, 1e-4 * lost);
}

// A quasi-static valvetrain state: the lifter pressed on the base circle (Rb 20 mm) of the resting tangent
// cam by the spring's preload of 500 N, the contact damped (e = 0.3 at 0.01 m/s) so that the lifter settles
// within a few ms. At rest (the last sample, 20 ms) the contact force is the spring's, preload - k delta
// (statics), and the approach, the semi-axes and p0 are Hertz's exact ones at that force, through Harris &
// Kotzalas's dimensionless a*, b*, delta* (Rolling Bearing Analysis, 5th ed. 2007, eqs. 6.39-6.41):
//   s = (3 F / (2 Sigma rho E*))^(1/3),  a = a* s,  b = b* s,  delta = delta* s^2 Sigma rho / 2,  p0 = 3 F /
//   (2 pi a b),
// Sigma rho = 1/Rx + 1/Rc, Rx = 1/(1/Rr + 1/Rb) = 7.5 mm, with a*, b*, delta* from SciPy
// (testdata/valvetrain/hertz_ellipse_reference.csv, the rows r = 2.5 and 100). Crowns: 100 Rx and 2.5 Rx (the
// major semi-axis along the roller's axis: `half_length`), and Rx / 2.5 (the major one along the rolling
// direction: `half_width`).
TEST(CrownedRoller, QuasiStaticContactOnTheBaseCircleAgainstExactHertz) {
  struct Case {
    double ratio, a_star, b_star, delta_star;
    bool major_along_axis;
  };
  const double rx = 1 / (1 / kRr + 1 / kRb), preload = 500, k_spring = 5e4;
  double worst = 0;
  for (const Case& c : {Case{100, 5.9606853421778849, 0.32774243048711299, 0.45813148339222037, true},
                        Case{2.5, 1.3863947124652316, 0.75437998388038607, 0.95566091398570907, true},
                        Case{2.5, 1.3863947124652316, 0.75437998388038607, 0.95566091398570907, false}}) {
    const double crown = c.major_along_axis ? rx * c.ratio : rx / c.ratio;
    const std::string keys = "crown_radius = " + num(crown) + "\nrestitution = 0.3\nreference_speed = 0.01\n";
    const auto file = run_text(scene("rpm = 0", preload, keys, 0.02, 1e-5, 1000),
                               "crowned_static_" + std::to_string(int(crown * 1e4)));
    const Eigen::Index last = signal(file, "time").size() - 1;
    const double f = signal(file, "forces/cam/normal_force")[last],
                 delta = -signal(file, "forces/cam/gap")[last],
                 p0 = signal(file, "forces/cam/hertz_pressure")[last],
                 width = signal(file, "forces/cam/half_width")[last],
                 length = signal(file, "forces/cam/half_length")[last];
    const double sigma = 1 / rx + 1 / crown, s = std::cbrt(3 * f / (2 * sigma * kEStar));
    const double a = c.a_star * s, b = c.b_star * s, delta_ref = c.delta_star * s * s * sigma / 2;
    const double p_ref = 3 * f / (2 * kPi * a * b);
    const double major = c.major_along_axis ? length : width, minor = c.major_along_axis ? width : length;
    const double err_f = f / (preload - k_spring * delta) - 1, err_d = delta / delta_ref - 1,
                 err_a = major / a - 1, err_b = minor / b - 1, err_p = p0 / p_ref - 1;
    std::printf(
        "measured: crown %.4g m (ratio %g, major along the %s): F %.6g N (statics %+.1e), delta %.5g um "
        "(%+.1e), a %.5g mm (%+.1e), b %.5g mm (%+.1e), p0 %.6g MPa (%+.1e)\n",
        crown, c.ratio, c.major_along_axis ? "axis" : "rolling direction", f, err_f, delta * 1e6, err_d,
        a * 1e3, err_a, b * 1e3, err_b, p0 * 1e-6, err_p);
    for (const double err : {err_f, err_d, err_a, err_b, err_p}) {
      EXPECT_LT(std::abs(err), 1e-6) << "crown " << crown;
      worst = std::max(worst, std::abs(err));
    }
  }
  std::printf("measured: quasi-static crowned contact against exact Hertz, worst relative error %.2e\n",
              worst);
}

}  // namespace
}  // namespace nvh::solve
