// The flexible roller follower lever (testdata/valvetrain/lever.toml, a Craig-Bampton beam superelement;
// docs/valvetrain.md section 10, "The flexible lever") against closed forms written out here:
//   1. its sections are the dimensions its comments give (rectangles, the boss's ligaments, the fork's
//   cheeks;
//      Roark's J, Cowper's shear factor: beam_statics.hpp);
//   2. its mass, centre of mass and Izz about the pivot are those of the file's beam and point masses summed
//   by
//      hand (a uniform bar per segment: rho A L, its first and second moments);
//   3. condense: its static compliance with the pivot clamped - at the roller and at the cup, and across (a
//   load
//      at one, the deflection at the other: both lie on the same side of the pivot) - is the stepped
//      Timoshenko cantilever's by the unit-load method (beam_statics.hpp);
//   4. solve: the valvetrain with the flexible lever (valvetrain_lever_flexible.toml) at 325 cam rpm against
//   the
//      lever chain's geometry (lever_chain.hpp) with the cup moved off the chord pivot-roller by the lever's
//      bending under the forces the run reports: with the pivot pinned, the roller held by the cam and the
//      cup loaded by the pushrod, the cup stands off the chord by w = u_c - (L_pp / L_rp) u_r, u the
//      cantilever's deflections across the lever (3's compliances, cross terms included) under the cam's and
//      the pushrod's forces across it. The forces are in moment balance about the pivot (up to the lever's
//      inertia), so the clamped and the pinned beam bend alike.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "beam_statics.hpp"
#include "common/hdf5.hpp"
#include "common/provenance.hpp"
#include "lever_chain.hpp"
#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

namespace fs = std::filesystem;
using beam_statics::cantilever;
using beam_statics::Compliance;
using beam_statics::rectangle;
using beam_statics::Section;
using namespace lever_chain;

const fs::path kValvetrain = fs::path(NVH_SOURCE_DIR) / "testdata/valvetrain";
constexpr double kRoller = 0.050, kCup = 0.060;  // m from the pivot, along the lever (component x)

condense::Component lever_component() {
  return condense::read_component(kValvetrain / "lever.toml");
}

// lever.toml's comments: the pivot boss as two ligaments 6 x 24 mm at +-13 mm around the bore (J of the solid
// 32 x 24 mm envelope), the arm a solid 22 x 20 mm, the fork two cheeks 4 (z) x 24 (y) mm at z = +-10 mm.
std::vector<Section> sections_from_dimensions() {
  Section boss = rectangle(0.006, 0.024);
  boss.A = 2 * 0.006 * 0.024;
  boss.Iy = 2 * 0.006 * std::pow(0.024, 3) / 12;
  boss.Iz = 2 * (0.024 * std::pow(0.006, 3) / 12 + 0.006 * 0.024 * 0.013 * 0.013);
  boss.J = rectangle(0.032, 0.024).J;
  Section fork = rectangle(0.024, 0.004);
  fork.A *= 2;
  fork.Iz *= 2;
  fork.Iy = 2 * (fork.Iy + 0.024 * 0.004 * 0.010 * 0.010);
  fork.J *= 2;
  return {boss, rectangle(0.022, 0.020), fork, fork};
}

TEST(FlexibleLever, SectionsAreTheDimensionsOfItsComments) {
  beam_statics::expect_sections(lever_component(), sections_from_dimensions());
}

// The consistent mass of the beam elements carries each segment's rigid-body mass properties exactly.
TEST(FlexibleLever, MassCentreAndInertiaAreTheFilesPartsSummed) {
  const condense::Component c = lever_component();
  const double rho = c.materials.at(c.beam.material).rho;
  double m = 0, s = 0, izz = 0;  // about the pivot
  for (std::size_t k = 0; k + 1 < c.beam.points.size(); ++k) {
    const double a = c.beam.points[k][0], b = c.beam.points[k + 1][0], area = c.beam.segment_sections[k].A;
    m += rho * area * (b - a);
    s += rho * area * (b * b - a * a) / 2;
    // a bar's second moment about the pivot (its section's own polar inertia about its axis is the Ix term)
    izz += rho * area * (b * b * b - a * a * a) / 3 + rho * c.beam.segment_sections[k].Iz * (b - a);
  }
  for (const auto& p : c.beam.masses) {
    m += p.m;
    s += p.m * p.at[0];
    izz += p.m * p.at[0] * p.at[0] + p.J[2];
  }
  const condense::Superelement se = beam_statics::condense_quietly(c);
  std::printf(
      "measured: mass %.6f kg (by hand %.6f), centre of mass %.4f mm (%.4f), Izz about the pivot %.5e "
      "kg m^2 (%.5e)\n",
      se.inertia.mass, m, se.inertia.center_of_mass.x() * 1e3, s / m * 1e3, se.inertia.inertia_origin(2, 2),
      izz);
  EXPECT_NEAR(se.inertia.mass, m, 1e-9 * m);
  EXPECT_NEAR(se.inertia.center_of_mass.x(), s / m, 1e-9);
  EXPECT_NEAR(se.inertia.inertia_origin(2, 2), izz, 1e-6 * izz);
  EXPECT_NEAR(m, 0.4053, 1e-4);        // kg: the file's comment
  EXPECT_NEAR(s / m, 0.0322, 1e-4);    // m
  EXPECT_NEAR(izz, 6.53e-4, 0.01e-4);  // kg m^2
}

TEST(FlexibleLever, StaticComplianceWithThePivotClampedIsTheSteppedCantilevers) {
  const condense::Component c = lever_component();
  const condense::Superelement se = beam_statics::condense_quietly(c);
  const std::pair<std::string, double> points[] = {{"roller", kRoller}, {"cup", kCup}};
  for (const auto& [load, xl] : points)
    for (const auto& [at, xp] : points) {
      const Compliance ref = cantilever(c, xl, xp);
      const double transverse = beam_statics::static_compliance(se, "pivot", load, at, 1),
                   axial = beam_statics::static_compliance(se, "pivot", load, at, 0);
      std::printf(
          "measured: load at the %s, deflection at the %s: %.6e m/N across (closed form %.6e = bending "
          "%.3e + shear %.3e), %.6e m/N along (%.6e)\n",
          load.c_str(), at.c_str(), transverse, ref.transverse(), ref.bending, ref.shear, axial, ref.axial);
      EXPECT_NEAR(transverse, ref.transverse(), 1e-6 * ref.transverse()) << load << " -> " << at;
      EXPECT_NEAR(axial, ref.axial, 1e-6 * ref.axial) << load << " -> " << at;
    }
}

// ------------------------------------------------------------------ the valvetrain at 325 cam rpm
TEST(FlexibleLever, TopOfTheLiftIsTheLeverChainsGeometryLessTheDeflectionsAndTheLeversBending) {
  const fs::path dir = fs::temp_directory_path() / ("nvh_flexible_lever_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const condense::Component c = lever_component();
  condense::write_superelement(dir / "lever.h5", beam_statics::condense_quietly(c),
                               make_provenance("test", 0, nullptr, {}));
  fs::copy_file(kValvetrain / "exhaust_valve_gas.csv", dir / "exhaust_valve_gas.csv",
                fs::copy_options::overwrite_existing);
  const std::string text =
      testing::shipped_scene("valvetrain/valvetrain_lever_flexible.toml",
                             {{"rpm = 650 ", "rpm = 325 "}, {"end_angle_deg = 760", "end_angle_deg = 300"}});
  const auto file = testing::run_text_at(text, "valvetrain_lever_flexible", dir,
                                         dir / "valvetrain_lever_flexible.results.h5");

  const auto cam = scene_cam();
  const auto y = testing::signal(file, "bodies/valve/position", 1);
  const std::vector<Sample> run = samples(file);
  const double c_rr = cantilever(c, kRoller, kRoller).transverse(),
               c_rc = cantilever(c, kRoller, kCup).transverse(),
               c_cc = cantilever(c, kCup, kCup).transverse();
  // The cup's offset from the chord: the forces across the lever (normal (-sin beta, cos beta)) from the cam
  // on the roller and from the pushrod on the cup (its force along the rod, from the cup towards the rigid
  // chain's ball).
  auto bending = [&](const Sample& s, double beta) {
    const double nx = -std::sin(beta), ny = std::cos(beta);
    const double cup_x = kLeverX + kLpp * std::cos(beta), cup_y = kLeverY + kLpp * std::sin(beta);
    const double phi = rocker_angle(cup_x, cup_y, kLength);
    const double ex = kPx - kA * std::cos(phi) - cup_x, ey = kPy - kA * std::sin(phi) - cup_y,
                 el = std::hypot(ex, ey);
    const double f_roller = s.cam_fx * nx + s.cam_fy * ny, f_cup = -s.pushrod_j * (ex * nx + ey * ny) / el;
    const double u_r = c_rr * f_roller + c_rc * f_cup, u_c = c_rc * f_roller + c_cc * f_cup;
    return u_c - kLpp / kLrp * u_r;
  };
  double err = 0, err_rigid = 0, beta = 0, beta_rigid = 0, offset_top = 0;
  Eigen::Index top = 0;
  int n = 0;
  for (Eigen::Index k = 0; k < y.size(); ++k) {
    const double lift = kValveY0 - y[k];
    if (lift > kValveY0 - y[top]) top = k;
    if (lift < 0.002) continue;
    const Sample& s = run[static_cast<std::size_t>(k)];
    err = std::max(err, std::abs(lift - expected_lift(*cam, s, beta, bending)));
    err_rigid = std::max(err_rigid, std::abs(lift - expected_lift(*cam, s, beta_rigid, nullptr)));
    ++n;
  }
  {
    double b = beta;
    const double with = expected_lift(*cam, run[static_cast<std::size_t>(top)], b, bending);
    const double without = expected_lift(*cam, run[static_cast<std::size_t>(top)], b, nullptr);
    offset_top = without - with;
  }
  std::printf(
      "measured: valve lift at the top %.4f mm; the lever's bending takes %.3f um of it; largest error over "
      "%d samples with the valve open by more than 2 mm: %.3f um (%.3f um with the lever taken rigid)\n",
      (kValveY0 - y[top]) * 1e3, offset_top * 1e6, n, err * 1e6, err_rigid * 1e6);
  EXPECT_GT(n, 10);
  EXPECT_GT(offset_top, 2e-6);     // m: the bending is there to be seen (measured XXX um)
  EXPECT_LT(err, 5e-7);            // m (measured XXX um; the rigid lever's test 0.12 um)
  EXPECT_GT(err_rigid, 2 * 5e-7);  // the rigid lever's geometry misses it (measured 4.15 um)
  fs::remove_all(dir);
}

}  // namespace
}  // namespace nvh::solve
