// Published mechanical DAE references as scenes (issue 16 item 4): Simeon's flexible slider crank, the
// problem "Slider crank" of the Test Set for IVP Solvers (F. Mazzia, C. Magherini, University of Bari; B.
// Simeon, Math. Modelling of Systems 2, 1-18, 1996), an index-2 DAE of dimension 24, as
// testdata/scenes/slider_crank_simeon.toml with the rod written by testdata/scenes/make_simeon_rod.py (their
// headers give the equations). The reference solution at t = 0.1 s is the test set's subroutine cranksoln
// (MEBDFI, rtol = atol = 1e-14) as shipped in the R package deTestSet: repository rforge/bvpsolve, file
// pkg/deTestSet/src/Ex_crank.f, for the package's default variant (ini = 1, linear stiffness, no damping).
// An independent SciPy integration of the same published equations (testdata/scenes/simeon_crank_scipy.py,
// Radau, rtol 1e-10) agrees with it to 4.2e-9 in phi2 and 4.1e-10 m in x3. The rod's constants use the test
// set's pi = 3.1415927 (with the exact pi the elastic coordinates differ by 5e-11 m). Tolerances and measured
// errors: docs/verification.md, "Simeon's flexible slider crank".
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "solve_fixture.hpp"

namespace nvh::solve {
namespace {

using testing::run_text;
using testing::shipped_scene;
using testing::temp_path;

// y(t = 0.1): phi1, phi2, x3, q1..q4, their rates, accelerations, lambda1..3 (Ex_crank.f, cranksoln).
constexpr std::array<double, 24> kReference = {
    0.1500000000000104e+002,  -0.3311734988256260e+000, 0.1697373328427860e+000,
    0.1893192899613509e-003,  0.2375751249879174e-004,  -0.5323896770569702e-005,
    -0.8363313279112129e-005, 0.1500000000000000e+003,  0.6025346755138369e+002,
    -0.8753116326670527e+001, -0.3005541400289738e-001, -0.5500431812571696e-002,
    0.4974111734266989e-003,  0.1105560003626645e-002,  0.0,
    0.6488737541276957e+004,  0.2167938629509884e+004,  0.3391137060286523e+002,
    0.1715134772216488e+000,  -0.1422449408912512e+001, 0.1003946428124810e+001,
    -0.6232935833287916e+002, -0.1637920993367306e+003, 0.2529857947066878e+002};
// The test set's initial elastic state (deTestSet ini = 1): q(0), q'(0).
constexpr std::array<double, 4> kQ0 = {0, 0, 0.103339863e-4, 0.169327969e-4};
constexpr std::array<double, 4> kQd0 = {0.444896105, 0.463434311e-2, -0.178591076e-5, -0.268938672e-5};
constexpr double kPi = 3.14159265358979323846;

/// The rod's superelement, written once per test process by the generator (Debian's /usr/bin/python3).
std::string rod_file() {
  static const std::string path = [] {
    const std::string out = temp_path("simeon_rod.h5").string();
    const std::string cmd =
        "/usr/bin/python3 " + std::string(NVH_SOURCE_DIR) + "/testdata/scenes/make_simeon_rod.py -o " + out;
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    return out;
  }();
  return path;
}

struct CrankState {
  std::array<double, 14> y{};  // phi1, phi2, x3, q1..q4 and their rates, as the test set's y(1..14)
  std::array<double, 14> y0{};
  std::array<double, 3> lambda{};  // the test set's multipliers from the reactions
  double time = 0, max_z = 0;
  long steps = 0;
};

CrankState run_crank(const std::string& integrator, const std::string& tag,
                     std::initializer_list<std::pair<std::string, std::string>> edits = {}) {
  std::string text = shipped_scene("scenes/slider_crank_simeon.toml", edits);
  const std::string key = "superelement = \"simeon_rod.h5\"";
  const auto at = text.find(key);
  EXPECT_NE(at, std::string::npos);
  text.replace(at, key.size(), "superelement = \"" + rod_file() + "\"");
  const auto a = text.find("[integrator]"), b = text.find("[output]");
  text = text.substr(0, a) + integrator + "\n" + text.substr(b);
  RunSummary summary;
  const auto out = run_text(text, "simeon_" + tag, &summary);
  const Eigen::MatrixXd basis = h5::File::open_read(rod_file()).root().read_matrix("assumed_modes/basis");
  const Eigen::MatrixXd ec = testing::matrix(out, "bodies/crank/euler_parameters"),
                        er = testing::matrix(out, "bodies/rod/euler_parameters"),
                        wc = testing::matrix(out, "bodies/crank/angular_velocity"),
                        wr = testing::matrix(out, "bodies/rod/angular_velocity"),
                        xs = testing::matrix(out, "bodies/slider/position"),
                        vs = testing::matrix(out, "bodies/slider/velocity"),
                        eta = testing::matrix(out, "bodies/rod/modal_coordinates"),
                        etad = testing::matrix(out, "bodies/rod/modal_velocities"),
                        f_pin = testing::matrix(out, "joints/slider_pin/reaction_force"),
                        t_drive = testing::matrix(out, "joints/speed/reaction_torque"),
                        rod_pos = testing::matrix(out, "bodies/rod/position");
  const Eigen::VectorXd t = testing::signal(out, "time");
  CrankState s;
  s.time = t[t.size() - 1];
  s.steps = static_cast<long>(summary.statistics.steps);
  auto state = [&](Eigen::Index n) {
    std::array<double, 14> y{};
    // The crank's angle unwrapped by the prescribed omega t (its Euler parameters give it modulo 2 pi).
    const double phi1 = 2 * std::atan2(ec(n, 3), ec(n, 0));
    y[0] = phi1 + 2 * kPi * std::round((150.0 * t[n] - phi1) / (2 * kPi));
    y[1] = 2 * std::atan2(er(n, 3), er(n, 0));
    y[2] = xs(n, 0);
    const Eigen::VectorXd q = basis * eta.row(n).transpose(), qd = basis * etad.row(n).transpose();
    for (int k = 0; k < 4; ++k) {
      y[3 + k] = q[k];
      y[10 + k] = qd[k];
    }
    y[7] = wc(n, 2);
    y[8] = wr(n, 2);
    y[9] = vs(n, 0);
    return y;
  };
  s.y = state(t.size() - 1);
  s.y0 = state(0);
  // The test set's M w - f + G^T lambda = 0: the rail and the pin act on the slider with -lambda2 along x
  // (its g2 = x3 - ...) and on the rod's tip with -lambda1 along y (g1); the drive torque on the crank is
  // -lambda3 (g3 = phi1 - omega t).
  const Eigen::Index n = t.size() - 1;
  s.lambda = {f_pin(n, 1), -f_pin(n, 0), -t_drive(n, 2)};
  s.max_z = std::max(rod_pos.col(2).cwiseAbs().maxCoeff(), xs.col(2).cwiseAbs().maxCoeff());
  return s;
}

struct Errors {
  double position = 0, elastic = 0, velocity = 0, elastic_rate = 0;
};
// Absolute errors: phi2 (rad) and x3 (m); q1..q4 (m); phi2' (rad/s) and x3' (m/s); q1'..q4' (m/s).
Errors errors(const CrankState& s) {
  Errors e;
  for (int k : {1, 2}) e.position = std::max(e.position, std::abs(s.y[k] - kReference[k]));
  for (int k = 3; k < 7; ++k) e.elastic = std::max(e.elastic, std::abs(s.y[k] - kReference[k]));
  for (int k : {8, 9}) e.velocity = std::max(e.velocity, std::abs(s.y[k] - kReference[k]));
  for (int k = 10; k < 14; ++k) e.elastic_rate = std::max(e.elastic_rate, std::abs(s.y[k] - kReference[k]));
  return e;
}

// The superelement holds the test set's matrices: transformed back to the test set's coordinates q
// (q = B eta), /reduced/mass and /reduced/stiffness are RESMBS's MQ and KQ, written here from the published
// formulas (Ex_crank.f: FACM = rho b h L, FACK = E b h / L), and the quadratic invariants sum to the mass.
TEST(SimeonSliderCrank, RodFileHoldsTheTestSetsMatrices) {
  const h5::File f = h5::File::open_read(rod_file());
  const Eigen::MatrixXd b = f.root().read_matrix("assumed_modes/basis");
  const Eigen::MatrixXd binv = b.inverse();
  const Eigen::MatrixXd mq = binv.transpose() * f.root().read_matrix("reduced/mass") * binv;
  const Eigen::MatrixXd kq = binv.transpose() * f.root().read_matrix("reduced/stiffness") * binv;
  const double rho = 7870, bb = 0.008, hh = 0.008, l2 = 0.3, e = 0.2e12;
  const double facm = rho * bb * hh * l2, fack = e * bb * hh / l2;
  Eigen::Matrix4d mq_ref, kq_ref;
  mq_ref << 0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 8, 1, 0, 0, 1, 2;
  mq_ref *= facm;
  const double pi4 = std::pow(3.1415927, 4),  // RESMBS's PARAMETER PI = 3.1415927D0
      r2 = (hh / l2) * (hh / l2);
  kq_ref << pi4 / 24 * r2, 0, 0, 0, 0, pi4 * 2 / 3 * r2, 0, 0, 0, 0, 16.0 / 3, -8.0 / 3, 0, 0, -8.0 / 3,
      7.0 / 3;
  kq_ref *= fack;
  EXPECT_LT((mq - mq_ref).norm(), 1e-12 * mq_ref.norm());
  EXPECT_LT((kq - kq_ref).norm(), 1e-12 * kq_ref.norm());
  EXPECT_NEAR(f.root().read_double("invariants/mass"), 0.151104, 1e-15);  // the test set's M2
  // J2 = m (L^2/3 + h^2/12) about the pin: the test set's 0.0045339259 kg m^2 (given to 8 digits).
  EXPECT_NEAR(f.root().read_matrix("invariants/inertia_origin")(2, 2), 0.0045339259, 1e-10);
}

// IDA (rtol 1e-10) against the reference at t = 0.1 s. Tolerances (docs/verification.md): the published
// initial values have 9 digits and leave g2 = x3 - L1 cos phi1 - (L2 + q4) cos phi2 at 2.03e-10 m, which the
// reference's index-2 integration keeps to the end; the scene starts consistent (x3 = L1 + L2 + q4), so x3
// differs by that offset: positions 1e-9 (measured 1.8e-10 m in x3, 2.6e-11 rad in phi2). The rest is IDA's
// global error, measured as the largest over rtol 1e-9, 1e-10, 1e-11 (it is not monotone in rtol; 1e-11 meets
// SciPy's 3e-9): q within 5e-11 m (1.8e-11), phi2', x3' and q' within 3e-6, the multipliers within 1e-5 of
// their size (3.2e-6). The velocities' error moves with round-off: 6.3e-7 and 5.5e-7 m/s in 58,530 steps in
// the sweep (2026-11-25), 1.56e-6 and 1.36e-6 in 62,582 steps on a SkylakeX VM (2026-12-02, later code), so
// their bound is 1.9 x the largest seen (docs/verification.md).
TEST(SimeonSliderCrank, IdaMatchesTheTestSetReferenceAtT01) {
  const CrankState s = run_crank("[integrator]\nrtol = 1e-10\natol = 1e-13\n", "ida");
  ASSERT_EQ(s.time, 0.1);
  EXPECT_LT(s.max_z, 1e-12);  // planar
  // The initial state is the test set's (the elastic one through q = B eta).
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(s.y0[3 + k], kQ0[k], 1e-15) << "q" << k + 1 << "(0)";
    EXPECT_NEAR(s.y0[10 + k], kQd0[k], 1e-12) << "q" << k + 1 << "'(0)";
  }
  const Errors e = errors(s);
  std::printf(
      "[ simeon ] IDA rtol 1e-10: phi2 %.2e rad, x3 %.2e m, q %.2e m, phi2' %.2e, x3' %.2e, q' %.2e; "
      "lambda %.2e %.2e %.2e (relative); %ld steps\n",
      std::abs(s.y[1] - kReference[1]), std::abs(s.y[2] - kReference[2]), e.elastic,
      std::abs(s.y[8] - kReference[8]), std::abs(s.y[9] - kReference[9]), e.elastic_rate,
      std::abs(s.lambda[0] / kReference[21] - 1), std::abs(s.lambda[1] / kReference[22] - 1),
      std::abs(s.lambda[2] / kReference[23] - 1), s.steps);
  EXPECT_NEAR(s.y[0], kReference[0], 1e-9);  // phi1 = omega t
  EXPECT_NEAR(s.y[7], kReference[7], 1e-9);
  EXPECT_LT(e.position, 1e-9);
  EXPECT_LT(e.elastic, 5e-11);
  EXPECT_LT(e.velocity, 3e-6);
  EXPECT_LT(e.elastic_rate, 3e-6);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(s.lambda[k], kReference[21 + k], 1e-5 * std::abs(kReference[21 + k])) << "lambda" << k + 1;
}

// Generalized-alpha (fixed step, rho_inf 0.8, Newton to rtol 1e-10, atol 1e-11; atol 1e-13 fails its first
// Newton iteration) is second order in the positions: halving the step from 2e-5 s to 1e-5 s cuts the errors
// of phi2 and x3 by 4.33 and 4.66 (measured: 4.0e-7 -> 9.3e-8 rad, 2.0e-7 -> 4.3e-8 m). Its velocities are
// not (docs/verification.md): it keeps the constraints at position level only.
TEST(SimeonSliderCrank, GeneralizedAlphaPositionsConvergeAtSecondOrder) {
  std::array<double, 2> e_phi2{}, e_x3{};
  const std::array<const char*, 2> steps = {"2e-5", "1e-5"};
  for (int k = 0; k < 2; ++k) {
    const CrankState s = run_crank(std::string("[integrator]\nmethod = \"generalized-alpha\"\nstep = ") +
                                       steps[k] + "\nadaptive = false\nrtol = 1e-10\natol = 1e-11\n",
                                   std::string("alpha") + steps[k]);
    ASSERT_EQ(s.time, 0.1);
    e_phi2[k] = std::abs(s.y[1] - kReference[1]);
    e_x3[k] = std::abs(s.y[2] - kReference[2]);
    std::printf("[ simeon ] generalized-alpha step %s: phi2 %.2e rad, x3 %.2e m\n", steps[k], e_phi2[k],
                e_x3[k]);
  }
  EXPECT_LT(e_phi2[1], 2e-7);
  EXPECT_LT(e_x3[1], 1e-7);
  EXPECT_GT(e_phi2[0] / e_phi2[1], 3.5);  // 2^2 = 4
  EXPECT_LT(e_phi2[0] / e_phi2[1], 5.0);
  EXPECT_GT(e_x3[0] / e_x3[1], 3.5);
  EXPECT_LT(e_x3[0] / e_x3[1], 5.0);
}

// The test discriminates the rod's model: the same rod with the consistent longitudinal mass
// int rho N_u N_u^T dx (1/15 of the test set's block; make_simeon_rod.py --consistent-mass), started from the
// same q(0), q'(0), misses the reference by far more than the tolerances above (measured: x3 6.3e-8 m,
// q 6.0e-8 m, x3' 3.1e-4 m/s; docs/verification.md).
TEST(SimeonSliderCrank, ConsistentLongitudinalMassMissesTheReference) {
  const std::string rod = temp_path("simeon_rod_consistent.h5").string();
  const std::string cmd = "/usr/bin/python3 " + std::string(NVH_SOURCE_DIR) +
                          "/testdata/scenes/make_simeon_rod.py --consistent-mass -o " + rod;
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const Eigen::MatrixXd b = h5::File::open_read(rod).root().read_matrix("assumed_modes/basis");
  const Eigen::Vector4d eta0 = b.lu().solve(Eigen::Vector4d(kQ0.data())),
                        etad0 = b.lu().solve(Eigen::Vector4d(kQd0.data()));
  auto list = [](const Eigen::Vector4d& v) {
    std::ostringstream s;
    s.precision(17);
    s << '[' << v[0] << ", " << v[1] << ", " << v[2] << ", " << v[3] << ']';
    return s.str();
  };
  std::string text = shipped_scene("scenes/slider_crank_simeon.toml");
  std::string quoted(1, '"');
  quoted.append(rod).push_back('"');
  for (const auto& [key, value] : {std::pair{std::string("modal_coordinates = "), list(eta0)},
                                   std::pair{std::string("modal_velocities = "), list(etad0)},
                                   std::pair{std::string("superelement = "), quoted}}) {
    const auto at = text.find(key);
    ASSERT_NE(at, std::string::npos) << key;
    text.replace(at + key.size(), text.find('\n', at) - at - key.size(), value);
  }
  const auto out = run_text(text, "simeon_consistent_mass");
  const Eigen::MatrixXd xs = testing::matrix(out, "bodies/slider/position"),
                        eta = testing::matrix(out, "bodies/rod/modal_coordinates");
  const Eigen::Index n = xs.rows() - 1;
  const Eigen::VectorXd q = b * eta.row(n).transpose(), q0 = b * eta.row(0).transpose();
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(q0[k], kQ0[k], 1e-15);
  double eq = 0;
  for (int k = 0; k < 4; ++k) eq = std::max(eq, std::abs(q[k] - kReference[3 + k]));
  const double ex = std::abs(xs(n, 0) - kReference[2]);
  std::printf("[ simeon ] consistent longitudinal mass: x3 %.2e m, q %.2e m off the reference\n", ex, eq);
  EXPECT_GT(ex, 1e-8);  // 10 x the tolerance of the test set's model
  EXPECT_GT(eq, 1e-8);  // 100 x
}

}  // namespace
}  // namespace nvh::solve
