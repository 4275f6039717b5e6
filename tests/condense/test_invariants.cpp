// Mass properties and floating-frame invariants.
//
// Reference: a hand calculation with rigid-body formulas, independent of the finite elements: each
// prismatic segment of length L, section A, Iy, Iz (local axes) has mass rho A L at its midpoint and,
// about its centre in local axes, J = rho diag(L (Iy + Iz), Iy L + A L^3 / 12, Iz L + A L^3 / 12);
// rotated to component axes, moved by the parallel-axis theorem, plus the point masses with their own J.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "beam_fixtures.hpp"
#include "common/log.hpp"
#include "condense/beam_model.hpp"
#include "condense/component_reader.hpp"
#include "condense/condense.hpp"
#include "condense/timoshenko_beam.hpp"

namespace nvh::condense {
namespace {

using namespace testing;

const Logger kQuiet{std::cerr, "test", Verbosity::kQuiet};

/// A crank throw: journal along x, a web up in y (rectangular, y_axis given), a pin along x offset by
/// the crank radius, a web down, a journal; a counterweight on a rigid link opposite the pin, and a
/// flywheel mass at the end.
Component crank_throw() {
  Component c = straight_beam(1.0, circle(0.05, 0.9), 6);
  const double r = 0.045;
  c.beam.points = {Vec3{0, 0, 0},    Vec3{0.06, 0, 0}, Vec3{0.06, r, 0},
                   Vec3{0.12, r, 0}, Vec3{0.12, 0, 0}, Vec3{0.18, 0, 0}};
  BeamSection web = rectangle(0.07, 0.02, 0.833);  // 70 mm wide (local y), 20 mm thick (local z)
  web.y_axis = Vec3{0, 0, 1};                      // wide direction along global z
  c.beam.segment_sections = {circle(0.055, 0.9), web, circle(0.048, 0.9), web, circle(0.055, 0.9)};
  c.beam.rigid_links = {RigidLink{{0.06, 0, 0}, {0.06, -0.04, 0}, {}, {}}};
  c.beam.masses = {PointMass{{0.06, -0.04, 0}, 0.8, {1e-3, 2e-3, 3e-3}, {}, {}},
                   PointMass{{0.18, 0, 0}, 6.0, {0.08, 0.04, 0.05}, {}, {}}};
  c.interfaces = {point("main1", {0, 0, 0}), point("pin", {0.09, r, 0}), point("main2", {0.18, 0, 0})};
  c.observers = {point("flywheel", {0.18, 0, 0})};
  c.beam.elements_per_segment = 6;
  return c;
}

struct HandInertia {
  double m = 0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();   // sum m x
  Eigen::Matrix3d origin = Eigen::Matrix3d::Zero();  // about the origin

  void add(double mass, const Eigen::Vector3d& at, const Eigen::Matrix3d& j_own) {
    m += mass;
    first += mass * at;
    origin += j_own + mass * (at.squaredNorm() * Eigen::Matrix3d::Identity() - at * at.transpose());
  }
};

HandInertia hand_calculation(const Component& c) {
  const double rho = c.materials.at("steel").rho;
  HandInertia h;
  for (std::size_t s = 0; s + 1 < c.beam.points.size(); ++s) {
    const BeamSection& sec = c.beam.segment_sections[s];
    const Eigen::Vector3d a(c.beam.points[s].data()), b(c.beam.points[s + 1].data());
    const double L = (b - a).norm();
    const Eigen::Vector3d hint = sec.y_axis ? Eigen::Vector3d((*sec.y_axis).data()) : Eigen::Vector3d::Zero();
    const Eigen::Matrix3d R = beam_axes(a, b, hint);  // rows: local axes
    Eigen::Matrix3d local = Eigen::Matrix3d::Zero();
    local(0, 0) = rho * L * (sec.Iy + sec.Iz);
    local(1, 1) = rho * (sec.Iy * L + sec.A * L * L * L / 12.0);
    local(2, 2) = rho * (sec.Iz * L + sec.A * L * L * L / 12.0);
    h.add(rho * sec.A * L, 0.5 * (a + b), R.transpose() * local * R);
  }
  for (const PointMass& pm : c.beam.masses) {
    h.add(pm.m, Eigen::Vector3d(pm.at.data()), Eigen::Vector3d(pm.J.data()).asDiagonal());
  }
  return h;
}

TEST(Invariants, MassCentreAndInertiaMatchAHandCalculation) {
  const Component c = crank_throw();
  const HandInertia h = hand_calculation(c);
  const Superelement se = [&] {
    Component cc = c;
    cc.reduction.method = ReductionMethod::kModal;
    cc.reduction.modes = 6;
    return condense_component(cc, EigenBackend::kBlockLanczos, kQuiet);
  }();
  EXPECT_NEAR(se.inertia.mass / h.m, 1.0, 1e-12);
  const Eigen::Vector3d com = h.first / h.m;
  EXPECT_NEAR((se.inertia.center_of_mass - com).norm(), 0.0, 1e-12);
  EXPECT_NEAR((se.inertia.inertia_origin - h.origin).norm() / h.origin.norm(), 0.0, 1e-12);
  const Eigen::Matrix3d about_com =
      h.origin - h.m * (com.squaredNorm() * Eigen::Matrix3d::Identity() - com * com.transpose());
  EXPECT_NEAR((se.inertia.inertia - about_com).norm() / about_com.norm(), 0.0, 1e-10);
}

TEST(Invariants, TestdataCrankshaftMatchesAHandCalculation) {
  // The 4-cylinder crankshaft of testdata/: 28 segments, 8 counterweights on rigid links, pulley and
  // flywheel; the same prism-and-point-mass hand calculation.
  Component c = read_component(std::string(NVH_SOURCE_DIR) + "/testdata/crankshaft.toml");
  const HandInertia h = hand_calculation(c);
  c.reduction.method = ReductionMethod::kModal;
  c.reduction.modes = 4;
  c.reduction.fmax_hz = 0.0;
  const Superelement se = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
  EXPECT_NEAR(se.inertia.mass / h.m, 1.0, 1e-12);
  EXPECT_NEAR((se.inertia.center_of_mass - h.first / h.m).norm(), 0.0, 1e-12);
  EXPECT_NEAR((se.inertia.inertia_origin - h.origin).norm() / h.origin.norm(), 0.0, 1e-12);
  EXPECT_NEAR(h.m, 25.88, 0.01);  // the file's header: crank 16.4 kg + pulley 1.5 kg + flywheel 8 kg
}

TEST(Testdata, ComponentsCondenseAsWrittenAndMatchAFullModalSolve) {
  // Each example component reduced as its file says; the reduced frequencies in its band of interest
  // against the unreduced model's (modal solve), and the mass against the hand calculation.
  struct Case {
    const char* file;
    double band_hz;    // band of interest stated in the file
    double tolerance;  // relative, on every mode in the band
  };
  for (const Case& k : {Case{"crankshaft.toml", 3000.0, 1e-3}, Case{"conrod.toml", 5000.0, 1e-3}}) {
    const Component c = read_component(std::string(NVH_SOURCE_DIR) + "/testdata/" + k.file);
    const Superelement reduced = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
    Component full = c;
    full.reduction.method = ReductionMethod::kModal;
    full.reduction.fmax_hz = 1.2 * k.band_hz;
    full.reduction.modes = 0;
    const Superelement modal = condense_component(full, EigenBackend::kBlockLanczos, kQuiet);
    int in_band = 0;
    for (int i = 0; i < modal.frequency_hz.size() && modal.frequency_hz(i) <= k.band_hz; ++i, ++in_band) {
      EXPECT_NEAR(reduced.frequency_hz(i) / modal.frequency_hz(i), 1.0, k.tolerance)
          << k.file << " mode " << i + 1;
    }
    EXPECT_GE(in_band, 1) << k.file;
    EXPECT_NEAR(reduced.inertia.mass / hand_calculation(c).m, 1.0, 1e-12) << k.file;
  }
}

TEST(Invariants, RigidBodyBlockOfTheRawCraigBamptonMassEqualsTheMassProperties) {
  // In the raw Craig-Bampton basis a rigid motion is the interface DOF moving rigidly with the
  // fixed-interface modal coordinates at zero; R_r^T M_r R_r must then be the rigid-body mass matrix.
  Component c = crank_throw();
  c.reduction.method = ReductionMethod::kCraigBampton;
  c.reduction.modes = 8;
  c.reduction.orthonormalize = false;
  const Superelement se = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
  const HandInertia h = hand_calculation(c);
  Eigen::MatrixXd Rr = Eigen::MatrixXd::Zero(se.size(), 6);
  const char* dof_names[6] = {"x", "y", "z", "rx", "ry", "rz"};
  for (int j = 0; j < se.size(); ++j) {
    const std::string& name = se.coordinates[j];
    for (std::size_t p = 0; p < se.interfaces.names.size(); ++p) {
      for (int d = 0; d < 6; ++d) {
        if (name != se.interfaces.names[p] + "." + dof_names[d]) continue;
        const Eigen::Vector3d x = se.interfaces.position.row(p).transpose();
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector3d rot_u = Eigen::Vector3d::Unit(k).cross(x);
          Rr(j, k) = d == k ? 1.0 : 0.0;
          Rr(j, 3 + k) = d < 3 ? rot_u(d) : (d - 3 == k ? 1.0 : 0.0);
        }
      }
    }
  }
  const Eigen::MatrixXd rigid = Rr.transpose() * se.mass * Rr;
  EXPECT_NEAR(rigid(0, 0) / h.m, 1.0, 1e-9);
  EXPECT_NEAR(rigid(1, 1) / h.m, 1.0, 1e-9);
  EXPECT_NEAR((rigid.bottomRightCorner(3, 3) - h.origin).norm() / h.origin.norm(), 0.0, 1e-9);
  // First moment: the (rotation, translation) block is m [c]x.
  const Eigen::Vector3d mc = h.first;
  EXPECT_NEAR(rigid(5, 1), mc.x(), 1e-9 * h.m);  // ([c]x)(2,1) = c_x
  EXPECT_NEAR(rigid(3, 2), mc.y(), 1e-9 * h.m);  // ([c]x)(0,2) = c_y
  EXPECT_NEAR(rigid(4, 0), mc.z(), 1e-9 * h.m);  // ([c]x)(1,0) = c_z
}

TEST(Invariants, ModalInvariantsAreConsistentWithEachOther) {
  // Two independent routes through the element integrals must agree:
  // - rotational coupling (from the rigid-rotation field) = eps_{ikl} I_tilde_kl (from position moments);
  // - translational coupling S_bar_k = int rho S_k dV = (1/m) ... checked via x_k -> constant: the
  //   position moments with the rigid translation give m c;
  // - the trace of the quadratic invariants, S_11 + S_22 + S_33 = basis^T M basis = reduced mass.
  // The raw Craig-Bampton basis contains rigid-body motion, so none of these vanish.
  Component c = crank_throw();
  c.reduction.method = ReductionMethod::kCraigBampton;
  c.reduction.orthonormalize = false;
  c.reduction.modes = 10;
  const Superelement se = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
  const ModalInvariants& inv = se.invariants;
  const int n = se.size();
  ASSERT_GT(inv.rotational.norm(), 1e-3);
  for (int i = 0; i < 3; ++i) {
    const int k = (i + 1) % 3, l = (i + 2) % 3;
    const Eigen::VectorXd from_position = inv.position[3 * k + l] - inv.position[3 * l + k];
    EXPECT_NEAR((from_position - inv.rotational.row(i).transpose()).norm(), 0.0,
                1e-10 * inv.rotational.norm())
        << "axis " << i;
  }
  const Eigen::MatrixXd trace = inv.quadratic[0] + inv.quadratic[4] + inv.quadratic[8];
  EXPECT_NEAR((trace - se.mass).norm(), 0.0, 1e-10 * n);
  // Symmetry: S_kl = S_lk^T.
  EXPECT_NEAR((inv.quadratic[1] - inv.quadratic[3].transpose()).norm(), 0.0, 1e-12);
}

TEST(Invariants, ElasticModesOfAFreeBodyCarryNoMomentum) {
  // Elastic modes are M-orthogonal to rigid-body motion: no net momentum and no net angular momentum
  // about the origin (the mean-axis conditions hold for a free-free modal basis).
  Component c = crank_throw();
  c.reduction.method = ReductionMethod::kModal;
  c.reduction.modes = 10;
  const Superelement se = condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
  EXPECT_NEAR(se.invariants.translational.norm(), 0.0, 1e-8);
  EXPECT_NEAR(se.invariants.rotational.norm(), 0.0, 1e-8);
}

TEST(Invariants, PositionMomentsReproduceTheSecondMoments) {
  // int rho x_k x_l dV from the position moments applied to the field u = x_k e_l... is not a DOF
  // field in general; but applied to a rigid translation e_l they give int rho x_k dV = m c_k.
  const Component c = crank_throw();
  const FeModel model = build_beam_model(c);
  const Eigen::MatrixXd R = model.rigid_body_field();
  const HandInertia h = hand_calculation(c);
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) {
      const double value = model.position_moment_all.col(3 * k + l).dot(R.col(l));
      EXPECT_NEAR(value, h.first(k), 1e-12 * h.m) << k << "," << l;
    }
}

}  // namespace
}  // namespace nvh::condense
