// The point-set contact (solve/elements/point_set_contact.cpp): N points on one body against the plane of one
// marker, each with the law of `contact`. The scenes are TOML text run through solve's library; the results are
// read back from the results file (docs/results-format.md).
//
// References: four `contact` elements (the same law, one point each: the shipped element, itself verified
// against closed forms in test_elements_verification.cpp and test_contact_events.cpp); the statics of a rigid
// plate on four equal linear springs; the scene reader's errors. The Jacobian is checked in
// test_element_jacobians.cpp (per element) and test_jacobian.cpp (the model).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::run_text;
using testing::matrix;
using testing::num;
using testing::signal;
constexpr double kG = 9.81;

/// max |a - b| / max |b|
double relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

const char* kCorners[] = {"c1", "c2", "c3", "c4"};
const std::string kGround = R"(
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "o"
)";

// ==================================================================== equivalence with four `contact` elements
// A plate (four corner markers, 5 mm below its centre of mass) thrown, tilted and spinning, onto a table that
// sits on a soft bushing (it moves 10 mm): the plate lands on one edge, bounces, slides with Stribeck friction.
// The same scene once with one point-set contact and once with four contacts (plate.c_k against table.top) must
// give the same motion: the residuals are the same sums of the same laws (summed in another order on the
// table), so the difference is round-off carried through Newton's iterations and the integration.
// Positions are compared per body relative to the largest coordinate of that body.
std::string plate_on_table(const std::string& elements) {
  return "[scene]\ngravity = [0, 0, -9.81]\n" + kGround + R"([[body]]
name = "table"
type = "rigid"
mass = 5.0
inertia = [0.2, 0.3, 0.4]
  [[body.marker]]
  name = "base"
  [[body.marker]]
  name = "top"
  at = [0, 0, 0.02]
[[body]]
name = "plate"
type = "rigid"
mass = 1.0
inertia = [0.004, 0.008, 0.011]
position = [0.01, -0.02, 0.026]
orientation = [0.99995, 0.01, 0.0, 0.0]
velocity = [0.3, 0.1, -0.2]
angular_velocity = [1.0, -2.0, 0.5]
  [[body.marker]]
  name = "c1"
  at = [0.1, 0.05, -0.005]
  [[body.marker]]
  name = "c2"
  at = [-0.1, 0.05, -0.005]
  [[body.marker]]
  name = "c3"
  at = [-0.1, -0.05, -0.005]
  [[body.marker]]
  name = "c4"
  at = [0.1, -0.05, -0.005]
[[force]]
name = "mount"
type = "bushing"
i = "table.base"
j = "ground.o"
stiffness = [1e4, 1e4, 1e4, 1e2, 1e2, 1e2]
damping = [20, 20, 20, 0.2, 0.2, 0.2]
)" + elements + R"(
[clock]
end_time = 0.06
[integrator]
rtol = 1e-10
atol = 1e-12
[output]
sample_rate_hz = 10000
)";
}

const char* kLaw = R"(
stiffness = 1e7
exponent = 1.5
restitution = 0.5
reference_speed = 0.2
mu_static = 0.3
mu_dynamic = 0.2
stribeck_speed = 0.05
regularization_speed = 1e-3
)";

TEST(PointSetContact, EqualsFourContactElements) {
  const std::string set = std::string(R"(
[[force]]
name = "skirt"
type = "point-set-contact"
points = ["plate.c1", "plate.c2", "plate.c3", "plate.c4"]
j = "table.top"
)") + kLaw;
  std::string four;
  for (const char* c : kCorners)
    four += std::string("[[force]]\nname = \"") + c + "\"\ntype = \"contact\"\ni = \"plate." + c + "\"\nj = \"table.top\"\n" + kLaw;
  const auto a = run_text(plate_on_table(set), "point_set_equivalence_set");
  const auto b = run_text(plate_on_table(four), "point_set_equivalence_four");

  double position = 0, force = 0, channel = 0, energy = 0;
  for (const std::string body : {"plate", "table"})
    for (const std::string s : {"position", "euler_parameters"}) {
      const std::string path = "bodies/" + body + "/" + s;
      position = std::max(position, relative(matrix(a, path), matrix(b, path)));
    }
  // The results' force and torque of the point set: the resultant on the plate at c1's origin, i.e. the sum of
  // the four contacts' forces (each on its point) and their moments about c1.
  const Eigen::MatrixXd p1 = matrix(b, "markers/plate.c1/position");
  Eigen::MatrixXd sum_f = Eigen::MatrixXd::Zero(p1.rows(), 3), sum_t = sum_f;
  Eigen::VectorXd sum_fn = Eigen::VectorXd::Zero(p1.rows());
  for (int k = 0; k < 4; ++k) {
    const std::string c = kCorners[k], s = std::to_string(k + 1);
    const Eigen::MatrixXd f = matrix(b, "forces/" + c + "/force"), p = matrix(b, "markers/plate." + c + "/position");
    sum_f += f;
    for (Eigen::Index r = 0; r < f.rows(); ++r)
      sum_t.row(r) += Eigen::Vector3d(p.row(r) - p1.row(r)).cross(Eigen::Vector3d(f.row(r))).transpose();
    sum_fn += signal(b, "forces/" + c + "/normal_force");
    for (const std::string ch : {"gap", "normal_force", "slip_speed"})
      channel = std::max(channel, relative(signal(a, "forces/skirt/" + ch + "_" + s), signal(b, "forces/" + c + "/" + ch)));
  }
  force = std::max({relative(matrix(a, "forces/skirt/force"), sum_f), relative(matrix(a, "forces/skirt/torque"), sum_t)});
  channel = std::max(channel, relative(signal(a, "forces/skirt/normal_force"), sum_fn));
  for (const std::string e : {"potential", "dissipated", "balance"})
    energy = std::max(energy, (signal(a, "energy/" + e) - signal(b, "energy/" + e)).cwiseAbs().maxCoeff());
  const double peak = sum_fn.maxCoeff(), dissipated = signal(b, "energy/dissipated").maxCoeff();
  std::printf("measured: point-set vs four contacts: positions and Euler parameters %.2e relative, resultant "
              "force and torque %.2e, channels %.2e (peak total normal force %.4g N), energies %.2e J "
              "(dissipated %.4g J)\n",
              position, force, channel, peak, energy, dissipated);
  EXPECT_GT(peak, 10.0);        // N: the plate did land (weight 9.81 N)
  EXPECT_GT(dissipated, 1e-3);  // J: and slid or bounced
  EXPECT_LT(position, 1e-10);
  // forces: the positions' differences times the contact stiffness (1.5 k delta^0.5 ~ 3e5 N/m at the peak)
  EXPECT_LT(force, 1e-9);
  EXPECT_LT(channel, 1e-9);
  EXPECT_LT(energy, 1e-10 * dissipated);
}

// ==================================================================== statics of a plate on four springs
// A rigid rectangular plate 2A x 2B (mass m, centre of mass offset (ex, ey) from its centre, corners at the
// height of the centre of mass) rests under gravity on its four corners on the ground, linear contact law
// (exponent 1: fn = k delta (1 + alpha delta'), the damping only to settle). Four equal springs under a rigid
// plate: the penetrations lie on a plane w(X, Y) = w0 + a X + b Y (X, Y from the plate's centre), the loads are
// k w. Equilibrium: sum k w = m g; moments about the centre of mass sum k w (X - ex) = 0, sum k w (Y - ey) = 0.
// With sum X = sum Y = sum X Y = 0, sum X^2 = 4 A^2, sum Y^2 = 4 B^2 (corners (+-A, +-B)):
//   w0 = m g / (4 k),  a = m g ex / (4 k A^2),  b = m g ey / (4 k B^2),
//   load_k = (m g / 4) (1 + ex X_k / A^2 + ey Y_k / B^2),   settled gap_k = -load_k / k.
// The tilt does not change this: the corners' horizontal positions are one linear map of (X, Y), so the moment
// equations keep their solution. The resultant on the plate at c1's origin balances gravity: force (0, 0, m g),
// torque (c - p_1) x (0, 0, m g), with the untilted arm c - p_1 (the tilt, 1e-4 rad, changes it by 1e-8).
TEST(PointSetContact, PlateOnFourLinearSpringsStatics) {
  const double m = 2.0, A = 0.15, B = 0.1, ex = 0.03, ey = -0.02, k = 1e5;
  const double X[4] = {A, -A, -A, A}, Y[4] = {B, B, -B, -B};
  std::string markers;
  for (int c = 0; c < 4; ++c)
    markers += std::string("  [[body.marker]]\n  name = \"") + kCorners[c] + "\"\n  at = [" + num(X[c] - ex) + ", " +
               num(Y[c] - ey) + ", 0.0]\n";
  const std::string text = "[scene]\ngravity = [0, 0, -9.81]\n" + kGround + R"([[body]]
name = "plate"
type = "rigid"
mass = )" + num(m) + R"(
inertia = [0.008, 0.016, 0.022]
position = [0.0, 0.0, 1e-5]
)" + markers + R"(
[[force]]
name = "feet"
type = "point-set-contact"
points = ["plate.c1", "plate.c2", "plate.c3", "plate.c4"]
j = "ground.o"
stiffness = )" + num(k) + R"(
exponent = 1.0
restitution = 0.8
reference_speed = 0.003
[clock]
end_time = 0.5
[integrator]
rtol = 1e-10
atol = 1e-13
[output]
sample_rate_hz = 1000
)";
  const auto file = run_text(text, "point_set_plate_statics");
  const Eigen::Index last = signal(file, "time").size() - 1;
  double eload = 0, egap = 0;
  for (int c = 0; c < 4; ++c) {
    const std::string s = std::to_string(c + 1);
    const double load = m * kG / 4 * (1 + ex * X[c] / (A * A) + ey * Y[c] / (B * B));
    const double fn = signal(file, "forces/feet/normal_force_" + s)[last];
    const double gap = signal(file, "forces/feet/gap_" + s)[last];
    std::printf("measured: plate statics, corner %d: load %.10g N (closed form %.10g N), gap %.10g m (-load/k %.10g m)\n",
                c + 1, fn, load, gap, -load / k);
    eload = std::max(eload, std::abs(fn - load) / load);
    egap = std::max(egap, std::abs(gap + load / k) / (load / k));
  }
  const Eigen::Vector3d f = matrix(file, "forces/feet/force").row(last).transpose();
  const Eigen::Vector3d t = matrix(file, "forces/feet/torque").row(last).transpose();
  const Eigen::Vector3d weight(0, 0, m * kG), arm(ex - X[0], ey - Y[0], 0.0);  // c - p_1
  const double eforce = (f - weight).norm() / (m * kG), etorque = (t - arm.cross(weight)).norm() / arm.cross(weight).norm();
  std::printf("measured: plate statics, largest error: loads %.2e, gaps %.2e, resultant force %.2e, torque at c1 "
              "%.2e (relative; tolerance 1e-6)\n", eload, egap, eforce, etorque);
  EXPECT_LT(eload, 1e-6);
  EXPECT_LT(egap, 1e-6);
  EXPECT_LT(eforce, 1e-6);
  EXPECT_LT(etorque, 1e-6);
}

// ==================================================================== bad input
std::string error_of(const std::string& points, const std::string& j) {
  const std::string text = kGround + R"([[body]]
name = "piston"
type = "rigid"
mass = 1.0
inertia = [0.1, 0.1, 0.1]
  [[body.marker]]
  name = "a"
  [[body.marker]]
  name = "b"
[[force]]
name = "skirt"
type = "point-set-contact"
points = )" + points + "\nj = " + j + R"(
stiffness = 1e6
[clock]
end_time = 0.01
)";
  return testing::scene_error(text);
}

TEST(PointSetContact, BadMarkersAreNamedByTheirKey) {
  const std::string two_bodies = error_of(R"(["piston.a", "ground.o"])", R"("piston.b")");
  EXPECT_NE(two_bodies.find("points': all points must be on one body"), std::string::npos) << two_bodies;
  EXPECT_NE(two_bodies.find("bad.toml:19"), std::string::npos) << two_bodies;
  const std::string same = error_of(R"(["piston.a"])", R"("piston.b")");
  EXPECT_NE(same.find("j': marker j is on the points' body 'piston'"), std::string::npos) << same;
  EXPECT_NE(same.find("bad.toml:20"), std::string::npos) << same;
  const std::string none = error_of("[]", R"("ground.o")");
  EXPECT_NE(none.find("points': expected at least one marker"), std::string::npos) << none;
  const std::string missing = error_of(R"(["piston.a", "piston.c"])", R"("ground.o")");
  EXPECT_NE(missing.find("body 'piston' has no marker 'c'"), std::string::npos) << missing;
  EXPECT_EQ(error_of(R"(["piston.a", "piston.b"])", R"("ground.o")"), "no error");
}

}  // namespace
}  // namespace nvh::solve
