// The piston-liner element (solve/elements/piston_liner.cpp) against references not computed with this code.
//
// 1. Squeeze of a centred piston (V = 0, full circle, full film): the element's side force and pin moment
// against
//    SkirtFilm called directly (the element only maps the markers; 1e-12), against the separated solution of
//    the squeeze film F = -pi R A (L - 2 R tanh(L / 2R)), A = 12 mu v R^2 / c^3 (docs/bearing.md,
//    section 14.5), and at L/R = 0.05 against the short-bearing (Ocvirk) limit -pi mu R L^3 v / c^3, with the
//    grids and tolerances of tests/bearing/test_skirt.cpp (7e-4 at 80 x 144 cells and L/D 0.8; 5e-4 at 160 x
//    72, L/R 0.05). The moment about the pin of a uniform squeeze is -y_c F (y_c the skirt's centre).
// 2. Energy over a cycle: a prescribed periodic motion (sliding, lateral and tilt, in and out of asperity
//    contact). The wrenches' work is stored by the asperities or dissipated, so over a closed cycle (the
//    asperities' energy returns to its start)
//      int power_loss dt = int -F_friction V dt + int -(F_side e'_pin - M tilt') dt
//    with e'_pin, tilt' = d/dt (x_j . z_i) and V from the prescribed motion, not from the element.
// 3. The slap scene testdata/scenes/piston_slap_film.toml (two revolutions, IDA): the side force's sign
// changes
//    against the slider-crank force balance at constant crank speed, from the crank geometry alone: the
//    piston (mass m_p, acceleration a_p along the bore) takes R_y = F_gas + m_p a_p from the conrod; the
//    conrod (mass m_r, its centre of mass G half-way, inertia I_r, angular acceleration alpha; big end B,
//    small end P) balances its moments about B:  (P - B)_y R_x - (P - B)_x R_y = I_r alpha + ((G - B) x m_r
//    a_G)_z, and the liner's force on the piston is F_side = -R_x. With a massless conrod this is F_side =
//    -(F_gas + m_p a_p) tan(beta): sign changes at the dead centres only; the conrod's inertia adds two near
//    259 and 299 deg. The liner's friction
//    (~35 N at mid-stroke, times tan(beta) <= 0.26 laterally) is not in the balance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>

#include "common/input.hpp"
#include "solve/bearing/skirt_film.hpp"
#include "solve/element_registry.hpp"
#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

constexpr double kPi = std::numbers::pi;

struct Built {
  input::Document doc;
  std::unique_ptr<ForceElement> element;
};

Built build(const std::string& keys) {
  const ElementType* et = builtin_elements().find("force", "piston-liner");
  Built b{input::Document::parse(keys, "piston-liner.toml"), nullptr};
  if (!et) {
    ADD_FAILURE() << "piston-liner is not registered";
    return b;
  }
  const input::Table t = b.doc.root();
  std::vector<std::filesystem::path> files;
  ElementContext c{t, ".", files, {MarkerMotion{}, MarkerMotion{}}, {"piston", "ground"}};
  b.element = et->make(c);
  t.finish();
  return b;
}

struct Evaluated {
  std::vector<Wrench> wrenches = std::vector<Wrench>(2);
  std::vector<double> channels;
  ElementEnergy energy;
};

/// Channels: min_film, max_pressure, side_force, pin_moment, friction_force, power_loss, asperity_force,
/// oil_flow, eccentricity_top, eccentricity_bottom, sliding_speed, asperity_energy.
enum { kSide = 2, kMoment = 3, kFriction = 4, kPowerLoss = 5, kAsperity = 6, kAsperityEnergy = 11 };

Evaluated evaluate(const ForceElement& e, const MarkerMotion& i, const MarkerMotion& j) {
  Evaluated out;
  const std::vector<MarkerMotion> markers{i, j};
  const ElementInput in{0.0, 0.0, markers, {}, {}};
  ElementOutput o{out.wrenches, {}};
  e.evaluate(in, o);
  out.channels.resize(e.channels().size());
  e.channel_values(in, out.channels);
  out.energy = e.energy(in);
  return out;
}

std::string squeeze_keys(double R, double c, double L, int axial, int around) {
  std::ostringstream k;
  k.precision(17);
  k << "bore_radius = " << R << "\nradial_clearance = " << c << "\nskirt_length = " << L
    << "\nskirt_top = " << 0.6 * L << "\nviscosity = 0.01\ncavitation = \"none\"\narcs_deg = [[-180, 180]]\n"
    << "cells_axial = " << axial << "\ncells_around = " << around << "\n";
  return k.str();
}

// The piston centred in the bore (markers coincide, axes equal: x the thrust direction, z the bore axis)
// moving along x at v: the squeeze of a centred cylinder.
TEST(PistonLiner, SqueezeOfACentredPistonAgainstSkirtFilmAndClosedForms) {
  const double R = 0.04, c = 20e-6, mu = 0.01, v = 2e-3;
  struct Case {
    double L;
    int axial, around;
    double tolerance;
    bool short_limit;
  };
  for (const Case& cs : {Case{1.6 * R, 80, 144, 7e-4, false}, Case{0.05 * R, 160, 72, 5e-4, true}}) {
    const double L = cs.L;
    const Built b = build(squeeze_keys(R, c, L, cs.axial, cs.around));
    MarkerMotion i, j;
    i.velocity = Vec3(v, 0, 0);
    const Evaluated r = evaluate(*b.element, i, j);
    // SkirtFilm directly, the same spec
    bearing::SkirtSpec s;
    s.bore_radius = R, s.radial_clearance = c, s.skirt_length = L, s.skirt_top = 0.6 * L, s.viscosity = mu;
    s.cavitation = bearing::Cavitation::kNone, s.arcs = {{-kPi, kPi}};
    s.cells_axial = cs.axial, s.cells_around = cs.around;
    bearing::SkirtFilm film(s);
    const bearing::SkirtResult direct = film.evaluate({0, 0, v, v, 0});
    const double F = r.channels[kSide], M = r.channels[kMoment];
    EXPECT_NEAR(F, direct.side_force, 1e-12 * std::abs(direct.side_force));
    EXPECT_NEAR(M, direct.moment, 1e-12 * std::abs(direct.moment));
    EXPECT_NEAR(r.wrenches[0].force.x(), F, 1e-12 * std::abs(F));    // along x_j
    EXPECT_NEAR(r.wrenches[0].torque.y(), -M, 1e-12 * std::abs(M));  // M (x_j x z_i) = -M y
    EXPECT_NEAR((r.wrenches[0].force + r.wrenches[1].force).norm(), 0.0, 1e-12 * std::abs(F));  // reaction
    const double A = 12 * mu * v * R * R / (c * c * c);
    const double reference = cs.short_limit ? -kPi * mu * R * L * L * L * v / (c * c * c)
                                            : -kPi * R * A * (L - 2 * R * std::tanh(L / (2 * R)));
    const double yc = 0.6 * L - 0.5 * L;
    EXPECT_NEAR(F / reference - 1, 0.0, cs.tolerance) << (cs.short_limit ? "Ocvirk" : "separated");
    EXPECT_NEAR(M / (-yc * reference) - 1, 0.0, cs.tolerance);
    std::printf(
        "measured: piston-liner squeeze, L/R %.2f, %d x %d: side force %.6g N against %s %.6g N "
        "(relative %.2e, tolerance %.0e); pin moment relative %.2e\n",
        L / R, cs.axial, cs.around, F, cs.short_limit ? "Ocvirk" : "the separated solution", reference,
        F / reference - 1, cs.tolerance, M / (-yc * reference) - 1);
  }
}

// A periodic motion of period T: axial z = -(V0 / w) cos(w t) (V = V0 sin w t), the pin at x = e0 + e1 sin(w
// t + 0.7), the axis tilted about the pin axis by phi = phi0 sin(2 w t) (x_j . z_i = sin phi). The thrust
// side reaches h < 4 sigma (asperity contact) near the top of the lateral swing.
TEST(PistonLiner, CycleLossEqualsFrictionPowerPlusSqueezeWork) {
  const std::string keys =
      "bore_radius = 0.04\nradial_clearance = 30e-6\nskirt_length = 0.05\nskirt_top = 0.02\nviscosity = "
      "0.01\n"
      "barrel = [[-0.03, 10e-6], [-0.005, 0.0], [0.02, 10e-6]]\ncells_axial = 16\ncells_around = 12\n"
      "sigma = 1e-6\nK = 2.4e-4\nmodulus = 1.1e11\nmu_asperity = 0.1\n";
  const Built b = build(keys);
  const double w = 2 * kPi * 50, T = 2 * kPi / w, V0 = 10, e0 = 5e-6, e1 = 25e-6, phi0 = 2e-4;
  const int n = 4000;
  double loss = 0, friction = 0, squeeze = 0, u0 = 0, u_end = 0, largest_asperity = 0;
  for (int k = 0; k <= n; ++k) {
    const double t = k * T / n, weight = (k == 0 || k == n) ? 0.5 : 1.0;
    const double phi = phi0 * std::sin(2 * w * t), phi_dot = 2 * w * phi0 * std::cos(2 * w * t);
    const double x = e0 + e1 * std::sin(w * t + 0.7), x_dot = e1 * w * std::cos(w * t + 0.7);
    const double V = V0 * std::sin(w * t);
    MarkerMotion i, j;
    // rotation by -phi about y (the pin axis w = x_j x z_j = -y): z_i = (sin phi, 0, cos phi)
    i.axes = Eigen::AngleAxisd(phi, Vec3::UnitY()).toRotationMatrix();
    i.position = Vec3(x, 0, -V0 / w * std::cos(w * t));
    i.velocity = Vec3(x_dot, 0, V);
    i.angular_velocity = Vec3(0, phi_dot, 0);
    const Evaluated r = evaluate(*b.element, i, j);
    const double e_pin_dot = x_dot, tilt_dot = std::cos(phi) * phi_dot;  // d/dt (x_j . z_i) = d/dt sin(phi)
    const std::vector<double>& ch = r.channels;
    loss += weight * ch[kPowerLoss];
    friction -= weight * ch[kFriction] * V;
    squeeze -= weight * (ch[kSide] * e_pin_dot - ch[kMoment] * tilt_dot);
    EXPECT_NEAR(r.energy.dissipated, ch[kPowerLoss], 1e-12 * std::abs(ch[kPowerLoss]));
    EXPECT_NEAR(r.energy.stored, ch[kAsperityEnergy], 1e-12 * std::abs(ch[kAsperityEnergy]) + 1e-300);
    largest_asperity = std::max(largest_asperity, ch[kAsperity]);
    if (k == 0) u0 = ch[kAsperityEnergy];
    if (k == n) u_end = ch[kAsperityEnergy];
  }
  const double dt = T / n;
  loss *= dt, friction *= dt, squeeze *= dt;
  EXPECT_GT(largest_asperity, 10.0) << "the cycle should reach asperity contact";
  EXPECT_NEAR(u_end, u0, 1e-12 * std::max(1.0, u0));  // a closed cycle
  // Trapezoid rule on smooth periodic integrands (the asperity law is C^6 at its onset): the identity holds
  // to quadrature error; 1e-6 of the loss
  EXPECT_NEAR(loss, friction + squeeze, 1e-6 * loss);
  EXPECT_GT(friction, 0.0);
  std::printf(
      "measured: piston-liner cycle: loss %.9g J, friction power %.9g J + squeeze work %.9g J (relative "
      "difference %.2e, tolerance 1e-6); largest asperity force %.4g N\n",
      loss, friction, squeeze, (loss - friction - squeeze) / loss, largest_asperity);
}

// Bad input is an error located at its key (file:line:column and the key's name).
TEST(PistonLiner, BadInputNamesFileLineAndKey) {
  const std::string scene = testing::shipped_scene("scenes/piston_slap_film.toml");
  const auto error = [&](const std::string& from, const std::string& to) {
    std::string text = scene;
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return testing::scene_error(text);
  };
  const auto line_of = [&](const std::string& what) {
    return std::to_string(
        1 + std::count(scene.begin(), scene.begin() + static_cast<long>(scene.find(what)), '\n'));
  };
  std::string m = error("arcs_deg = [[-60, 60], [120, 240]]", "arcs_deg = [[-60, 60], [50, 240]]");
  EXPECT_NE(m.find("bad.toml:" + line_of("arcs_deg") + ":"), std::string::npos) << m;
  EXPECT_NE(m.find("arcs_deg"), std::string::npos) << m;
  m = error("modulus = 1.1e11", "");
  EXPECT_NE(m.find(".modulus'"), std::string::npos) << m;
  m = error("sigma_beta_eta = 0.04", "K = 1e-3\nsigma_beta_eta = 0.04");
  EXPECT_NE(m.find("bad.toml:"), std::string::npos) << m;
  EXPECT_NE(m.find(".K'"), std::string::npos) << m;
  m = error("radial_clearance = 30e-6", "radial_clearance = -30e-6");
  EXPECT_NE(m.find("bad.toml:" + line_of("radial_clearance") + ":"), std::string::npos) << m;
  m = error("bore_radius = 0.04", "bore_radius = 0.04\ndiameter = 0.08");
  EXPECT_NE(m.find(".bore_radius'"), std::string::npos) << m;
  m = error("cells_axial = 16", "cells_axial = 16\ncells_axal = 3");
  EXPECT_NE(m.find("cells_axal"), std::string::npos) << m;
}

// The slider-crank closed form of the lateral force on the piston (the top of this file): crank radius r,
// conrod l, crank angle theta from TDC turning about +z at w (the crank pin at (-r sin, r cos), the piston on
// +y).
double lateral_force(double theta_deg, double m_rod, double I_rod) {
  const double r = 0.05, l = 0.2, m_p = 0.4, w = 3000 * 2 * kPi / 60;
  // gas force (N, pushing the piston down) against crank angle: the scene's table, period 360 deg
  static const double table[][2] = {{0, 20000}, {20, 14000}, {60, 4000},   {120, 800},  {180, 0},
                                    {270, 600}, {330, 6000}, {350, 15000}, {360, 20000}};
  const double a = std::fmod(std::fmod(theta_deg, 360.0) + 360.0, 360.0);
  double gas = 0;
  for (int k = 0; k < 8; ++k)
    if (a >= table[k][0] && a <= table[k + 1][0])
      gas =
          table[k][1] + (a - table[k][0]) / (table[k + 1][0] - table[k][0]) * (table[k + 1][1] - table[k][1]);
  struct Ends {
    Eigen::Vector2d B, P;
  };
  const auto ends = [&](double t) {
    return Ends{{-r * std::sin(t), r * std::cos(t)},
                {0.0, r * std::cos(t) + std::sqrt(l * l - r * r * std::sin(t) * std::sin(t))}};
  };
  const auto angle = [](const Ends& e) { return std::atan2(e.P.y() - e.B.y(), e.P.x() - e.B.x()); };
  // accelerations at constant w by central differences of the closed-form positions (step 1e-4 rad)
  const double t = theta_deg * kPi / 180, h = 1e-4;
  const Ends e = ends(t), ep = ends(t + h), em = ends(t - h);
  const double s = w * w / (h * h);
  const Eigen::Vector2d aB = (ep.B - 2 * e.B + em.B) * s, aP = (ep.P - 2 * e.P + em.P) * s,
                        aG = 0.5 * (aB + aP);
  const double alpha = (angle(ep) - 2 * angle(e) + angle(em)) * s;
  const double Ry = gas + m_p * aP.y();
  const Eigen::Vector2d d = e.P - e.B, g = 0.5 * d;
  const double moment = I_rod * alpha + m_rod * (g.x() * aG.y() - g.y() * aG.x());
  const double Rx = (moment + d.x() * Ry) / d.y();
  return -Rx;
}

std::vector<double> sign_changes(const Eigen::VectorXd& x, const std::vector<double>& y, double from,
                                 double to) {
  std::vector<double> out;
  for (int k = 1; k < x.size(); ++k)
    if (x[k - 1] >= from && x[k] <= to && y[k - 1] != 0 && y[k] != 0 && (y[k] > 0) != (y[k - 1] > 0))
      out.push_back(x[k - 1] - y[k - 1] * (x[k] - x[k - 1]) / (y[k] - y[k - 1]));
  return out;
}

TEST(PistonLiner, SlapSceneThrustReversalsAgainstTheSliderCrankBalance) {
  RunSummary summary;
  const auto file =
      testing::run_text(testing::shipped_scene("scenes/piston_slap_film.toml"), "piston_slap_film", &summary);
  const Eigen::VectorXd theta = testing::signal(file, "crank_angle_deg");
  const Eigen::VectorXd side = testing::signal(file, "forces/skirt/side_force");
  ASSERT_GT(theta.size(), 100);
  EXPECT_GT(theta[theta.size() - 1], 719.0) << "two revolutions";
  std::vector<double> closed(theta.size()), massless(theta.size()),
      simulated(side.data(), side.data() + side.size());
  for (int k = 0; k < theta.size(); ++k)
    closed[k] = lateral_force(theta[k], 0.6, 0.002), massless[k] = lateral_force(theta[k], 0.0, 0.0);
  // after the start-up (the piston starts centred and at rest across the bore) and before the run's last
  // samples (the dead centre at 720 deg is its end): from 90 to 715 deg
  const std::vector<double> ref = sign_changes(theta, closed, 90.0, 715.0),
                            sim = sign_changes(theta, simulated, 90.0, 715.0);
  const std::vector<double> dead_centres = sign_changes(theta, massless, 90.0, 715.0);
  EXPECT_EQ(dead_centres.size(), 3u);  // 180, 360, 540: the massless conrod reverses at the dead centres only
  ASSERT_EQ(sim.size(), ref.size()) << "the number of thrust reversals after 90 deg";
  double worst = 0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    EXPECT_NEAR(sim[k], ref[k], 4.0) << "reversal " << k << " (deg)";
    worst = std::max(worst, std::abs(sim[k] - ref[k]));
    std::printf("measured: thrust reversal at %.2f deg, closed form %.2f deg (difference %+.2f deg)\n",
                sim[k], ref[k], sim[k] - ref[k]);
  }
  // the side force itself, away from the start: within 5 % of the largest closed-form force plus the
  // friction's lateral share (35 N x 0.26)
  double largest = 0, worst_force = 0;
  for (int k = 0; k < theta.size(); ++k)
    if (theta[k] >= 90) largest = std::max(largest, std::abs(closed[k]));
  for (int k = 0; k < theta.size(); ++k)
    if (theta[k] >= 90) worst_force = std::max(worst_force, std::abs(simulated[k] - closed[k]));
  EXPECT_LT(worst_force, 0.05 * largest + 10.0);
  // The run's energy balance (kinetic + dissipated - input, the element's power_loss among the dissipated):
  // its drift is the integration error (2.8e-2, 6.4e-3, 2.4e-3 J at rtol, velocity_atol = 1e-6, 1e-5; 1e-6,
  // 1e-6; 1e-7, 1e-6, the scene's); 1e-3 of the dissipated energy.
  const Eigen::VectorXd balance = testing::signal(file, "energy/balance");
  const Eigen::VectorXd dissipated = testing::signal(file, "energy/dissipated");
  const double drift = balance.cwiseAbs().maxCoeff(), lost = dissipated[dissipated.size() - 1];
  EXPECT_LT(drift, 1e-3 * lost);
  std::printf(
      "measured: slap scene: %zu reversals in 90 .. 715 deg, worst angle difference %.2f deg (tolerance 4); "
      "side force within %.1f N of the closed form (largest %.1f N); energy balance within %.3g J of %.4g J "
      "dissipated; %.2f s for two revolutions, %ld steps\n",
      sim.size(), worst, worst_force, largest, drift, lost, summary.wall_seconds,
      static_cast<long>(summary.statistics.steps));
}

}  // namespace
}  // namespace nvh::solve
