// The bridge over two valves (testdata/valvetrain/valvetrain_bridge.toml; docs/valvetrain.md section 8): the
// shipped scene at a low cam speed with 0.1 mm more lash at valve 2, against the statics of a bridge that is
// free to tilt between its valves and loaded at its middle - the two pads share the foot's force equally
// whatever the lashes, so both valves open alike, and the bridge tilts by the lash difference over the pads'
// span, 0.1 mm / 40 mm = 2.5 mrad (a simply supported beam loaded at mid-span; any statics text).
#include <gtest/gtest.h>

#include <cmath>

#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::signal;

TEST(ValveBridge, PadsShareTheFootForceAndTheBridgeTiltsByTheLashDifference) {
  // 200 cam rpm, from the base circle to past the top of the lift (the nose at 270 deg); 0.1 mm at pad 2.
  const std::string text = testing::shipped_scene(
      "valvetrain/valvetrain_bridge.toml",
      {{"rpm = 650 ", "rpm = 200 "},
       {"end_angle_deg = 760", "end_angle_deg = 275"},
       {"sample_rate_hz = 40000", "sample_rate_hz = 2000"},
       {"i = \"bridge.pad2\"\nj = \"valve2.tip\"\n", "i = \"bridge.pad2\"\nj = \"valve2.tip\"\nclearance = 0.0001\n"}});
  const auto out = testing::run_text(text, "valve_bridge");
  const auto a = signal(out, "crank_angle_deg");
  const auto f1 = signal(out, "forces/pad1/normal_force"), f2 = signal(out, "forces/pad2/normal_force");
  const auto foot = signal(out, "forces/lash/normal_force"), tilt = signal(out, "forces/bridge_guide/rotation_x");
  const auto y1 = signal(out, "bodies/valve1/position", 1), y2 = signal(out, "bodies/valve2/position", 1);
  // Around the top of the lift (260..275 deg): the valves are open by about 13 mm.
  double share = 0, tilt_err = 0, lift_diff = 0, sum_err = 0;
  int n = 0;
  for (int k = 0; k < a.size(); ++k) {
    if (a[k] < 260) continue;
    ++n;
    share = std::max(share, std::abs(f1[k] - f2[k]) / (f1[k] + f2[k]));
    tilt_err = std::max(tilt_err, std::abs(std::abs(tilt[k]) - 2.5e-3));
    lift_diff = std::max(lift_diff, std::abs((y1[0] - y1[k]) - (y2[0] - y2[k])));
    sum_err = std::max(sum_err, std::abs(f1[k] + f2[k] - foot[k]) / foot[k]);
    EXPECT_GT(y1[0] - y1[k], 0.012);
  }
  ASSERT_GT(n, 10);
  std::printf("bridge at the top: pads differ by %.2e of their sum, tilt within %.2e rad of 2.5 mrad, lifts "
              "differ by %.2e m, pads against foot %.2e\n", share, tilt_err, lift_diff, sum_err);
  // Equal halves: measured 1.3e-4 of the sum (0.2 N of 1.7 kN: the bridge's inertia, the friction and damping).
  EXPECT_LT(share, 2e-3);
  // Equal forces on equal springs give equal lifts; the springs are soft (40.9 N/mm), so the 0.2 N left over
  // shows as 5 um (measured 4.8 um), and the tilt is (0.1 mm - that) / 40 mm: 1.2e-4 rad from 2.5 mrad.
  EXPECT_LT(lift_diff, 1e-5);  // m
  EXPECT_LT(tilt_err, 2.5e-4); // rad
  EXPECT_LT(sum_err, 2e-2);   // the bridge's weight and inertia (0.15 kg) against ~2 kN
}

}  // namespace
}  // namespace nvh::solve
