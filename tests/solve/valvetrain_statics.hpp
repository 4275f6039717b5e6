#pragma once
// The valvetrain of valvetrain.toml at the top of its lift, quasi-static (a low cam speed): the valve stands
// where the kinematic chain puts it (the paper's eq. 7 with the rocker ratio 58/40 and the lash), less the
// chain's elastic deflections under the forces a run reports, each by its closed form - the pushrod's rate
// EA/L, Palmgren's approach of the roller along the tappet's line (Harris & Kotzalas eq. 6.46, l = 15 mm),
// the elephant foot's Hertz sphere delta = (F / k)^(2/3) - and the pushrod's tilt: the rocker's ball end
// swings 40 mm (1 - cos phi) sideways as the rocker turns by phi = asin(lift / 40 mm), which shortens the 300
// mm pushrod's height by 0.3 - sqrt(0.3^2 - that^2). Shared by test_roller_cam.cpp (the 3-mass pushrod) and
// test_flexible_pushrod.cpp (the beam superelement).
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "solve_fixture.hpp"

namespace nvh::solve::valvetrain_statics {

struct TopOfLift {
  double kinematic, deflection, tilt, expected;  // m: the rigid chain's lift less the lash; the rest
};

/// pushrod_force, cam_force, lash_force (N) at the top; pushrod_rate EA/L (N/m).
inline TopOfLift top_of_lift(double pushrod_force, double cam_force, double lash_force, double pushrod_rate) {
  const double ratio = 0.058 / 0.040, cam_lift = 0.00966, lash = 0.0005;
  TopOfLift t;
  t.kinematic = ratio * cam_lift - lash;
  t.deflection = ratio * (pushrod_force / pushrod_rate +
                          3.84e-5 * std::pow(cam_force, 0.9) / std::pow(15.0, 0.8) * 1e-3) +
                 std::pow(lash_force / 1.5e10, 2.0 / 3.0);
  const double phi = std::asin(cam_lift / 0.040), swing = 0.040 * (1 - std::cos(phi));
  t.tilt = ratio * (0.3 - std::sqrt(0.3 * 0.3 - swing * swing));
  t.expected = t.kinematic - t.deflection - t.tilt;
  return t;
}

/// The valve's lift at the top of the second cam revolution of a results file of valvetrain.toml (or a
/// variant) less top_of_lift() under the forces reported there (the pushrod's force per sample given),
/// printed; m.
inline double top_of_second_lift_error(const std::filesystem::path& file,
                                       const Eigen::VectorXd& pushrod_force, double pushrod_rate) {
  using testing::signal;
  const Eigen::VectorXd y = signal(file, "bodies/valve/position", 1), a = signal(file, "crank_angle_deg");
  const Eigen::VectorXd fc = signal(file, "forces/cam/normal_force"),
                        fl = signal(file, "forces/lash/normal_force");
  Eigen::Index top = 0;
  for (Eigen::Index k = 0; k < y.size(); ++k)
    if (a[k] >= 360 && a[k] < 720 && y[k] < y[top]) top = k;
  const TopOfLift t = top_of_lift(pushrod_force[top], fc[top], fl[top], pushrod_rate);
  const double lift = y[0] - y[top];
  std::printf(
      "measured: valve lift at the top %.4f mm, kinematic %.4f mm less deflections %.4f mm and tilt %.4f mm "
      "= %.4f mm (error %.2g um)\n",
      lift * 1e3, t.kinematic * 1e3, t.deflection * 1e3, t.tilt * 1e3, t.expected * 1e3,
      (lift - t.expected) * 1e6);
  return lift - t.expected;
}

}  // namespace nvh::solve::valvetrain_statics
