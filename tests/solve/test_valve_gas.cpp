// The cylinder's gas on the exhaust valve (testdata/valvetrain/valvetrain.toml's [[load]] "gas", off in the
// motored scene; issue 13 item 2): the shipped scene with the gas load on and off, at a low cam speed where
// the chain is quasi-static, against the statics of the rocker. With the valve open, the foot carries the
// valve's spring, its gas load and its inertia; the rocker turns the foot's force into the pushrod's by the
// lever ratio b / a = 58 / 40 (both arms on one line through the pivot: the ratio holds at any rocker angle).
// Between the two runs the inertia is the same (the same kinematics to a tenth of a millimetre), so
//   F_pushrod(gas) - F_pushrod(motored) = (b / a) (F_gas(theta) + k dlift),
// F_gas = 196.35 N/bar x the table's pressure difference at the cam angle (exhaust_valve_gas.csv, read here),
// k dlift the valve spring's force change (40.9 N/mm) from the smaller lift the gas leaves. The valve's
// opening against the gas rings the chain (its 0.9 kHz mode, about 1.2 cam deg here: +-20 % early, +-2 % by
// 236 deg), so the two sides are compared as their means over 222-240 cam deg (8 to 1 bar; some 15 periods).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::signal;

// The CSV's pressure difference (bar) against the cam angle (deg), on its 0.5 deg grid.
std::map<double, double> gas_table() {
  std::ifstream in(std::string(NVH_SOURCE_DIR) + "/testdata/valvetrain/exhaust_valve_gas.csv");
  std::map<double, double> dp;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 'c') continue;
    std::istringstream row(line);
    double cam = 0, crank = 0, bar = 0;
    char comma = 0;
    row >> cam >> comma >> crank >> comma >> bar;
    dp[cam] = bar;
  }
  return dp;
}

TEST(ValveGas, PushrodCarriesTheGasLoadTimesTheRockerRatio) {
  constexpr double kScale = 196.35, kRatio = 0.058 / 0.040, kSpring = 40886;
  auto run = [](const std::string& scale) {
    const std::string text = testing::shipped_scene(
        "valvetrain/valvetrain.toml",
        {{"scale = 0                  # sweep: gas_scale", "scale = " + scale + " # sweep: gas_scale"},
         {"rpm = 650 ", "rpm = 200 "},
         {"end_angle_deg = 760", "end_angle_deg = 240"},
         {"sample_rate_hz = 40000", "sample_rate_hz = 12000"}});
    return testing::run_text(text, "valve_gas_" + scale, nullptr, "valvetrain");
  };
  const auto with_gas = run("196.35"), motored = run("0");
  const auto dp = gas_table();
  ASSERT_GT(dp.size(), 700u);
  const auto angle = signal(with_gas, "crank_angle_deg");
  ASSERT_EQ(angle.size(), signal(motored, "crank_angle_deg").size());
  const auto push_gas = signal(with_gas, "forces/pushrod/force_i"),
             push_motored = signal(motored, "forces/pushrod/force_i");
  const auto y_gas = signal(with_gas, "bodies/valve/position", 1),
             y_motored = signal(motored, "bodies/valve/position", 1);
  const auto load = signal(with_gas, "forces/gas/magnitude");
  double worst_load = 0, sum_measured = 0, sum_expected = 0;
  int checked = 0;
  for (int k = 0; k < angle.size(); ++k) {
    // The load itself, everywhere: the table at the clock's angle (linear between its 0.5 deg points).
    const double cam = std::fmod(angle[k], 360.0);
    const auto hi = dp.upper_bound(cam);
    const auto lo = std::prev(hi);
    const double bar =
        hi == dp.end() ? lo->second
                       : lo->second + (hi->second - lo->second) * (cam - lo->first) / (hi->first - lo->first);
    worst_load = std::max(worst_load, std::abs(load[k] - kScale * bar));
    // The statics while the valve is open and the gas pushes (the main lift starts at 218 deg, EVO).
    if (cam < 222 || cam > 240) continue;
    const double dlift = y_motored[k] - y_gas[k];  // the lift's change (lift = y0 - y): < 0 with the gas
    sum_expected += kRatio * (kScale * bar + kSpring * dlift);
    sum_measured += push_gas[k] - push_motored[k];
    ++checked;
  }
  EXPECT_GT(checked, 100);
  // N: the table times the scale, at the clock's angle. The load reads the clock's integrated state, the
  // results its measured angle (scene-format.md section 6); they differ by the state's integration error,
  // here about 5e-9 deg on the table's steepest slope (measured 1.1e-5 N; 1e-9 N before the angle was
  // measured)
  EXPECT_LT(worst_load, 1e-4);
  const double error = sum_measured / sum_expected - 1;
  EXPECT_LT(std::abs(error), 0.01);  // of the pushrod force's change, mean over the window (measured -0.18 %)
  std::printf(
      "valve gas: load within %.1e N of the table; the pushrod force's change over 222-240 deg: %.1f N "
      "mean against the statics' %.1f N (%+.2f %%)\n",
      worst_load, sum_measured / checked, sum_expected / checked, 100 * error);
}

}  // namespace
}  // namespace nvh::solve
