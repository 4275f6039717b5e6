// The slap scene (testdata/slap/slap_film.toml, level (b)) with the film's liner given as markers
// (docs/bearing.md section 17), over its first 20 deg (the gas-exchange TDC's thrust change: the skirt
// crosses the clearance into the film on the anti-thrust side), against references not computed with the
// liner path:
// 1. The liner as 180 markers (15 levels x 12 angles) of a rigid ring body held to ground by a fixed joint
//    reproduces the rigid-liner element's run: the ring's states enter IDA's Newton through the element's
//    liner columns (the linearized-film Jacobian, `liner_jacobian` default) but not the answer. Measure: the
//    largest difference of the pin's lateral position over the window, against 1e-3 of the clearance (30 nm:
//    the integrator's tolerance, rtol 1e-7 of positions of 0.2 m plus atol 1e-9, over about 60 steps) and the
//    side force's largest difference against 1e-3 of its peak.
// 2. Energy over the window with the ring on a stiff bushing (1e9 N/m radially: it moves by about 1 um under
//    the film's load, so the film works on the liner markers): the run's energy balance (/energy/balance:
//    kinetic + potential + dissipated - input; the element's dissipation counts p dh/dt of the full dh/dt
//    including the liner's motion, section 17.3) equals the rigid-liner run's - whose error is the
//    integration's over the 4.9 J the crank train exchanges in the window, about 9e-5 J - to 0.1 of the
//    ring's largest elastic energy: a liner power missing from the element's accounting would shift it by
//    about that energy (the work the film does on the ring).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::column;
using testing::run_text;
using testing::shipped_scene;
using testing::signal;

constexpr double kPi = std::numbers::pi;

/// The ring body "liner": 15 levels (y = 0.065 .. 0.205 m, the skirt's travel) x 12 angles on the bore
/// (radius 43 mm; theta from the thrust side +x towards w = x cross y = +z), and its bore frame.
std::string ring_body(std::vector<std::string>& names) {
  std::ostringstream s;
  s << "[[body]]\nname = \"liner\"\ntype = \"rigid\"\nmass = 2.0\ninertia = [0.004, 0.002, 0.004]\n"
    << "  [[body.marker]]\n  name = \"main\"\n"
    << "  [[body.marker]]\n  name = \"bore\"\n  z = [0, 1, 0]\n  x = [1, 0, 0]\n";
  s.precision(9);
  for (int b = 0; b < 12; ++b)
    for (int a = 0; a < 15; ++a) {
      const double th = 2 * kPi * b / 12, y = 0.065 + 0.01 * a;
      std::ostringstream name;
      name << 'l' << a << '_' << b;
      names.push_back("liner." + name.str());
      s << "  [[body.marker]]\n  name = \"" << name.str() << "\"\n  at = [" << 0.043 * std::cos(th) << ", "
        << y << ", " << 0.043 * std::sin(th) << "]\n";
    }
  return s.str() + "\n";
}

std::string liner_scene(const std::string& holding) {
  std::vector<std::string> names;
  const std::string body = ring_body(names);
  std::string list = "liner = [";
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (k > 0) list += ", ";
    list += '"';
    list += names[k];
    list += '"';
  }
  list += "]\n";
  return shipped_scene("slap/slap_film.toml",
                       {{"[[body]]\nname = \"crank\"", body + "[[body]]\nname = \"crank\""},
                        {"j = \"ground.bore\"\n", "j = \"liner.bore\"\n" + list},
                        {"[[driver]]", holding + "\n[[driver]]"},
                        {"end_cycles = 1", "end_angle_deg = 20"}});
}

const std::string kRigid = "end_cycles = 1";

TEST(SlapEhl, RingOfMarkersHeldReproducesTheRigidLiner) {
  RunSummary rs, ls;
  const auto rigid = run_text(shipped_scene("slap/slap_film.toml", {{kRigid, "end_angle_deg = 20"}}),
                              "slap_ehl_rigid", &rs, "slap");
  const auto held = run_text(
      liner_scene("[[joint]]\nname = \"hold\"\ntype = \"fixed\"\ni = \"liner.main\"\nj = \"ground.main\"\n"),
      "slap_ehl_held", &ls, "slap");
  const auto xr = column(rigid, "/markers/piston.pin/position", 0),
             xh = column(held, "/markers/piston.pin/position", 0);
  const auto fr = column(rigid, "/forces/skirt/side_force"), fh = column(held, "/forces/skirt/side_force");
  ASSERT_EQ(xr.size(), xh.size());
  double dx = 0, df = 0, peak = 0, travel = 0;
  for (std::size_t k = 0; k < xr.size(); ++k) {
    dx = std::max(dx, std::abs(xr[k] - xh[k]));
    df = std::max(df, std::abs(fr[k] - fh[k]));
    peak = std::max(peak, std::abs(fr[k]));
    travel = std::max(travel, std::abs(xr[k] - xr[0]));
  }
  EXPECT_GT(peak, 100.0) << "the window should load the film";
  EXPECT_GT(travel, 10e-6) << "the window should move the piston across the clearance";
  EXPECT_LT(dx, 30e-9);
  EXPECT_LT(df, 1e-3 * peak);
  std::printf(
      "measured: first 20 deg, liner as 180 markers on a held ring against the rigid liner: pin lateral "
      "difference %.3g m (tolerance 3e-8, pin travel %.3g m), side force difference %.3g N of peak %.5g N "
      "(tolerance 1e-3); steps %d against %d\n",
      dx, travel, df, peak, int(ls.statistics.steps), int(rs.statistics.steps));
}

TEST(SlapEhl, EnergyBalanceWithTheRingOnABushing) {
  RunSummary s;
  const auto rigid = run_text(shipped_scene("slap/slap_film.toml", {{kRigid, "end_angle_deg = 20"}}),
                              "slap_ehl_rigid2", nullptr, "slap");
  const auto h5 = run_text(
      liner_scene(
          "[[force]]\nname = \"ring_mount\"\ntype = \"bushing\"\ni = \"liner.main\"\nj = \"ground.main\"\n"
          "stiffness = [1e9, 1e10, 1e9, 1e7, 1e7, 1e7]\ndamping = [2e3, 2e3, 2e3, 1, 1, 1]\n"),
      "slap_ehl_bushing", &s, "slap");
  const auto balance = column(h5, "/energy/balance"), reference = column(rigid, "/energy/balance");
  const auto mount = column(h5, "/forces/ring_mount/displacement_x");
  ASSERT_EQ(balance.size(), reference.size());
  double worst = 0, ring = 0;
  for (std::size_t k = 0; k < balance.size(); ++k) {
    worst = std::max(worst, std::abs(balance[k] - reference[k]));
    ring = std::max(ring, 0.5 * 1e9 * mount[k] * mount[k]);  // the ring's elastic energy in x
  }
  EXPECT_GT(ring, 1e-4) << "the ring should take a sizeable energy";
  EXPECT_LT(worst, 0.1 * ring);
  std::printf(
      "measured: first 20 deg, ring on a 1e9 N/m bushing: largest difference of the energy balance from the "
      "rigid-liner run's %.3g J against the ring's largest elastic energy %.3g J (relative %.3f, tolerance "
      "0.1); rigid run's largest |balance| %.3g J; %d steps\n",
      worst, ring, worst / ring,
      *std::max_element(reference.begin(), reference.end(),
                        [](double a, double b) { return std::abs(a) < std::abs(b); }),
      int(s.statistics.steps));
}

}  // namespace
}  // namespace nvh::solve
