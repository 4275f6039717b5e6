// Each element's own analytic Jacobian (ForceElement::jacobian, force_element.hpp) against central
// differences of its own evaluate(), element by element, built through the registry (issue 12, item 3).
//
// Oracle: column c of [wrench rows; state rows] by central differences with the model's perturbations (dp, a
// small global rotation dA = dtheta~ A of the marker axes, dv, domega per marker; z with z' += cj dz; the
// crank angle), step h = 1e-6 (scaled by the magnitude of the perturbed value). Tolerance: for every entry |J
// - J_fd| <= 1e-6 * (largest |J_fd| of that row), at several random marker motions per case; a row that
// vanishes to round-off is measured against 1e-5 of the largest entry of the matrix instead (its differences
// are noise).
// test_jacobian.cpp checks the same elements through the whole model.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <sstream>

#include <Eigen/Geometry>

#include "common/input.hpp"
#include "solve/cam/cam_profile.hpp"
#include "solve/element_registry.hpp"

namespace nvh::solve {
namespace {

constexpr double kTolerance = 1e-6;

/// An element built by the registry from the TOML keys of its table, with its markers' initial motion; the
/// markers are on body "a" but the last, on "b" (one marker: on "a").
struct Built {
  input::Document doc;
  std::unique_ptr<ForceElement> element;
};

Built build(const std::string& section, const std::string& type, const std::string& keys,
            const std::vector<MarkerMotion>& initial) {
  const ElementType* et = builtin_elements().find(section, type);
  EXPECT_NE(et, nullptr) << section << " " << type << " is not registered";
  if (!et) return {input::Document::parse("", "empty.toml"), nullptr};
  Built b{input::Document::parse(keys, type + ".toml"), nullptr};
  const input::Table t = b.doc.root();
  std::vector<std::filesystem::path> files;
  std::vector<std::string> bodies(initial.size(), "a");
  if (bodies.size() > 1) bodies.back() = "b";
  ElementContext c{t, std::filesystem::path(NVH_SOURCE_DIR) / "testdata/scenes", files, initial, bodies};
  b.element = et->make(c);
  return b;
}

MarkerMotion random_motion(std::mt19937& rng, double spread = 0.1) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  MarkerMotion m;
  m.position = spread * Vec3(u(rng), u(rng), u(rng));
  m.axes = Eigen::AngleAxisd(3.0 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
  m.velocity = Vec3(u(rng), u(rng), u(rng));
  m.angular_velocity = 3.0 * Vec3(u(rng), u(rng), u(rng));
  return m;
}

/// The model's perturbation of a marker (model.cpp: perturb): column 0-2 dp, 3-5 dtheta, 6-8 dv, 9-11 domega.
void perturb(MarkerMotion& m, int column, double h) {
  const int axis = column % 3;
  switch (column / 3) {
    case 0:
      m.position[axis] += h;
      break;
    case 1:
      m.axes = Eigen::AngleAxisd(h, Vec3::Unit(axis)).toRotationMatrix() * m.axes;
      break;
    case 2:
      m.velocity[axis] += h;
      break;
    default:
      m.angular_velocity[axis] += h;
      break;
  }
}

struct Point {
  std::vector<MarkerMotion> markers;
  std::vector<double> z, zp;
  double time = 0.37, crank = 0.0;
};

Eigen::VectorXd rows_of(const ForceElement& e, const Point& p) {
  const int nm = static_cast<int>(p.markers.size()), ns = static_cast<int>(p.z.size());
  std::vector<Wrench> w(nm);
  std::vector<double> r(ns);
  const ElementInput in{p.time, p.crank, p.markers, p.z, p.zp};
  ElementOutput out{w, r};
  e.evaluate(in, out);
  Eigen::VectorXd v(6 * nm + ns);
  for (int k = 0; k < nm; ++k) v.segment<3>(6 * k) = w[k].force, v.segment<3>(6 * k + 3) = w[k].torque;
  for (int s = 0; s < ns; ++s) v[6 * nm + s] = r[s];
  return v;
}

struct Result {
  bool analytic = false;
  double worst = 0;  // largest |J - J_fd| / (largest |J_fd| of the row)
  std::string where;
  double largest = 0;  // largest |J| (a case with all zeros says so)
};

Result check(const ForceElement& e, const Point& p, double cj = 321.0) {
  const int nm = static_cast<int>(p.markers.size()), ns = static_cast<int>(p.z.size());
  const int rows = 6 * nm + ns, cols = 12 * nm + ns + 1;
  Eigen::MatrixXd ja = Eigen::MatrixXd::Zero(rows, cols);
  const ElementInput in{p.time, p.crank, p.markers, p.z, p.zp};
  ElementJacobian jac{cj, ja};
  Result res;
  res.analytic = e.jacobian(in, jac);
  res.largest = ja.cwiseAbs().maxCoeff();
  Eigen::MatrixXd jf(rows, cols);
  for (int c = 0; c < cols; ++c) {
    Point plus = p, minus = p;
    double h = 1e-6;
    if (c < 12 * nm) {
      const int k = c / 12, col = c % 12;
      const MarkerMotion& m = p.markers[k];
      const double value = col < 3   ? m.position[col % 3]
                           : col < 6 ? 0.0
                           : col < 9 ? m.velocity[col % 3]
                                     : m.angular_velocity[col % 3];
      h *= std::max(1.0, std::abs(value));
      perturb(plus.markers[k], col, h);
      perturb(minus.markers[k], col, -h);
    } else if (c < 12 * nm + ns) {
      const int s = c - 12 * nm;
      h *= std::max(1.0, std::abs(p.z[s]));
      plus.z[s] += h, plus.zp[s] += cj * h;
      minus.z[s] -= h, minus.zp[s] -= cj * h;
    } else {
      h *= std::max(1.0, std::abs(p.crank));
      plus.crank += h, minus.crank -= h;
    }
    jf.col(c) = (rows_of(e, plus) - rows_of(e, minus)) / (2 * h);
  }
  static const char* kColumn[] = {"dp", "dtheta", "dv", "domega"};
  const double overall = jf.cwiseAbs().maxCoeff();
  for (int r = 0; r < rows; ++r) {
    // a row that vanishes to round-off (the reaction torque of a force along the line of the markers) is
    // measured against 1e-5 of the largest entry of the whole matrix: the differences' own noise is ~1e-12 of
    // it
    const double scale = std::max(jf.row(r).cwiseAbs().maxCoeff(), 1e-5 * overall);
    for (int c = 0; c < cols; ++c) {
      const double diff = std::abs(ja(r, c) - jf(r, c));
      const double err = diff == 0 ? 0.0 : diff / std::max(scale, 1e-300);
      if (err > res.worst) {
        std::ostringstream s;
        s << "row " << r << ", column " << c;
        if (c < 12 * nm)
          s << " (marker " << c / 12 << " " << kColumn[(c % 12) / 3] << "_"
            << "xyz"[c % 3] << ")";
        s << ": analytic " << ja(r, c) << ", differences " << jf(r, c) << ", row scale " << scale;
        res.worst = err;
        res.where = s.str();
      }
    }
  }
  return res;
}

/// Worst relative error per element type over the whole test binary (printed at the end).
std::map<std::string, double>& worst_per_type() {
  static std::map<std::string, double> w;
  return w;
}

void expect_matches(const ForceElement& e, const Point& p, const std::string& what,
                    bool expect_nonzero = true) {
  const Result r = check(e, p);
  EXPECT_TRUE(r.analytic) << what << ": jacobian() returned false";
  EXPECT_LE(r.worst, kTolerance) << what << ": worst at " << r.where;
  if (expect_nonzero) {
    EXPECT_GT(r.largest, 0.0) << what << ": the Jacobian is all zeros";
  } else {
    EXPECT_EQ(r.largest, 0.0) << what << ": expected no force and a zero Jacobian";
  }
  double& w = worst_per_type()[e.type()];
  w = std::max(w, r.worst);
}

Point two_random(std::mt19937& rng, double spread = 0.1) {
  return {{random_motion(rng, spread), random_motion(rng, spread)}, {}, {}};
}

// ---------------------------------------------------------------------------------------------------------------

TEST(ElementJacobians, Bushing) {
  std::mt19937 rng(11);
  std::ostringstream k, d;  // full 6 x 6 matrices: the off-diagonal couplings enter every column
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  k << "stiffness = [";
  d << "damping = [";
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) {
      const double sk = (r < 3 ? 1e5 : 1e3) * (r == c ? 3.0 : 0.3 * u(rng));
      const double sd = (r < 3 ? 30.0 : 0.3) * (r == c ? 3.0 : 0.3 * u(rng));
      k << (r + c ? ", " : "") << sk;
      d << (r + c ? ", " : "") << sd;
    }
  k << "]\n";
  d << "]\n";
  const Built b = build("force", "bushing", k.str() + d.str(), {MarkerMotion{}, MarkerMotion{}});
  for (int n = 0; n < 8; ++n)
    expect_matches(*b.element, two_random(rng), "bushing, random " + std::to_string(n));
  // relative rotations from large (2.5 rad) down to none: the exact rotation-vector derivative and its
  // small-angle series (below 0.01 rad)
  for (double angle : {2.5, 1.0, 0.1, 0.02, 0.009, 1e-3, 1e-6, 0.0}) {
    Point p = two_random(rng);
    p.markers[0].axes =
        p.markers[1].axes * Eigen::AngleAxisd(angle, Vec3(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
    expect_matches(*b.element, p, "bushing, relative rotation " + std::to_string(angle) + " rad");
  }
  // the diagonal form too
  const Built diag = build("force", "bushing",
                           "stiffness = [1e5, 2e5, 3e5, 1e3, 2e3, 3e3]\n"
                           "damping = [10, 20, 30, 0.1, 0.2, 0.3]\n",
                           {MarkerMotion{}, MarkerMotion{}});
  for (int n = 0; n < 4; ++n)
    expect_matches(*diag.element, two_random(rng), "diagonal bushing " + std::to_string(n));
}

// bearing-spring: random motions, and the journal turned about the bore's axis by up to several turns (where
// a bushing's rotation vector jumps) with a small tilt, against central differences of evaluate().
constexpr const char* kBearingSpringKeys =
    "radial_stiffness = 2e5\nradial_damping = 30\naxial_stiffness = 5e4\naxial_damping = 7\n"
    "tilt_stiffness = 3e3\ntilt_damping = 0.4\n";
TEST(ElementJacobians, BearingSpringMatchesDifferences) {
  std::mt19937 rng(11);
  const Built b = build("force", "bearing-spring", kBearingSpringKeys, {MarkerMotion{}, MarkerMotion{}});
  for (int n = 0; n < 8; ++n)
    expect_matches(*b.element, two_random(rng), "bearing-spring, random " + std::to_string(n));
  for (double spin : {0.0, 1.0, 3.1, 3.2, 20.0}) {
    Point p = two_random(rng);
    p.markers[0].axes = p.markers[1].axes * Eigen::AngleAxisd(spin, Vec3::UnitZ()).toRotationMatrix() *
                        Eigen::AngleAxisd(0.01, Vec3(1, 0.3, 0).normalized()).toRotationMatrix();
    expect_matches(*b.element, p, "bearing-spring, spun " + std::to_string(spin) + " rad about z_j");
  }
}

// Contact: a point's origin (marker i = 0) against the plane of j (= 1, normal z_j). Velocities are set so
// that the normal rate is as wanted (the clamp: separating fast enough that 1 + alpha delta' < 0).
void set_normal_rate(Point& p, double vn, int i = 0, int plane = 1) {
  const MarkerMotion& j = p.markers[plane];
  const Vec3 n = j.axes.col(2), d = p.markers[i].position - j.position;
  const Vec3 vr = p.markers[i].velocity - j.velocity - j.angular_velocity.cross(d);
  p.markers[i].velocity += (vn - n.dot(vr)) * n;
}
void set_tangential(Point& p, double speed, std::mt19937& rng, int i = 0, int plane = 1) {
  const MarkerMotion& j = p.markers[plane];
  const Vec3 n = j.axes.col(2), d = p.markers[i].position - j.position;
  const Vec3 vr = p.markers[i].velocity - j.velocity - j.angular_velocity.cross(d);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vec3 t = Vec3(u(rng), u(rng), u(rng));
  t = (t - t.dot(n) * n).normalized();
  p.markers[i].velocity += speed * t - (vr - vr.dot(n) * n);
}

// The contact law's keys (contact, point-set-contact): alpha = 3 (1 - e) / (2 v_ref) = 12 s/m, the clamp (fn
// = 0) for delta' < -1/12 m/s; Stribeck and regularization speeds within the random slip speeds.
const std::string kContactLaw = R"(
stiffness = 1.0e6
exponent = 1.5
restitution = 0.2
reference_speed = 0.1
mu_static = 0.3
mu_dynamic = 0.2
stribeck_speed = 0.2
regularization_speed = 0.05
)";

TEST(ElementJacobians, ContactNormalFrictionOpenAndClamp) {
  const std::string& common = kContactLaw;
  // |d| <= 0.35 along z_j: clearance -0.5 keeps i 0.15 .. 0.85 m deep, +0.5 keeps it open
  const Built in_contact =
      build("force", "contact", common + "clearance = -0.5\n", {MarkerMotion{}, MarkerMotion{}});
  const Built open =
      build("force", "contact", common + "clearance = 0.5\n", {MarkerMotion{}, MarkerMotion{}});
  const Built frictionless =
      build("force", "contact", "stiffness = 1.0e6\nexponent = 1.0\nrestitution = 0.5\nclearance = -0.5\n",
            {MarkerMotion{}, MarkerMotion{}});
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n = 0; n < 6; ++n) {
    const std::string tag =
        std::string(" ").append(std::to_string(n));  // (" " + ... trips GCC 12 -Wrestrict)
    Point p = two_random(rng);
    set_normal_rate(p, 0.05 * u(rng));           // |delta'| < 1/12: pressing or separating slowly, no clamp
    set_tangential(p, 0.5 + u(rng) * 0.4, rng);  // sliding, the Stribeck range
    expect_matches(*in_contact.element, p, "contact sliding" + tag);
    set_tangential(p, 0.02 * (1.0 + u(rng)), rng);  // in the tanh's regularization (near sticking)
    expect_matches(*in_contact.element, p, "contact near sticking" + tag);
    set_tangential(p, 1e-5 * (1.0 + u(rng)), rng);  // tanh(x)/x by its series
    expect_matches(*in_contact.element, p, "contact, slip 1e-5 m/s" + tag);
    set_tangential(p, 0.0, rng);  // no slip (to round-off)
    expect_matches(*in_contact.element, p, "contact, no slip" + tag);
    set_tangential(p, 3.0, rng);
    expect_matches(*frictionless.element, p, "contact without friction" + tag);
    set_normal_rate(p, 0.5 + 0.4 * u(rng));  // separating fast: 1 + alpha delta' < 0, clamped to fn = 0
    expect_matches(*in_contact.element, p, "contact in the clamp" + tag, false);
    expect_matches(*open.element, two_random(rng), "contact open" + tag, false);
  }
}

// Point-set contact: six points (85 columns: more than ElementRows holds) against the plane of j, each at its
// own gap - in contact sliding, near sticking, without slip, in the clamp, open - so every kind of point's
// rows and the sum of the reactions on j are checked at once.
TEST(ElementJacobians, PointSetContactPointsInEveryState) {
  const Built b = build("force", "point-set-contact", kContactLaw, std::vector<MarkerMotion>(7));
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // gap of each point (m; < 0 in contact) and its slip speed (m/s); point 5 separates fast (the clamp)
  const double gap[6] = {-0.2, -0.05, -0.1, -0.15, -0.08, 0.1}, slip[6] = {0.5, 0.02, 1e-5, 0.0, 0.3, 0.7};
  for (int n = 0; n < 4; ++n) {
    Point p;
    for (int k = 0; k < 7; ++k) p.markers.push_back(random_motion(rng));
    const MarkerMotion& j = p.markers[6];
    for (int k = 0; k < 6; ++k) {
      Vec3 t = Vec3(u(rng), u(rng), u(rng));
      t -= t.dot(j.axes.col(2)) * j.axes.col(2);
      p.markers[k].position = j.position + gap[k] * j.axes.col(2) + t;
      set_normal_rate(p, k == 4 ? 0.5 : 0.05 * u(rng), k, 6);
      set_tangential(p, slip[k], rng, k, 6);
    }
    expect_matches(*b.element, p, "point-set contact " + std::to_string(n));
  }
}

// Valve seat: the valve (i = 0) along z_j of the seat (j = 1), in contact (axial closure 10..50 mm: far
// beyond a real seat's microns, so that the differences' step 1e-6 m is small against it), closing or opening
// slowly (alpha = 3 (1 - 0.8) / (2 * 1 m/s) = 0.3 s/m: the clamp fn = 0 for delta_a' < -3.3 m/s), opening
// fast (the clamp) and open; Palmgren's law (exponent 10/9) at 45 and 30 deg, a concave seat, and the linear
// `stiffness`.
TEST(ElementJacobians, ValveSeatInContactWithRateClampAndOpen) {
  const std::string law =
      "seat_diameter = 0.03\nface_radius = 0.05\nrestitution = 0.8\nreference_speed = 1.0\n";
  const std::vector<Built> seats = [&] {
    std::vector<Built> b;
    b.push_back(build("force", "valve-seat", law, {MarkerMotion{}, MarkerMotion{}}));
    b.push_back(build("force", "valve-seat", law + "seat_angle_deg = 30.0\nseat_radius = -0.2\n",
                      {MarkerMotion{}, MarkerMotion{}}));
    b.push_back(build("force", "valve-seat", law + "stiffness = 2.0e8\n", {MarkerMotion{}, MarkerMotion{}}));
    return b;
  }();
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n = 0; n < 6; ++n) {
    for (std::size_t k = 0; k < seats.size(); ++k) {
      const std::string tag =
          std::string(" (seat ").append(std::to_string(k)).append(", ").append(std::to_string(n)) + ")";
      Point p = two_random(rng);
      const MarkerMotion& j = p.markers[1];
      // on the axis, or off it by up to 5 mm (a misplaced marker: the law is still a plane law along z_j)
      const Vec3 off = (n % 2 ? 0.005 : 0.0) * Vec3(u(rng), u(rng), u(rng));
      p.markers[0].position = j.position - (0.03 + 0.02 * u(rng)) * j.axes.col(2) + off;
      set_normal_rate(p, 0.5 * u(rng));  // closing or opening slowly
      expect_matches(*seats[k].element, p, "valve seat in contact" + tag);
      set_normal_rate(p, 5.0 + u(rng));  // opening fast: 1 + alpha delta_a' < 0, clamped to no force
      expect_matches(*seats[k].element, p, "valve seat in the clamp" + tag, false);
      p.markers[0].position = j.position + (0.001 + 0.02 * (1.0 + u(rng))) * j.axes.col(2) + off;
      set_normal_rate(p, -0.5);  // closing, still open
      expect_matches(*seats[k].element, p, "valve seat open" + tag, false);
    }
  }
}

TEST(ElementJacobians, TableForce) {
  std::mt19937 rng(5);
  // breakpoints at +-0.6 and +-2 m: the random deflections (|x| <= 0.35) stay on the middle piece
  const Built b =
      build("force", "table-force", "table = [[-2.0, 3.0e4], [-0.6, 1.0e4], [0.6, -2.0e4], [2.0, -3.0e4]]\n",
            {MarkerMotion{}, MarkerMotion{}});
  for (int n = 0; n < 8; ++n) expect_matches(*b.element, two_random(rng), "table force " + std::to_string(n));
  // beyond the table's ends (constant): only the direction's turning with z_j
  const Built narrow = build("force", "table-force", "table = [[-0.001, 50.0], [0.001, -50.0]]\n",
                             {MarkerMotion{}, MarkerMotion{}});
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n = 0; n < 4; ++n) {
    Point p = two_random(rng);
    const Vec3 n_j = p.markers[1].axes.col(2);
    p.markers[0].position = p.markers[1].position + (n % 2 ? 0.2 : -0.2) * n_j + 0.1 * Vec3(u(rng), 0.0, 0.0);
    expect_matches(*narrow.element, p, "table force beyond the table " + std::to_string(n));
  }
}

TEST(ElementJacobians, MotorAsForceAndAsDriver) {
  std::mt19937 rng(3);
  // breakpoints at +-1000 rpm (105 rad/s); the random relative speeds stay below 100 rpm
  const std::string curve = "table = [[-3000.0, 20.0], [-1000.0, 15.0], [1000.0, -5.0], [3000.0, -10.0]]\n";
  for (const std::string section : {"force", "driver"}) {
    const Built b = build(section, "motor", curve, {MarkerMotion{}, MarkerMotion{}});
    for (int n = 0; n < 6; ++n)
      expect_matches(*b.element, two_random(rng), section + " motor " + std::to_string(n));
  }
}

TEST(ElementJacobians, LoadsAgainstTimeCrankAngleAndHarmonic) {
  std::mt19937 rng(9);
  struct Case {
    std::string type, keys;
  };
  // crank-angle tables are periodic (720 deg); the first leaves a wrap from 700 deg to 0 (= 720)
  const std::string crank_table =
      "abscissa = \"crank-angle\"\noffset_deg = 15.0\nscale = 2.5\n"
      "table = [[0.0, 0.0], [100.0, 40.0], [300.0, 100.0], [500.0, 20.0], [700.0, 5.0]]\n";
  const std::vector<Case> cases = {
      {"force", "direction = [0.0, 1.0, 0.5]\naxes = \"marker\"\n" + crank_table},
      {"torque", "direction = [1.0, -2.0, 0.5]\naxes = \"marker\"\n" + crank_table},
      {"force", "direction = [0.3, 1.0, 0.0]\n" + crank_table},
      {"torque", "direction = [1.0, 0.0, 0.0]\ntable = [[0.0, 1.0], [1.0, 3.0]]\n"},
      {"force", "direction = [1.0, 2.0, 3.0]\naxes = \"marker\"\ntable = [[0.0, 1.0], [1.0, 3.0]]\n"},
      {"force", "direction = [0.0, 0.0, 1.0]\naxes = \"marker\"\namplitude = 5.0\nfrequency_hz = 30.0\n"},
      {"torque",
       "direction = [0.0, 1.0, 1.0]\naxes = \"marker\"\namplitude = 5.0\nfrequency_hz = 30.0\nphase_deg = "
       "20\n"},
      {"torque", "direction = [0.0, 1.0, 1.0]\namplitude = 5.0\nfrequency_hz = 30.0\n"},
  };
  // crank angles (rad) away from the breakpoints: 1.9 deg (-15 wraps to 706.9: the wrap piece), 74, 401,
  // 710.5 - 15, -57 deg (wraps), and a later cycle
  const std::vector<double> cranks = {0.0333, 1.3, 7.0, 12.4, -1.0, 30.0};
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const Built b = build("load", cases[k].type, cases[k].keys, {MarkerMotion{}});
    const bool crank = b.element->uses_crank_angle();
    for (double c : cranks) {
      Point p{{random_motion(rng)}, {}, {}, 0.0123 + 0.1 * c * c, c};
      // loads along global axes against time have no dependence on any column: all zeros
      const bool moves = crank || cases[k].keys.find("\"marker\"") != std::string::npos;
      expect_matches(*b.element, p,
                     cases[k].type + " load " + std::to_string(k) + " at crank " + std::to_string(c), moves);
    }
  }
}

TEST(ElementJacobians, SpringDampersForReference) {
  std::mt19937 rng(21);
  const Built sd =
      build("force", "spring-damper", "k = 1e5\nd = 300\nkB = 2e5\ndB = 100\nxB = 0.01\nfree_length = 0.02\n",
            {MarkerMotion{}, MarkerMotion{}});
  const Built tsd = build("force", "torsional-spring-damper", "k = 500.0\nd = 2.0\nangle0_deg = 10.0\n",
                          {MarkerMotion{}, MarkerMotion{}});
  const Built mx =
      build("force", "maxwell", "k = 1e5\nc = 300\nfree_length = 0.02\n", {MarkerMotion{}, MarkerMotion{}});
  for (int n = 0; n < 4; ++n) {
    Point pm = two_random(rng);
    pm.z = {0.01 * n - 0.02};
    pm.zp = {0.5 - 0.3 * n};
    expect_matches(*mx.element, pm, "maxwell " + std::to_string(n));
    expect_matches(*sd.element, two_random(rng), "spring-damper " + std::to_string(n));
    Point p = two_random(rng);
    p.z = {0.3 * n - 0.4};
    p.zp = {1.7 - n};
    expect_matches(*tsd.element, p, "torsional spring-damper " + std::to_string(n));
  }
}

// Mass chain and valve spring: marker i at distance L from j along a random direction, the internal masses at
// their static positions plus offsets (m) and random speeds. Cases open, every segment in coil clash, and
// mixed (one segment shorter than its solid share, its neighbour longer); N = 1, 5 and 20 (65 columns).
Point chain_point(std::mt19937& rng, double length, double end_height, const std::vector<double>& offset) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Point p = two_random(rng);
  const Vec3 e = Vec3(u(rng), u(rng), u(rng)).normalized();
  p.markers[0].position = p.markers[1].position + length * e;
  const int n = static_cast<int>(offset.size());
  for (int k = 1; k <= n; ++k) {
    p.z.push_back(end_height + k * (length - 2 * end_height) / (n + 1) + offset[k - 1]);
    p.z.push_back(0.5 * u(rng));
    p.zp.push_back(0.3 * u(rng));
    p.zp.push_back(50.0 * u(rng));
  }
  return p;
}

TEST(ElementJacobians, MassChainAndValveSpringOpenAndInClash) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // valve spring: d 4 mm, 6 active coils, one dead coil per end (h = 4 mm), solid 32 mm, segment solid 4 mm
  const std::string spring =
      "wire_diameter = 0.004\nmean_diameter = 0.025\nactive_coils = 6\nfree_length = 0.05\n"
      "damping_ratio = 0.02\n";
  const std::vector<MarkerMotion> at_rest = {MarkerMotion{}, MarkerMotion{}};
  for (int n : {1, 5, 20}) {
    const Built b = build("force", "valve-spring", spring + "masses = " + std::to_string(n) + "\n", at_rest);
    const double seg_solid = 0.024 / (n + 1);
    for (int c = 0; c < 3; ++c) {
      std::vector<double> noise(n);
      for (double& x : noise) x = 0.05 * seg_solid * u(rng);
      const std::string tag = " (N = " + std::to_string(n) + ", " + std::to_string(c) + ")";
      expect_matches(*b.element, chain_point(rng, 0.042, 0.004, noise), "valve spring open" + tag);
      expect_matches(*b.element, chain_point(rng, 0.026, 0.004, noise), "valve spring in clash" + tag);
      // active length 28 mm: segments 4.67 mm / (N + 1) * 6; moving mass 1 by -0.3 segment solid puts the
      // segment below it in clash and the one above it open
      std::vector<double> mixed = noise;
      mixed[0] -= 0.3 * seg_solid;
      expect_matches(*b.element, chain_point(rng, 0.036, 0.004, mixed), "valve spring mixed" + tag);
    }
  }
  // mass chain with unequal masses, segment damping and a solid length of 0.1 m (segment 0.025 m)
  const Built chain =
      build("force", "mass-chain",
            "mass_list = [0.01, 0.02, 0.015]\nstiffness = 1e5\ndamping = 20\nfree_length = 0.3\n"
            "solid_length = 0.1\n",
            at_rest);
  for (int c = 0; c < 4; ++c) {
    const std::vector<double> noise = {0.005 * u(rng), 0.005 * u(rng), 0.005 * u(rng)};
    expect_matches(*chain.element, chain_point(rng, 0.2, 0.0, noise), "mass chain open " + std::to_string(c));
    expect_matches(*chain.element, chain_point(rng, 0.08, 0.0, noise),
                   "mass chain in clash " + std::to_string(c));
  }
}

// Every registered element type has its analytic Jacobian (the journal bearing differentiates its film model
// partly by differences and is checked in test_jacobian.cpp). A new type needs its keys here.
// The roller on a cam: the roller's centre placed at a random angle on the pitch curve (cam::pitch_point),
// pushed in along the normal by 3 mm (the differences step 1e-6 m must be small against it) and moved off the
// cam's plane, the cam turned and spinning at random, the roller moving at random (pressing and separating
// slowly, below the clamp of the damping): on the tangent cam's base circle, flanks and nose (the normal
// turns with the foot, except on the flanks), and on the eccentric.
TEST(ElementJacobians, RollerCamOnEveryRegionOfTheProfile) {
  const std::string common = "roller_width = 0.015\nrestitution = 0.7\nroller_radius = 0.012\n";
  const Built tangent = build("force", "roller-cam",
                              common +
                                  "profile = \"tangent\"\nbase_radius = 0.02\nnose_radius = 0.01\n"
                                  "lobe_distance = 0.02\n",
                              {MarkerMotion{}, MarkerMotion{}});
  const Built eccentric = build(
      "force", "roller-cam", common + "profile = \"eccentric\"\nbase_radius = 0.02\neccentricity = 0.005\n",
      {MarkerMotion{}, MarkerMotion{}});
  const Built linear =
      build("force", "roller-cam",
            common + "stiffness = 1e8\nprofile = \"eccentric\"\nbase_radius = 0.02\neccentricity = 0.005\n",
            {MarkerMotion{}, MarkerMotion{}});
  const auto profile_of = [](const std::string& keys) {
    const input::Document doc = input::Document::parse(keys, "cam.toml");
    std::vector<std::filesystem::path> files;
    return cam::read_cam_profile(doc.root(), ".", files);
  };
  const auto tangent_profile = profile_of(
      "profile = \"tangent\"\nbase_radius = 0.02\nnose_radius = 0.01\n"
      "lobe_distance = 0.02\nroller_radius = 0.012\n");
  const auto eccentric_profile = profile_of(
      "profile = \"eccentric\"\nbase_radius = 0.02\neccentricity = 0.005\nroller_radius = 0.012\n");
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto place = [&](const cam::CamProfile& profile, double psi) {
    Point p = two_random(rng, 0.05);
    MarkerMotion& cam = p.markers[1];
    const cam::PitchPoint pp = cam::pitch_point(profile, psi);
    const double depth = 3e-3 * (1.0 + 0.3 * u(rng));  // deep: the differences step is 1e-6 m
    const Vec3 local(pp.x - depth * pp.nx, pp.y - depth * pp.ny, 0.003 * u(rng));
    p.markers[0].position = cam.position + cam.axes * local;
    // the roller's velocity relative to the cam's material point under it: along the normal within 1 mm/s
    const Vec3 n = cam.axes * Vec3(pp.nx, pp.ny, 0.0);
    const Vec3 vr = p.markers[0].velocity - cam.velocity -
                    cam.angular_velocity.cross(p.markers[0].position - cam.position);
    p.markers[0].velocity += (1e-3 * u(rng) - n.dot(vr)) * n;
    return p;
  };
  // Cam angles theta (the lift's; psi = -theta): the nose is at 0, the flanks between about 32 and 60 deg.
  for (const double deg : {0.0, 15.0, 40.0, -45.0, 120.0, 200.0}) {
    const double psi = -deg * std::numbers::pi / 180;
    expect_matches(*tangent.element, place(*tangent_profile, psi),
                   "roller-cam, tangent cam at " + std::to_string(deg));
    expect_matches(*eccentric.element, place(*eccentric_profile, psi),
                   "roller-cam, eccentric at " + std::to_string(deg));
    expect_matches(*linear.element, place(*eccentric_profile, psi),
                   "roller-cam, linear law at " + std::to_string(deg));
  }
  Point open = place(*eccentric_profile, 0.3);
  open.markers[0].position =
      open.markers[1].position + open.markers[1].axes * Vec3(0.06, 0.01, 0.0);  // lifted off
  expect_matches(*eccentric.element, open, "roller-cam open", false);
}

// roller-cam's options (valvetrain.md section 2): the crowned roller's point law on the polynomial event,
// whose curvature changes along the profile (K follows the foot: R_p'(psi)), and on the tangent cam with a
// crown smaller than the rolling radius (the ellipse's major axis in the rolling plane); the roller's
// resistance in pure rolling; the slipping roller whose spin is a state (slip speed within +-0.3 m/s of pure
// rolling, a regularization of 0.3 m/s and a Stribeck hump so that mu' and tanh' enter). Placed as in the
// test above.
TEST(ElementJacobians, RollerCamCrownedAndWithRollerFriction) {
  const std::string common = "roller_width = 0.015\nrestitution = 0.7\nroller_radius = 0.012\n";
  const std::string poly =
      "profile = \"polynomial\"\nbase_radius = 0.02\nlift = 0.008\nrise_deg = 60\nramp_deg = 20\n"
      "ramp_height = 0.0003\n";
  const std::string tang =
      "profile = \"tangent\"\nbase_radius = 0.02\nnose_radius = 0.01\nlobe_distance = 0.02\n";
  const std::string resistance = "pin_friction = 0.1\npin_radius = 0.004\nrolling_resistance = 1e-4\n";
  const std::string slip =
      "roller_inertia = 2e-6\nmu_static = 0.15\nmu_dynamic = 0.08\nstribeck_speed = "
      "0.2\nregularization_speed = 0.3\n";
  const std::vector<MarkerMotion> two{MarkerMotion{}, MarkerMotion{}};
  const Built crowned = build("force", "roller-cam", common + poly + "crown_radius = 0.5\n", two);
  const Built ball = build("force", "roller-cam", common + tang + "crown_radius = 0.004\n", two);
  const Built rolling =
      build("force", "roller-cam", common + poly + resistance + "regularization_speed = 0.3\n", two);
  const Built slipping =
      build("force", "roller-cam", common + poly + "crown_radius = 0.5\n" + resistance + slip, two);
  const Built slipping_line = build("force", "roller-cam", common + tang + resistance + slip, two);
  const auto profile_of = [](const std::string& keys) {
    const input::Document doc = input::Document::parse(keys, "cam.toml");
    std::vector<std::filesystem::path> files;
    return cam::read_cam_profile(doc.root(), ".", files);
  };
  const auto poly_profile = profile_of(poly + "roller_radius = 0.012\n");
  const auto tang_profile = profile_of(tang + "roller_radius = 0.012\n");
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto place = [&](const cam::CamProfile& profile, double psi, bool spin) {
    Point p = two_random(rng, 0.05);
    MarkerMotion& cam = p.markers[1];
    const cam::PitchPoint pp = cam::pitch_point(profile, psi);
    const double depth = 3e-3 * (1.0 + 0.3 * u(rng));  // deep: the differences step is 1e-6 m
    const Vec3 local(pp.x - depth * pp.nx, pp.y - depth * pp.ny, 0.003 * u(rng));
    p.markers[0].position = cam.position + cam.axes * local;
    const Vec3 n = cam.axes * Vec3(pp.nx, pp.ny, 0.0);
    const Vec3 vr = p.markers[0].velocity - cam.velocity -
                    cam.angular_velocity.cross(p.markers[0].position - cam.position);
    p.markers[0].velocity += (1e-3 * u(rng) - n.dot(vr)) * n;
    if (spin) {  // the roller's spin: pure rolling (v_slip = 0) plus a slip of up to 0.3 m/s
      const Vec3 t = cam.axes * Vec3(pp.dx, pp.dy, 0.0).normalized(), z = cam.axes.col(2);
      const Vec3 vr2 = p.markers[0].velocity - cam.velocity -
                       cam.angular_velocity.cross(p.markers[0].position - cam.position);
      const double rolling = (t.dot(vr2) + 0.012 * z.dot(cam.angular_velocity)) / 0.012;
      p.z = {rolling + 0.3 * u(rng) / 0.012};
      p.zp = {1e3 * u(rng)};
    }
    return p;
  };
  // Not at the polynomial event's top (0 deg) itself: its jerk jumps there, so the pitch curve's curvature
  // has a kink and central differences straddling it disagree with either side (the plain element's too).
  for (const double deg : {3.0, -2.0, 25.0, -50.0, 70.0, 120.0, 200.0}) {
    const double psi = -deg * std::numbers::pi / 180;
    const std::string at = " at " + std::to_string(deg);
    expect_matches(*crowned.element, place(*poly_profile, psi, false), "roller-cam crowned, polynomial" + at);
    expect_matches(*ball.element, place(*tang_profile, psi, false), "roller-cam crown 4 mm, tangent" + at);
    expect_matches(*rolling.element, place(*poly_profile, psi, false), "roller-cam rolling resistance" + at);
    expect_matches(*slipping.element, place(*poly_profile, psi, true), "roller-cam slipping, crowned" + at);
    expect_matches(*slipping_line.element, place(*tang_profile, psi, true),
                   "roller-cam slipping, tangent" + at);
  }
  Point open = place(*poly_profile, 0.3, false);
  open.markers[0].position =
      open.markers[1].position + open.markers[1].axes * Vec3(0.06, 0.01, 0.0);  // lifted off
  expect_matches(*crowned.element, open, "roller-cam crowned, open", false);
  expect_matches(*rolling.element, open, "roller-cam rolling resistance, open", false);
}

// The piston-liner element scaled up so that the differences step (1e-6 m, relative to the clearance 0.5 m)
// resolves the film: a skirt of 0.1 m in a bore of radius 1 m, random marker motions keep the film above 0.1
// m; the asperities (sigma 0.04 m) touch where the film is below 0.16 m; the film solved to 1e-13.
const std::string kPistonLinerKeys =
    "bore_radius = 1.0\nradial_clearance = 0.5\nskirt_length = 0.1\nskirt_top = 0.05\nviscosity = 0.01\n"
    "sigma = 0.04\nK = 1e-3\nmodulus = 1e8\nmu_asperity = 0.1\nfriction_regularization_speed = 0.5\n"
    "cells_axial = 8\ncells_around = 6\nfilm_tolerance = 1e-13\nbarrel = [[-0.05, 0.01], [0.0, 0.0], [0.05, "
    "0.02]]\n";

// The piston near the liner's thrust side: in the film only, in mixed contact, and past the nominal contact
// (h < 0 over part of the skirt: the film floor and the asperities); sliding fast, slowly (the asperity
// friction's regularization) and with both cavitation models.
TEST(ElementJacobians, PistonLinerFromFilmToContact) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Built jfo = build("force", "piston-liner", kPistonLinerKeys, {MarkerMotion{}, MarkerMotion{}});
  const Built full =
      build("force", "piston-liner", kPistonLinerKeys + "cavitation = \"none\"\narcs_deg = [[-180, 180]]\n",
            {MarkerMotion{}, MarkerMotion{}});
  for (const double e : {0.1, 0.38, 0.47, 0.53}) {  // clearance 0.5: sigma 0.04 touches below h = 0.16
    for (const double speed : {2.0, 0.1}) {
      Point p = two_random(rng);
      const MarkerMotion& j = p.markers[1];
      MarkerMotion& i = p.markers[0];
      // piston axis along z_j tilted by 0.02 rad about the pin axis, pin 0.01 m off e along x_j
      i.axes = Eigen::AngleAxisd(0.02 * u(rng), -j.axes.col(1)).toRotationMatrix() * j.axes;
      i.position = j.position + (e + 0.01 * u(rng)) * j.axes.col(0) + 0.1 * u(rng) * j.axes.col(2);
      i.velocity = j.velocity + j.angular_velocity.cross(i.position - j.position) + speed * j.axes.col(2) +
                   0.2 * u(rng) * j.axes.col(0);
      const std::string tag = "e = " + std::to_string(e) + ", V = " + std::to_string(speed);
      expect_matches(*jfo.element, p, "piston-liner JFO, " + tag);
      expect_matches(*full.element, p, "piston-liner full circle, " + tag);
    }
  }
}

/// The piston-liner element's markers (tests below): the piston at eccentricity e (+-0.01) in a bore moving
/// at random, tilted up to 0.02 rad about the pin axis, sliding at 1.5 m/s; then each surface marker k >= 2
/// at its initial grid point (about j's axis for k < first_skirt, the liner's; about i's from there, the
/// skirt's) displaced radially by up to 0.05 m and moving at random relative to that marker.
Point piston_with_surface_markers(std::mt19937& rng, const std::vector<MarkerMotion>& initial,
                                  std::size_t first_skirt, double e) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Point p = two_random(rng);
  const MarkerMotion& j = p.markers[1];
  MarkerMotion& i = p.markers[0];
  i.axes = Eigen::AngleAxisd(0.02 * u(rng), -j.axes.col(1)).toRotationMatrix() * j.axes;
  i.position = j.position + (e + 0.01 * u(rng)) * j.axes.col(0) + 0.02 * u(rng) * j.axes.col(2);
  i.velocity = j.velocity + j.angular_velocity.cross(i.position - j.position) + 1.5 * j.axes.col(2) +
               0.2 * u(rng) * j.axes.col(0);
  for (std::size_t k = 2; k < initial.size(); ++k) {
    const MarkerMotion o = k < first_skirt ? p.markers[1] : p.markers[0];
    MarkerMotion m = random_motion(rng);
    const Vec3 local = initial[k].position;
    const Vec3 radial = Vec3(local.x(), local.y(), 0).normalized();
    m.position = o.position + o.axes * (local + 0.05 * u(rng) * radial);
    m.velocity =
        o.velocity + o.angular_velocity.cross(m.position - o.position) + 0.3 * u(rng) * (o.axes * radial);
    p.markers.push_back(m);
  }
  return p;
}

// The elasto-hydrodynamic liner (piston-liner with `liner` markers, docs/bearing.md section 17): a grid of 3
// axial levels x 6 angles on the bore (R 1 m) around the piston's position, each marker displaced radially by
// up to 0.05 m (a tenth of the clearance) and moving at random; j moving at random as well (the markers'
// radial rates are relative to it); in the film and in mixed contact. The liner markers' columns are central
// differences of the film (piston_liner.cpp): the check is that the chain rule and the force transfer are
// right.
TEST(ElementJacobians, PistonLinerOnDeformableLinerMarkers) {
  std::mt19937 rng(17);
  const double levels[] = {-0.12, -0.02, 0.09}, pi = std::numbers::pi;
  std::vector<MarkerMotion> initial(2);  // i, j at the origin with identity axes; the ring around j's z axis
  std::vector<std::string> bodies = {"piston", "block"};
  for (int b = 0; b < 6; ++b)
    for (double z : levels) {
      MarkerMotion m;
      const double th = -pi + (b + 0.3) * pi / 3;
      m.position = Vec3(std::cos(th), std::sin(th), z);  // x_j, y_j = -w: theta from x_j towards w = -y_j
      initial.push_back(m), bodies.push_back("block");
    }
  for (const std::string& cav : {std::string("jfo"), std::string("none")}) {
    const input::Document doc =
        input::Document::parse(kPistonLinerKeys + "cavitation = \"" + cav + "\"\n", "ehl.toml");
    const input::Table t = doc.root();
    std::vector<std::filesystem::path> files;
    ElementContext c{t, ".", files, initial, bodies};
    const auto element = builtin_elements().find("force", "piston-liner")->make(c);
    ASSERT_EQ(element->marker_count(), 20);
    for (const double e : {0.1, 0.45}) {
      const Point p = piston_with_surface_markers(rng, initial, initial.size(), e);
      expect_matches(*element, p, "piston-liner on liner markers, " + cav + ", e = " + std::to_string(e));
    }
  }
}

// The flexible piston's skirt (piston-liner with `skirt` markers, docs/bearing.md section 18), alone and with
// the liner markers of the test above: a grid of 3 levels x 6 angles on the skirt (radius 1 m about i's
// axis), each marker displaced radially by up to 0.05 m and moving at random relative to i. The check is that
// the chain rule to i's columns and the force transfer to the skirt markers and back to i are right.
TEST(ElementJacobians, PistonLinerOnDeformableSkirtMarkers) {
  std::mt19937 rng(23);
  const double pi = std::numbers::pi;
  for (const bool with_liner : {false, true}) {
    std::vector<MarkerMotion> initial(2);  // i, j at the origin with identity axes
    std::vector<std::string> bodies = {"piston", "block"};
    auto ring = [&](const std::vector<double>& levels, double offset, const char* body) {
      for (int b = 0; b < 6; ++b)
        for (double z : levels) {
          MarkerMotion m;
          const double th = -pi + (b + offset) * pi / 3;
          m.position = Vec3(std::cos(th), std::sin(th), z);
          initial.push_back(m), bodies.push_back(body);
        }
    };
    if (with_liner) ring({-0.12, -0.02, 0.09}, 0.3, "block");
    const std::size_t first_skirt = initial.size();
    ring({-0.04, 0.0, 0.05}, 0.1, "piston");
    std::string skirt = "skirt = [";
    for (int k = 0; k < 18; ++k) skirt += (k ? ", \"piston.s" : "\"piston.s") + std::to_string(k) + "\"";
    const input::Document doc = input::Document::parse(kPistonLinerKeys + skirt + "]\n", "skirt.toml");
    const input::Table t = doc.root();
    std::vector<std::filesystem::path> files;
    ElementContext c{t, ".", files, initial, bodies};
    const auto element = builtin_elements().find("force", "piston-liner")->make(c);
    ASSERT_EQ(element->marker_count(), static_cast<int>(initial.size()));
    for (const double e : {0.1, 0.4}) {
      const Point p = piston_with_surface_markers(rng, initial, first_skirt, e);
      expect_matches(*element, p,
                     std::string("piston-liner on skirt markers") + (with_liner ? " and liner markers" : "") +
                         ", e = " + std::to_string(e));
    }
  }
}

// flat-face-cam: the face pressed 0.5 to 1.5 mm into the cam, at a random offset along the face, tilted up to
// 0.05 rad out of the cam's plane (the projection's derivative), the cam turned and spinning at random, the
// face sliding at random (friction with a Stribeck hump and a wide regularization, so that mu' enters) and
// approaching within 1 mm/s; on the polynomial event's base circle, ramp, rise and top, and on the eccentric
// cam (Palmgren's and a linear law); lifted off: no force, no Jacobian.
TEST(ElementJacobians, FlatFaceCamAroundTheProfile) {
  const std::string friction =
      "mu_static = 0.15\nmu_dynamic = 0.08\nstribeck_speed = 0.2\nregularization_speed = 0.05\n";
  const std::string common = "face_width = 0.015\nrestitution = 0.7\nroller_radius = 0.012\n" + friction;
  const std::string poly =
      "profile = \"polynomial\"\nbase_radius = 0.02\nlift = 0.008\nrise_deg = 60\n"
      "ramp_deg = 20\nramp_height = 0.0003\n";
  const std::string ecc = "profile = \"eccentric\"\nbase_radius = 0.02\neccentricity = 0.005\n";
  const Built polynomial = build("force", "flat-face-cam", common + poly, {MarkerMotion{}, MarkerMotion{}});
  const Built eccentric = build("force", "flat-face-cam", common + ecc, {MarkerMotion{}, MarkerMotion{}});
  const Built linear =
      build("force", "flat-face-cam", common + "stiffness = 1e8\n" + ecc, {MarkerMotion{}, MarkerMotion{}});
  const auto profile_of = [](const std::string& keys) {
    const input::Document doc = input::Document::parse(keys, "cam.toml");
    std::vector<std::filesystem::path> files;
    return cam::read_cam_profile(doc.root(), ".", files);
  };
  const auto poly_profile = profile_of(poly + "roller_radius = 0.012\n");
  const auto ecc_profile = profile_of(ecc + "roller_radius = 0.012\n");
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // The face's support value h by brute force over the pitch curve (the cam surface is its inner offset).
  const auto support_h = [](const cam::CamProfile& profile, double phi) {
    double h = -1e300;
    for (int k = 0; k < 200000; ++k) {
      const cam::PitchPoint pp = cam::pitch_point(profile, 2 * std::numbers::pi * k / 200000);
      h = std::max(h, pp.x * std::cos(phi) + pp.y * std::sin(phi));
    }
    return h - profile.roller_radius();
  };
  const auto place = [&](const cam::CamProfile& profile, double phi) {
    Point p = two_random(rng, 0.05);
    MarkerMotion& cam = p.markers[1];
    MarkerMotion& face = p.markers[0];
    const double depth = 1e-3 * (1.0 + 0.5 * u(rng));
    const Vec3 uc(std::cos(phi), std::sin(phi), 0.0), tc(-std::sin(phi), std::cos(phi), 0.0);
    const Vec3 local =
        (support_h(profile, phi) - depth) * uc + 0.01 * u(rng) * tc + Vec3(0, 0, 0.003 * u(rng));
    face.position = cam.position + cam.axes * local;
    // z_i = -u, tilted out of the cam's plane by up to 0.05 rad about t
    const Vec3 zi = Eigen::AngleAxisd(0.05 * u(rng), cam.axes * tc).toRotationMatrix() * (cam.axes * -uc);
    const Vec3 xi = zi.unitOrthogonal();
    face.axes.col(0) = xi;
    face.axes.col(1) = zi.cross(xi);
    face.axes.col(2) = zi;
    // slow approach: the normal relative velocity at the face's origin within 1 mm/s
    const Vec3 n = cam.axes * uc;
    const Vec3 vr = face.velocity - cam.velocity - cam.angular_velocity.cross(face.position - cam.position);
    face.velocity += (1e-3 * u(rng) - n.dot(vr)) * n;
    face.angular_velocity *= 0.1;
    return p;
  };
  // Face directions: the lift's cam angle theta = -phi; the polynomial event's nose at 0, its ramps at
  // +-(60..80) deg, the base circle beyond.
  for (const double deg : {0.0, 25.0, -50.0, 70.0, 120.0, 200.0}) {
    const double phi = -deg * std::numbers::pi / 180;
    expect_matches(*polynomial.element, place(*poly_profile, phi),
                   "flat-face-cam, polynomial at " + std::to_string(deg));
    expect_matches(*eccentric.element, place(*ecc_profile, phi),
                   "flat-face-cam, eccentric at " + std::to_string(deg));
    expect_matches(*linear.element, place(*ecc_profile, phi),
                   "flat-face-cam, linear law at " + std::to_string(deg));
  }
  Point open = place(*ecc_profile, 0.3);
  open.markers[0].position +=
      0.01 * (open.markers[1].axes * Vec3(std::cos(0.3), std::sin(0.3), 0.0));  // lifted off
  expect_matches(*eccentric.element, open, "flat-face-cam open", false);
}

TEST(ElementJacobians, EveryRegisteredTypeIsAnalytic) {
  const std::map<std::string, std::string> keys = {
      {"force spring-damper", "k = 1e4\nd = 10\n"},
      {"force maxwell", "k = 1e5\nc = 300\nfree_length = 0.02\n"},
      {"force mass-chain",
       "masses = 3\nmass = 0.03\nstiffness = 1e5\ndamping_ratio = 0.05\nfree_length = 0.2\n"},
      {"force valve-spring",
       "wire_diameter = 0.004\nmean_diameter = 0.025\nactive_coils = 6\nfree_length = 0.05\n"},
      {"force bushing",
       "stiffness = [1e5, 2e5, 3e5, 1e3, 2e3, 3e3]\ndamping = [10, 20, 30, 0.1, 0.2, 0.3]\n"},
      {"force torsional-spring-damper", "k = 500.0\nd = 2.0\n"},
      {"force bearing-spring", kBearingSpringKeys},
      {"force contact", "stiffness = 1e6\nclearance = -0.5\nmu_static = 0.3\n"},
      {"force point-set-contact", "stiffness = 1e6\nclearance = -0.5\nmu_static = 0.3\n"},
      {"force table-force", "table = [[-1.0, 1e4], [1.0, -1e4]]\n"},
      {"force roller-cam",
       "roller_width = 0.01\nprofile = \"eccentric\"\nbase_radius = 0.1\neccentricity = 0.02\n"
       "roller_radius = 0.02\n"},
      {"force motor", "table = [[-1000.0, 20.0], [3000.0, -5.0]]\n"},
      {"force flat-face-cam",
       "face_width = 0.01\nprofile = \"eccentric\"\nbase_radius = 0.1\n"
       "eccentricity = 0.02\nroller_radius = 0.02\nmu_static = 0.1\n"},
      {"driver motor", "table = [[-1000.0, 20.0], [3000.0, -5.0]]\n"},
      {"load force", "direction = [0, 0, 1]\naxes = \"marker\"\namplitude = 1.0\nfrequency_hz = 10.0\n"},
      {"load torque",
       "direction = [0, 0, 1]\nabscissa = \"crank-angle\"\ntable = [[0.0, 0.0], [720.0, 1.0]]\n"},
      {"force valve-seat", "seat_diameter = 0.03\nface_radius = 0.05\nrestitution = 0.8\n"},
      {"force piston-liner", kPistonLinerKeys},
  };
  std::mt19937 rng(1);
  std::set<std::string> seen;
  for (const ElementType* et : builtin_elements().all()) {
    const std::string name = et->section + " " + et->name;
    if (et->name == "journal-bearing") continue;
    seen.insert(name);
    const auto it = keys.find(name);
    ASSERT_NE(it, keys.end()) << name
                              << ": a registered type without keys in this test (add them, and its checks)";
    // one marker per key, three for a list key (`name[]`, element_registry.hpp)
    std::size_t markers = 0;
    for (const auto& key : et->marker_keys) markers += key.ends_with("[]") ? 3 : key.ends_with("[]?") ? 0 : 1;
    std::vector<MarkerMotion> initial(markers);
    const Built b = build(et->section, et->name, it->second, initial);
    Point p;
    for (std::size_t k = 0; k < initial.size(); ++k) p.markers.push_back(random_motion(rng));
    for (const auto& s : b.element->states()) p.z.push_back(s.initial + 0.1), p.zp.push_back(0.2);
    p.crank = 1.0;
    const Result r = check(*b.element, p);
    EXPECT_TRUE(r.analytic) << name << ": jacobian() returns false (the model differentiates it locally)";
    EXPECT_LE(r.worst, kTolerance) << name << ": worst at " << r.where;
    double& w = worst_per_type()[b.element->type()];
    w = std::max(w, r.worst);
  }
  EXPECT_EQ(seen.size(), keys.size()) << "a type listed here is no longer registered";
  // The worst error per type over this test and the ones before it in the same run (docs/verification.md).
  for (const auto& [type, worst] : worst_per_type())
    std::printf("measured: element Jacobian %-26s worst relative error %.2e (tolerance %.0e)\n", type.c_str(),
                worst, kTolerance);
}

}  // namespace
}  // namespace nvh::solve
