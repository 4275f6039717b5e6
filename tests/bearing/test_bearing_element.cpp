// The journal-bearing force element in solve: the frame mapping, and journals run through solve's library
// (parse_scene + run_scene) against the Ocvirk short-bearing closed form.
//
// Reference (not computed with this code): Ocvirk's steady short bearing (Dubois and Ocvirk, NACA Report
// 1157, 1953; Hamrock, Schmid and Jacobson, Fundamentals of Fluid Film Lubrication, 2nd ed. 2004,
// eqs. 12.62-12.66), with u = R (omega_journal + omega_shell):
//   W_r = mu u L^3 eps^2 / (c^2 (1 - eps^2)^2),   W_t = pi mu u L^3 eps / (4 c^2 (1 - eps^2)^(3/2)),
//   W = sqrt(W_r^2 + W_t^2),   tan(attitude) = pi sqrt(1 - eps^2) / (4 eps).
// The film force on the journal is -W_r e/|e| + W_t z x e/|e| (rotation positive about z).
// For a load that rotates with the journal (omega_load = omega_journal, shell at rest) the film sees the
// effective speed omega_j + omega_s - 2 omega_load = -omega_j (Booker's mobility method, J. Lubr. Technol.
// 87, 1965): the journal runs on a circle of the static eccentricity for the same load.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <sstream>

#include "../solve/solve_fixture.hpp"
#include "solve/bearing/bearing_reader.hpp"
#include "common/error.hpp"
#include "solve/element_registry.hpp"
#include "solve/journal_bearing_element.hpp"

namespace nvh::solve {
namespace {

// The element through its interface (force_element.hpp): the wrench on the journal (marker i) at its centre.
struct Result {
  Vec3 force, torque, point;
};
Result evaluate(const JournalBearingElement& e, const MarkerMotion& journal, const MarkerMotion& shell) {
  std::array<MarkerMotion, 2> markers{journal, shell};
  std::array<Wrench, 2> wrenches{};
  ElementInput in;
  in.markers = markers;
  ElementOutput out{wrenches, {}};
  e.evaluate(in, out);
  return {wrenches[0].force, wrenches[0].torque, journal.position};
}
void channel_values(const JournalBearingElement& e, const MarkerMotion& journal, const MarkerMotion& shell,
                    std::vector<double>& out) {
  std::array<MarkerMotion, 2> markers{journal, shell};
  ElementInput in;
  in.markers = markers;
  e.channel_values(in, out);
}

using testing::run_text;
using testing::signal;
constexpr double kPi = std::numbers::pi;

// The test bearing: D = 50 mm, L = 20 mm, c = 50 um, mu = 0.01 Pa s, 3000 rpm.
constexpr double kD = 0.05, kL = 0.02, kC = 50e-6, kMu = 0.01, kOmega = 3000 * 2 * kPi / 60;

double ocvirk_load(double eps, double omega_sum) {
  const double u = 0.5 * kD * omega_sum;
  return kMu * u * kL * kL * kL / (4 * kC * kC) * eps / std::pow(1 - eps * eps, 2) *
         std::sqrt(kPi * kPi * (1 - eps * eps) + 16 * eps * eps);
}
double ocvirk_attitude(double eps) {
  return std::atan(kPi * std::sqrt(1 - eps * eps) / (4 * eps));
}
/// The eccentricity ratio that carries W (bisection; W grows monotonically with eps).
double ocvirk_eccentricity(double w, double omega_sum) {
  double lo = 1e-9, hi = 1 - 1e-9;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (ocvirk_load(mid, omega_sum) < w ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

std::string bearing_keys(const std::string& model, const std::string& extra = "") {
  std::ostringstream s;
  s << "model = \"" << model << "\"\ndiameter = " << kD << "\nwidth = " << kL << "\nradial_clearance = " << kC
    << "\nviscosity = " << kMu << "\n"
    << extra;
  return s.str();
}

// ------------------------------------------------------------------ the frame mapping
// A shell marker turned and tilted arbitrarily, both markers translating together (no squeeze): the global
// force must be Ocvirk's, in the shell's plane, and the friction torque about the shell's axis.
TEST(bearing_element, ForceInGlobalAxesMatchesOcvirkForATurnedShell) {
  const auto doc = input::Document::parse(bearing_keys("short"), "element.toml");
  const JournalBearingElement element(bearing::read_bearing(doc.root()));
  const Mat3 axes = (Eigen::AngleAxisd(0.7, Vec3(0.3, -0.5, 0.8).normalized())).toRotationMatrix();
  const Vec3 x = axes.col(0), y = axes.col(1), z = axes.col(2);
  const double eps = 0.55, alpha = 2.1;  // eccentricity ratio and direction in the shell plane
  for (double omega_shell : {0.0, 0.4 * kOmega}) {
    MarkerMotion shell, journal;
    shell.position = Vec3(0.1, 0.2, -0.3);
    shell.axes = axes;
    shell.velocity = Vec3(1.0, -2.0, 0.5);
    shell.angular_velocity = omega_shell * z;
    const Vec3 e_dir = std::cos(alpha) * x + std::sin(alpha) * y;
    journal.position = shell.position + eps * kC * e_dir + 0.002 * z;  // an axial offset does not count
    journal.axes = axes;
    journal.velocity = shell.velocity;
    journal.angular_velocity = kOmega * z;
    const Result f = evaluate(element, journal, shell);
    const double wr = kMu * 0.5 * kD * (kOmega + omega_shell) * std::pow(kL, 3) * eps * eps /
                      (kC * kC * std::pow(1 - eps * eps, 2));
    const double wt = kPi * kMu * 0.5 * kD * (kOmega + omega_shell) * std::pow(kL, 3) * eps /
                      (4 * kC * kC * std::pow(1 - eps * eps, 1.5));
    const Vec3 expected = -wr * e_dir + wt * z.cross(e_dir);
    EXPECT_LT((f.force - expected).norm() / expected.norm(), 1e-10) << "omega_shell " << omega_shell;
    EXPECT_NEAR(std::abs(ocvirk_load(eps, kOmega + omega_shell) / f.force.norm() - 1), 0, 1e-10);
    EXPECT_LT(f.torque.cross(z).norm(), 1e-12 * f.torque.norm());  // about the shell's axis
    EXPECT_LT((f.point - journal.position).norm(), 1e-15);
    std::vector<double> ch(element.channels().size());
    channel_values(element, journal, shell, ch);
    EXPECT_NEAR(ch[0], eps, 1e-12);
    EXPECT_NEAR(ch[1], ocvirk_attitude(eps), 1e-10);
    EXPECT_NEAR(ch[2], (1 - eps) * kC, 1e-12 * kC);
  }
}

// Squeeze: a journal approaching the centred shell radially feels the short-bearing squeeze force of
// Hamrock et al. (2004) eq. 12.80 for eps = 0: F = -mu L^3 v pi / (2 c^3) * R (pure squeeze, no rotation)...
// only its direction and its proportionality to the approach speed are asserted here, in global axes.
TEST(bearing_element, SqueezeOpposesTheApproachInGlobalAxes) {
  const auto doc = input::Document::parse(bearing_keys("short"), "element.toml");
  const JournalBearingElement element(bearing::read_bearing(doc.root()));
  MarkerMotion shell, journal;
  shell.axes = Eigen::AngleAxisd(1.0, Vec3::UnitZ()).toRotationMatrix();
  journal.velocity = Vec3(0.0, 1e-3, 0.0);  // towards +y, both at rest in rotation
  const Vec3 f1 = evaluate(element, journal, shell).force;
  journal.velocity *= 2;
  const Vec3 f2 = evaluate(element, journal, shell).force;
  // Short bearing, eps = 0, pure squeeze over the half circle where h shrinks:
  // F = mu R L^3 v / c^3 int_{-pi/2}^{pi/2} cos^2 = pi mu R L^3 v / (2 c^3), against the motion.
  const double expected = kPi * kMu * 0.5 * kD * std::pow(kL, 3) * 1e-3 / (2 * std::pow(kC, 3));
  EXPECT_NEAR(f1.y() / -expected, 1.0, 1e-10);
  EXPECT_NEAR(f1.x() / expected, 0.0, 1e-10);
  EXPECT_NEAR(f2.y() / f1.y(), 2.0, 1e-10);
}

// ------------------------------------------------------------------ through solve
std::string journal_scene(const std::string& bearing, double mass, const std::string& load, double end_time,
                          double y0) {
  std::ostringstream s;
  s << R"(
[scene]
name = "journal"
[[body]]
name = "ground"
type = "ground"
  [[body.marker]]
  name = "shell"
[[body]]
name = "journal"
type = "rigid"
mass = )"
    << mass << R"(
inertia = [1e-5, 1e-5, 2e-5]
position = [0, )"
    << y0 << R"(, 0]
  [[body.marker]]
  name = "centre"
[[driver]]
name = "speed"
type = "speed"
i = "journal.centre"
j = "ground.shell"
rpm = 3000
[[force]]
name = "bearing"
type = "journal-bearing"
i = "journal.centre"
j = "ground.shell"
)" << bearing
    << load << R"(
[clock]
end_time = )"
    << end_time << R"(
[integrator]
rtol = 1e-7
atol = 1e-12
[output]
sample_rate_hz = 5000
markers = ["journal.centre"]
)";
  return s.str();
}

// A constant load W = 200 N along -y: the journal settles where the film carries it, at Ocvirk's
// eccentricity and attitude angle.
TEST(bearing_element, JournalSettlesAtTheOcvirkStaticSolution) {
  const double w = 200;
  const std::string load =
      "[[load]]\nname = \"w\"\ntype = \"force\"\nat = \"journal.centre\"\n"
      "direction = [0, -1, 0]\ntable = [[0, 200], [1, 200]]\n";
  const auto file =
      run_text(journal_scene(bearing_keys("short"), 1.0, load, 0.1, -0.3 * kC), "bearing_static");
  const Eigen::VectorXd ex = signal(file, "markers/journal.centre/position", 0);
  const Eigen::VectorXd ey = signal(file, "markers/journal.centre/position", 1);
  const Eigen::VectorXd eps = signal(file, "forces/bearing/eccentricity_ratio");
  const Eigen::VectorXd att = signal(file, "forces/bearing/attitude_angle");
  const Eigen::VectorXd fy = signal(file, "forces/bearing/force", 1);
  const double eps0 = ocvirk_eccentricity(w, kOmega), phi0 = ocvirk_attitude(eps0);
  const Eigen::Index n = ex.size() - 1;
  // The journal sits at eps0 c, turned by the attitude angle from the load line (-y) in the rotation sense.
  EXPECT_NEAR(std::hypot(ex[n], ey[n]) / kC, eps0, 1e-5);
  EXPECT_NEAR(std::atan2(ex[n], -ey[n]), phi0, 1e-5);
  EXPECT_NEAR(eps[n], eps0, 1e-5);
  EXPECT_NEAR(att[n], phi0, 1e-5);
  EXPECT_NEAR(fy[n] / w, 1.0, 1e-5);
}

// A load of 200 N turning with the journal: after the start transient the journal runs on a circle of
// Ocvirk's static eccentricity for 200 N (mass 10 g: centrifugal force m omega^2 e = 0.02 N, 1e-4 of the
// load), and the orbit closes from one revolution to the next.
TEST(bearing_element, RotatingLoadOrbitClosesAtTheOcvirkRadius) {
  const std::string load =
      "[[load]]\nname = \"w\"\ntype = \"force\"\nat = \"journal.centre\"\naxes = \"marker\"\n"
      "direction = [0, -1, 0]\ntable = [[0, 200], [1, 200]]\n";
  const auto file =
      run_text(journal_scene(bearing_keys("short"), 0.01, load, 0.12, -0.3 * kC), "bearing_rotating");
  const Eigen::VectorXd t = signal(file, "time");
  const Eigen::VectorXd ex = signal(file, "markers/journal.centre/position", 0);
  const Eigen::VectorXd ey = signal(file, "markers/journal.centre/position", 1);
  const double eps0 = ocvirk_eccentricity(200, kOmega);
  const int per_rev = 100;  // 5000 samples/s at 50 rev/s
  double radius_error = 0, gap = 0;
  for (Eigen::Index k = t.size() - per_rev; k < t.size(); ++k) {
    radius_error = std::max(radius_error, std::abs(std::hypot(ex[k], ey[k]) / kC - eps0));
    gap = std::max(gap, std::hypot(ex[k] - ex[k - per_rev], ey[k] - ey[k - per_rev]) / kC);
  }
  EXPECT_LT(radius_error, 1e-3) << "eps0 " << eps0;
  EXPECT_LT(gap, 1e-4);
  // It is an orbit, not a standstill: the journal goes round once per revolution.
  EXPECT_GT(ex.tail(per_rev).maxCoeff() - ex.tail(per_rev).minCoeff(), 1.8 * eps0 * kC * 0.99);
}

// The finite bearing in a scene: at L/D = 0.1 it approaches the short bearing (Ocvirk) within the 3 % the
// finite model shows alone (tests/bearing/test_finite.cpp); the warm start runs through the integrator's
// perturbed calls.
TEST(bearing_element, FiniteBearingSettlesNearOcvirkAtSmallWidth) {
  const double w = 20;
  std::string keys = bearing_keys("finite", "cavitation = \"swift-stieber\"\ngrid = [48, 6]\n");
  keys.replace(keys.find("width = 0.02"), 12, "width = 0.005");
  const std::string load =
      "[[load]]\nname = \"w\"\ntype = \"force\"\nat = \"journal.centre\"\n"
      "direction = [0, -1, 0]\ntable = [[0, 20], [1, 20]]\n";
  const auto file = run_text(journal_scene(keys, 1.0, load, 0.05, -0.3 * kC), "bearing_finite");
  const Eigen::VectorXd eps = signal(file, "forces/bearing/eccentricity_ratio");
  const Eigen::VectorXd att = signal(file, "forces/bearing/attitude_angle");
  // Ocvirk with L = 5 mm
  const double scale = std::pow(0.005 / kL, 3);
  const double eps0 = ocvirk_eccentricity(w / scale, kOmega), phi0 = ocvirk_attitude(eps0);
  const Eigen::Index n = eps.size() - 1;
  EXPECT_NEAR(eps[n] / eps0, 1.0, 0.03) << eps[n] << " vs " << eps0;
  EXPECT_NEAR(att[n], phi0, 1.5 * kPi / 180) << att[n] << " vs " << phi0;
}

// The warm start is a starting guess only: the film at a state does not depend on the states visited before
// (reference: a cold solve of the same state), to well within what the integrator resolves. JFO with a feed
// hole (without a feed, the mass-conserving film has no source and drains).
TEST(bearing_element, WarmStartDoesNotDependOnHistory) {
  const auto doc = input::Document::parse(bearing_keys("finite",
                                                       "grid = [48, 8]\nsupply_pressure = 2e5\n"
                                                       "[[hole]]\nangle_deg = 90\ndiameter = 0.004\n"),
                                          "element.toml");
  const bearing::BearingSpec spec = bearing::read_bearing(doc.root());
  const JournalBearingElement warm(spec);
  MarkerMotion shell, journal;
  journal.angular_velocity = kOmega * Vec3::UnitZ();
  for (double eps : {0.2, 0.9, 0.4, 0.7}) {  // a history far from the state asked last
    journal.position = Vec3(0, -eps * kC, 0);
    journal.velocity = Vec3(0.3 * eps * kC * kOmega, 0, 0);
    evaluate(warm, journal, shell);
  }
  journal.position = Vec3(0.1 * kC, -0.6 * kC, 0);
  journal.velocity = Vec3(0.01, 0.02, 0) * kC * kOmega;
  const Vec3 f_warm = evaluate(warm, journal, shell).force;
  const JournalBearingElement cold(spec);
  const Vec3 f_cold = evaluate(cold, journal, shell).force;
  EXPECT_LT((f_warm - f_cold).norm() / f_cold.norm(), 1e-9);
}

// `film_tolerance`: the finite film's Newton tolerance in a run (default 1e-8, a hundredth of the default rtol),
// read by the element's factory and handed to the film solver; out of range, an error naming the key.
TEST(bearing_element, FilmToleranceReachesTheFilmSolverAndIsChecked) {
  const ElementType& type = *builtin_elements().find("force", "journal-bearing");
  std::vector<std::filesystem::path> files;
  const auto build = [&](const std::string& extra) {
    const auto doc = input::Document::parse(bearing_keys("finite", "grid = [24, 4]\n" + extra), "element.toml");
    ElementContext context{doc.root(), ".", files, {}, {}};
    return type.make(context);
  };
  const auto tolerance_of = [](const std::unique_ptr<ForceElement>& e) {
    return dynamic_cast<const JournalBearingElement&>(*e).bearing().finite()->options().tolerance;
  };
  EXPECT_EQ(tolerance_of(build("")), JournalBearingElement::kFilmTolerance);
  EXPECT_EQ(tolerance_of(build("film_tolerance = 1e-11\n")), 1e-11);
  try {
    build("film_tolerance = 0.1\n");
    FAIL() << "no error for film_tolerance = 0.1";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("film_tolerance"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nvh::solve
