// The valve seat contact (`[[force]] type = "valve-seat"`, solve/elements/valve_seat.cpp; issue 13, item 2)
// run through solve's library against references written out here, not taken from the element's code:
//   - Palmgren's approach of a steel line contact as Harris & Kotzalas print it (Rolling Bearing Analysis,
//     5th ed. 2007, eq. 6.46): delta [mm] = 3.84e-5 Q^0.9 / l^0.8, Q in N, l in mm;
//   - Johnson's Hertz line contact (Contact Mechanics 1985, eqs. 4.43, 4.45): p0 = sqrt(F E* / (pi L R)),
//     b = sqrt(4 F R / (pi L E*)), 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2;
//   - the seat cone's statics: the normal load F_n on the ring has the axial resultant F_n cos(beta) (the
//     radial parts cancel), and an axial closure delta_a is a normal approach delta_a cos(beta);
//   - Newton's law at rest (the seat carries the load), energy conservation of an undamped impact, and the
//     Hunt-Crossley rebound G(v_out) = G(v_in), G(v) = v/alpha - ln(1 + alpha v)/alpha^2 (exact for one
//     degree of freedom: solve_fixture.hpp) with its first-order form e = v_out / v_in at v_in = v_ref.
// The valve is a point mass on the axis of a ground seat (only axial forces act: it stays on the axis).
// Tolerances are stated at each assertion; the measured errors are printed ("measured: ...").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::hunt_crossley_rebound;
using testing::num;
using testing::run_text;
using testing::signal;
constexpr double kPi = std::numbers::pi;

// Steel on steel (Palmgren's law is for steel): E = 207 GPa, nu = 0.3.
const double kEStar = 1.0 / (2.0 * (1.0 - 0.3 * 0.3) / 207e9);
constexpr double kSeatDiameter = 0.03;  // m: L = pi d = 94.2 mm
constexpr double kFaceRadius = 0.05;    // m: the crowning of the face across the band (seat flat: R = 0.05)
constexpr double kMass = 0.05;          // kg: an inlet valve

/// Palmgren's approach (m) of a steel line contact under the normal load q (N) on the length l (m), as
/// printed: delta [mm] = 3.84e-5 Q^0.9 / l^0.8 with Q in N and l in mm.
double palmgren_approach(double q, double l) {
  return 1e-3 * 3.84e-5 * std::pow(q, 0.9) / std::pow(l * 1e3, 0.8);
}

/// A valve (point mass "valve", marker "face") above a ground seat (marker "seat", z up: the opening
/// direction) at gap `gap0` (m) moving at `v` (m/s, + opening), with the element's extra keys and more TOML.
std::string valve_scene(double gap0, double v, const std::string& seat_keys, const std::string& more,
                        double end_time, double rate_hz) {
  return R"(
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "seat"
[[body]]
name = "valve"
type = "point-mass"
mass = )" +
         num(kMass) + R"(
position = [0, 0, )" +
         num(gap0) + R"(]
velocity = [0, 0, )" +
         num(v) + R"(]
  [[body.marker]]
  name = "face"
[[force]]
name = "seat"
type = "valve-seat"
i = "valve.face"
j = "ground.seat"
seat_diameter = )" +
         num(kSeatDiameter) + R"(
face_radius = )" +
         num(kFaceRadius) + "\n" + seat_keys + more + R"(
[clock]
end_time = )" +
         num(end_time) + R"(
[output]
sample_rate_hz = )" +
         num(rate_hz) + "\n";
}

/// A constant axial load f (N) closing the valve (along -z).
std::string closing_load(double f) {
  return R"(
[[load]]
name = "spring"
type = "force"
at = "valve.face"
direction = [0, 0, -1]
table = [[0, )" +
         num(f) + "], [1, " + num(f) + "]]\n";
}

/// The channels at the last sample of a valve pressed on its seat by f (N) and settled (damping e = 0.5 at
/// 0.1 m/s: about critical at these loads); it lands from 1 um above the seat.
struct AtRest {
  double gap, normal, axial, pressure, half_width, speed;
};
AtRest seated(double f, const std::string& seat_keys, const std::string& name) {
  const std::string text =
      valve_scene(1e-6, 0.0, seat_keys + "restitution = 0.5\nreference_speed = 0.1\n",
                  closing_load(f) + "[integrator]\nrtol = 1e-10\natol = 1e-15\n", 0.003, 10000);
  const auto file = run_text(text, name);
  auto last = [&](const std::string& channel) {
    const Eigen::VectorXd s = signal(file, "forces/seat/" + channel);
    return s[s.size() - 1];
  };
  const Eigen::VectorXd vz = signal(file, "bodies/valve/velocity", 2);
  return {last("gap"),        last("normal_force"), last("axial_force"), last("hertz_pressure"),
          last("half_width"), vz[vz.size() - 1]};
}

double rel(double measured, double expected) {
  return std::abs(measured / expected - 1.0);
}

// ==================================================================== static seating, 45 deg
// At rest the seat carries the load: axial_force = F. The normal load on the ring F_n = F / cos(45 deg); its
// approach is Palmgren's, delta_n = -gap cos(45 deg); p0 and b are Johnson's for F_n on L = pi d, R.
TEST(ValveSeat, StaticSeatingAgainstPalmgrenAndJohnson) {
  const double f = 2000.0, c = std::cos(kPi / 4), l = kPi * kSeatDiameter, fn = f / c;
  const AtRest r = seated(f, "", "valve_seat_static");
  const double e_axial = rel(r.axial, f), e_normal = rel(r.normal, fn);
  const double e_approach = rel(-r.gap * c, palmgren_approach(fn, l));
  const double e_p0 = rel(r.pressure, std::sqrt(fn * kEStar / (kPi * l * kFaceRadius)));
  const double e_b = rel(r.half_width, std::sqrt(4.0 * fn * kFaceRadius / (kPi * l * kEStar)));
  std::printf(
      "measured: valve seat at rest under %.0f N (45 deg): axial force %.3g, normal force %.3g, approach "
      "(Palmgren, %.4g um) %.3g, p0 (Johnson, %.4g MPa) %.3g, b %.3g relative; speed %.2g m/s\n",
      f, e_axial, e_normal, palmgren_approach(fn, l) * 1e6, e_approach, r.pressure * 1e-6, e_p0, e_b,
      r.speed);
  EXPECT_LT(e_axial, 1e-6);
  EXPECT_LT(e_normal, 1e-6);
  EXPECT_LT(e_approach,
            1e-6);  // Palmgren's law is exact for steel on steel (hertz_line.hpp): F's error alone
  EXPECT_LT(e_p0, 1e-6);
  EXPECT_LT(e_b, 1e-6);
}

// A seat insert of another material (a copper-beryllium insert: E = 130 GPa, nu = 0.3; an austenitic valve:
// E = 200 GPa, nu = 0.29) and a concave seat (radius -0.2 m across the band): p0 and b are Johnson's with
// 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 and 1/R = 1/R1 + 1/R2, written out here.
TEST(ValveSeat, MaterialsAndSeatCrowningThroughJohnson) {
  const double f = 2000.0, c = std::cos(kPi / 4), l = kPi * kSeatDiameter, fn = f / c;
  const double e_star = 1.0 / ((1.0 - 0.29 * 0.29) / 200e9 + (1.0 - 0.3 * 0.3) / 130e9);
  const double r = 1.0 / (1.0 / kFaceRadius + 1.0 / -0.2);
  const AtRest a = seated(f,
                          "valve_youngs_modulus = 200e9\nvalve_poisson = 0.29\nseat_youngs_modulus = 130e9\n"
                          "seat_poisson = 0.3\nseat_radius = -0.2\n",
                          "valve_seat_materials");
  const double e_p0 = rel(a.pressure, std::sqrt(fn * e_star / (kPi * l * r)));
  const double e_b = rel(a.half_width, std::sqrt(4.0 * fn * r / (kPi * l * e_star)));
  std::printf(
      "measured: valve seat, CuBe insert and concave seat: p0 %.4g MPa error %.3g, b %.4g um error %.3g\n",
      a.pressure * 1e-6, e_p0, a.half_width * 1e6, e_b);
  EXPECT_LT(e_p0, 1e-6);
  EXPECT_LT(e_b, 1e-6);
}

// ==================================================================== the seat angle
// The same load on a 30 deg seat, a 45 deg one and a flat one (0 deg): F_n / F_a = 1 / cos(beta) and the
// axial closure -gap = delta_n / cos(beta) with delta_n Palmgren's for F_n. A measured axial `stiffness` k
// instead: -gap = F / k, F_n = F / cos(beta).
TEST(ValveSeat, SeatAngleGeometry) {
  const double f = 2000.0, l = kPi * kSeatDiameter;
  double worst_ratio = 0, worst_gap = 0;
  for (double deg : {45.0, 30.0, 0.0}) {
    const double c = std::cos(deg * kPi / 180.0);
    const AtRest r = seated(f, "seat_angle_deg = " + num(deg) + "\n", "valve_seat_angle_" + num(deg));
    const double e_ratio = rel(r.normal / r.axial, 1.0 / c);
    const double e_gap = rel(-r.gap, palmgren_approach(f / c, l) / c);
    std::printf(
        "measured: valve seat %2.0f deg: F_n / F_a = %.7f (1 / cos = %.7f), error %.3g; axial closure "
        "%.5g um, error %.3g\n",
        deg, r.normal / r.axial, 1.0 / c, e_ratio, -r.gap * 1e6, e_gap);
    EXPECT_LT(e_ratio, 1e-9);  // a ratio of two channels of one sample: round-off
    EXPECT_LT(e_gap, 1e-6);
    worst_ratio = std::max(worst_ratio, e_ratio);
    worst_gap = std::max(worst_gap, e_gap);
  }
  const double k = 5e8;
  const AtRest r = seated(f, "seat_angle_deg = 30.0\nstiffness = " + num(k) + "\n", "valve_seat_linear");
  const double e_gap = rel(-r.gap, f / k), e_normal = rel(r.normal, f / std::cos(kPi / 6));
  std::printf(
      "measured: valve seat, axial stiffness %.3g N/m at 30 deg: closure error %.3g, normal force error "
      "%.3g\n",
      k, e_gap, e_normal);
  EXPECT_LT(e_gap, 1e-6);
  EXPECT_LT(e_normal, 1e-6);
}

// ==================================================================== impact
// The valve 0.1 mm above the seat closing at v0 = 0.5 m/s, no load: it flies at v0 to the seat, bounces and
// leaves at v_out. Without damping (e = 1) v_out = v0 (energy conservation; the tolerance 1e-3 is the
// integrator's over a 20 us impact, rtol 1e-9); the closing_speed channel reads v0 up to the impact.
struct Bounce {
  double v_out, closing_before, balance;
};
Bounce bounce(double v0, const std::string& keys, const std::string& name) {
  const std::string text =
      valve_scene(1e-4, -v0, keys, "[integrator]\nrtol = 1e-9\natol = 1e-14\n", 2e-4 + 1e-4, 1e6);
  const auto file = run_text(text, name);
  const Eigen::VectorXd gap = signal(file, "forces/seat/gap"),
                        closing = signal(file, "forces/seat/closing_speed");
  const Eigen::VectorXd vz = signal(file, "bodies/valve/velocity", 2),
                        balance = signal(file, "energy/balance");
  Eigen::Index k = 0;
  while (k + 1 < gap.size() && gap[k + 1] > 0) ++k;  // the last sample before the first contact
  EXPECT_LT(k + 1, gap.size()) << name << ": no contact";
  EXPECT_GT(gap[gap.size() - 1], 0) << name << ": still in contact at the end";
  return {vz[vz.size() - 1], closing[k], balance.cwiseAbs().maxCoeff()};
}

TEST(ValveSeat, ElasticImpactReboundsAtTheSeatingSpeed) {
  const double v0 = 0.5;
  const Bounce b = bounce(v0, "restitution = 1.0\n", "valve_seat_elastic");
  const double e_rebound = rel(b.v_out, v0), e_closing = rel(b.closing_before, v0);
  const double ke = 0.5 * kMass * v0 * v0;
  std::printf(
      "measured: valve seat elastic impact at %.2f m/s: rebound %.9f m/s (error %.3g), closing_speed "
      "before contact error %.3g, energy balance %.3g of the kinetic energy\n",
      v0, b.v_out, e_rebound, e_closing, b.balance / ke);
  EXPECT_LT(e_rebound, 1e-3);
  EXPECT_LT(e_closing, 1e-6);       // free flight, read from IDA's interpolant (rtol 1e-9): measured 2e-9
  EXPECT_LT(b.balance / ke, 1e-3);  // the stored energy P delta_n / (n + 1) against the force's work
}

// Hunt-Crossley damping with e at the reference speed v_ref = v0 (axial): the rebound ratio against the
// exact G(v_out) = G(v_in) of the law, alpha = 3 (1 - e) / (2 v_ref) (1e-3: the integrator's), and against e
// itself, which is the law's ratio only to first order in alpha v0 (Hunt & Crossley 1975: e = 1 - (2/3) alpha
// v; the exact ratio is 0.909 at e = 0.9, 0.833 at 0.8): within 5 % for e >= 0.8.
TEST(ValveSeat, DampedImpactReboundRatio) {
  const double v0 = 0.5;
  for (double e : {0.9, 0.8}) {
    const Bounce b = bounce(v0, "restitution = " + num(e) + "\nreference_speed = " + num(v0) + "\n",
                            "valve_seat_damped_" + num(e));
    const double ratio = b.v_out / v0, exact = hunt_crossley_rebound(3.0 * (1.0 - e) / (2.0 * v0), v0) / v0;
    const double ke = 0.5 * kMass * v0 * v0;
    std::printf(
        "measured: valve seat impact e = %.2f at v_ref = v0 = %.2f m/s: rebound ratio %.6f, exact "
        "(G(v_out) = G(v_in)) %.6f (error %.3g), against e %.3g; energy balance %.3g of the kinetic "
        "energy\n",
        e, v0, ratio, exact, rel(ratio, exact), rel(ratio, e), b.balance / ke);
    EXPECT_LT(rel(ratio, exact), 1e-3);
    EXPECT_LT(rel(ratio, e), 0.05);
    EXPECT_LT(b.balance / ke, 1e-3);  // dissipated = the damping part's power, integrated
  }
}

// Refused keys name themselves: a concave seat tighter than the face (no contact line), a seat radius of 0, a
// seat angle at which the cone is nearly a cylinder.
TEST(ValveSeat, BadGeometryIsRefusedWithItsKey) {
  const std::string base = valve_scene(0.0, 0.0, "", "", 0.01, 1000);
  for (const auto& [keys, key] : std::vector<std::pair<std::string, std::string>>{
           {"seat_radius = -0.04\n", "seat_radius"},
           {"seat_radius = -0.05\n", "seat_radius"},
           {"seat_radius = 0.0\n", "seat_radius"},
           {"seat_angle_deg = 85.0\n", "seat_angle_deg"},
           {"seat_diameter_typo = 1.0\n", "seat_diameter_typo"}}) {
    std::string text = base;
    text.insert(text.find("[clock]"), keys);
    const std::string msg = testing::scene_error(text);
    EXPECT_NE(msg.find("bad.toml"), std::string::npos) << keys << msg;
    EXPECT_NE(msg.find(key), std::string::npos) << keys << msg;
  }
}

}  // namespace
}  // namespace nvh::solve
