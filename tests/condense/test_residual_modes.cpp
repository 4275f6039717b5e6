// Residual (inertia-relief attachment) modes of a free-free modal reduction, against the full model.
//
// The component: a free-free steel round bar, L = 1 m, d = 30 mm, Timoshenko (kappa = 0.9), 40 elements,
// interface points at x = 0 ("a"), 0.5 ("mid") and 1 m ("b"): 18 interface DOF.
//
// The reference is the full finite-element model's static solution, computed here densely (Eigen LLT)
// and independently of the reduction: the free body is held at one statically determinate node (6 DOF at
// x = 0.25 m); the load is self-equilibrated (or balanced by inertia relief), so the holding node carries
// no reaction and any rigid-invariant measure of the deflection is that of the free body. The rigid part
// is removed M-orthogonally with the rigid-body field of the geometry (not with the eigen-solve's modes).
//
// The reduced model is used as solve uses the file: the superelement's K_r and interface shapes S_p
// (6 x n per point), q = K_r^-1 sum_p S_p^T f_p, u_p = S_p q.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cstdio>
#include <filesystem>

#include "beam_fixtures.hpp"
#include "common/log.hpp"
#include "common/provenance.hpp"
#include "condense/beam_model.hpp"
#include "condense/component_reader.hpp"
#include "condense/condense.hpp"

namespace nvh::condense {
namespace {

using namespace testing;

const Logger kQuiet{std::cerr, "test", Verbosity::kQuiet};

constexpr double kLength = 1.0;
constexpr int kElements = 40;

Component free_bar() {
  Component c = straight_beam(kLength, circle(0.03, 0.9), kElements);
  c.interfaces = {point("a", {0, 0, 0}), point("mid", {0.5, 0, 0}), point("b", {kLength, 0, 0})};
  c.reduction.method = ReductionMethod::kModal;
  c.reduction.modes = 6;
  return c;
}

/// A static load case: a force or moment component `dof` (0..5: x y z rx ry rz) at interface `point`.
struct PointLoad {
  int point;
  int dof;
  double value;
};

/// Nodal load vector (6N) of the loads at the interface nodes (node = x / (L / elements) on the bar).
Eigen::VectorXd nodal_load(const Component& c, const std::vector<PointLoad>& loads, int dofs) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(dofs);
  for (const PointLoad& l : loads) {
    const int node = static_cast<int>(std::lround(c.interfaces[l.point].at[0] / (kLength / kElements)));
    f(6 * node + l.dof) += l.value;
  }
  return f;
}

/// The full model's elastic static deflection (6N), M-orthogonal to the rigid-body motion.
/// `inertia_relief`: the load is first balanced by the d'Alembert forces of its rigid-body acceleration,
/// f <- f - M Phi_r Phi_r^T f (else it must be self-equilibrated already).
Eigen::VectorXd full_deflection(const Component& c, const std::vector<PointLoad>& loads,
                                bool inertia_relief) {
  const FeModel model = build_beam_model(c);
  EXPECT_EQ(model.free_dofs(), model.all_dofs());  // no supports or links: T = I
  const Eigen::MatrixXd K(model.stiffness()), M(model.mass());
  const int n = static_cast<int>(K.rows());
  // Rigid-body modes from the geometry, M-orthonormalized: Phi_r = R (R^T M R)^-1/2.
  const Eigen::MatrixXd R = model.rigid_body_field();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> g(R.transpose() * M * R);
  const Eigen::MatrixXd phi_r = R * g.operatorInverseSqrt();
  Eigen::VectorXd f = nodal_load(c, loads, n);
  const Eigen::VectorXd unbalanced = phi_r.transpose() * f;
  if (inertia_relief) {
    f -= M * phi_r * unbalanced;
  } else {
    EXPECT_LT(unbalanced.norm(), 1e-12) << "the load is not self-equilibrated";
  }
  // Held: the 6 DOF of the node at x = L/4 (statically determinate; no load there).
  const int held = kElements / 4;
  std::vector<int> keep;
  for (int d = 0; d < n; ++d)
    if (d / 6 != held) keep.push_back(d);
  const int nk = static_cast<int>(keep.size());
  Eigen::MatrixXd Kc(nk, nk);
  Eigen::VectorXd fc(nk);
  for (int i = 0; i < nk; ++i) {
    fc(i) = f(keep[i]);
    for (int j = 0; j < nk; ++j) Kc(i, j) = K(keep[i], keep[j]);
  }
  const Eigen::VectorXd uc = Kc.llt().solve(fc);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < nk; ++i) u(keep[i]) = uc(i);
  return u - phi_r * (phi_r.transpose() * (M * u));  // the elastic part
}

/// The reduced model's static deflection at the interfaces: 6 rows per interface point.
Eigen::VectorXd reduced_deflection(const Superelement& se, const std::vector<PointLoad>& loads) {
  Eigen::VectorXd generalized = Eigen::VectorXd::Zero(se.size());
  for (const PointLoad& l : loads)
    generalized += l.value * se.interfaces.shapes[l.point].row(l.dof).transpose();
  const Eigen::VectorXd q = se.stiffness.ldlt().solve(generalized);
  const int points = static_cast<int>(se.interfaces.names.size());
  Eigen::VectorXd u(6 * points);
  for (int p = 0; p < points; ++p) u.segment(6 * p, 6) = se.interfaces.shapes[p] * q;
  return u;
}

/// The full deflection at the interface nodes, in the layout of reduced_deflection.
Eigen::VectorXd at_interfaces(const Component& c, const Eigen::VectorXd& u) {
  Eigen::VectorXd out(6 * static_cast<int>(c.interfaces.size()));
  for (std::size_t p = 0; p < c.interfaces.size(); ++p) {
    const int node = static_cast<int>(std::lround(c.interfaces[p].at[0] / (kLength / kElements)));
    out.segment(6 * static_cast<int>(p), 6) = u.segment(6 * node, 6);
  }
  return out;
}

Superelement condensed(bool residual) {
  Component c = free_bar();
  c.reduction.residual_modes = residual;
  return condense_component(c, EigenBackend::kBlockLanczos, kQuiet);
}

// Three-point bending of the free bar: +1 N (y) at mid, -0.5 N at each end; self-equilibrated.
// delta = v_mid - (v_a + v_b) / 2 is rigid-invariant; for the Timoshenko beam the closed form of the
// simply supported span is delta = F L^3 / (48 EI) + F L / (4 kappa G A).
TEST(ResidualModes, ThreePointBendingMatchesTheFullModelAndTheClosedForm) {
  const Component c = free_bar();
  const std::vector<PointLoad> loads = {{1, 1, 1.0}, {0, 1, -0.5}, {2, 1, -0.5}};
  const Eigen::VectorXd full = at_interfaces(c, full_deflection(c, loads, false));
  auto delta = [](const Eigen::VectorXd& u) { return u(6 + 1) - 0.5 * (u(1) + u(12 + 1)); };
  const BeamSection s = circle(0.03, 0.9);
  const Steel steel;
  const double closed =
      std::pow(kLength, 3) / (48.0 * steel.E * s.Iz) + kLength / (4.0 * 0.9 * steel.G() * s.A);
  const double d_full = delta(full);
  const double d_with = delta(reduced_deflection(condensed(true), loads));
  const double d_without = delta(reduced_deflection(condensed(false), loads));
  std::printf(
      "[ three-point bending ] delta: closed form %.9e m, full %.9e m, residual modes %.9e m "
      "(rel. error %.2e), 6 modes only %.9e m (rel. error %.2e)\n",
      closed, d_full, d_with, d_with / d_full - 1.0, d_without, d_without / d_full - 1.0);
  EXPECT_NEAR(d_full / closed, 1.0, 1e-9);  // the FE model itself: Timoshenko elements are nodally exact
  EXPECT_NEAR(d_with / d_full, 1.0, 1e-6);
  EXPECT_GT(std::abs(d_without / d_full - 1.0), 1e-3);  // the truncation error of 6 free-free modes
}

// Unit loads at one interface point, balanced by inertia relief: every interface DOF of the reduced
// model (18 values) against the full model's elastic deflection, relative to the largest one.
TEST(ResidualModes, InertiaReliefDeflectionUnderUnitLoadsMatchesTheFullModel) {
  const Component c = free_bar();
  const Superelement with = condensed(true), without = condensed(false);
  const char* names[6] = {"Fx", "Fy", "Fz", "Mx", "My", "Mz"};
  const std::vector<PointLoad> cases = {{0, 1, 1.0}, {1, 2, 1.0}, {2, 0, 1.0}, {2, 3, 1.0}, {0, 5, 1.0}};
  for (const PointLoad& l : cases) {
    const Eigen::VectorXd full = at_interfaces(c, full_deflection(c, {l}, true));
    const double scale = full.cwiseAbs().maxCoeff();
    const double err_with = (reduced_deflection(with, {l}) - full).cwiseAbs().maxCoeff() / scale;
    const double err_without = (reduced_deflection(without, {l}) - full).cwiseAbs().maxCoeff() / scale;
    std::printf(
        "[ inertia relief ] unit %s at %s: max |u| %.3e, rel. error with residual modes %.2e, "
        "6 modes only %.2e\n",
        names[l.dof], c.interfaces[l.point].name.c_str(), scale, err_with, err_without);
    EXPECT_LT(err_with, 1e-6) << names[l.dof] << " at " << c.interfaces[l.point].name;
    EXPECT_GT(err_without, 1e-3) << names[l.dof] << " at " << c.interfaces[l.point].name;
  }
}

// The kept modes are untouched by the added vectors; the added coordinates lie above the band; the
// basis stays mass-orthonormal (checked on the nodal shapes through the quadratic invariants).
TEST(ResidualModes, KeepTheModesAndAddCoordinatesAboveTheBand) {
  const Superelement with = condensed(true), without = condensed(false);
  ASSERT_EQ(without.size(), 6);
  ASSERT_EQ(with.size(), 6 + 18);  // one per interface DOF: 3 points x 6
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(with.frequency_hz(i) / without.frequency_hz(i), 1.0, 1e-9) << "mode " << i + 1;
    EXPECT_EQ(with.coordinates[i], "mode " + std::to_string(i + 1));
  }
  std::printf("[ frequencies ] kept modes %.4f .. %.4f Hz; residual modes:", without.frequency_hz(0),
              without.frequency_hz(5));
  for (int i = 6; i < with.size(); ++i) {
    std::printf(" %.1f", with.frequency_hz(i));
    EXPECT_GT(with.frequency_hz(i), without.frequency_hz(5) * (1 + 1e-6));
    EXPECT_EQ(with.coordinates[i].rfind("residual mode ", 0), 0u) << with.coordinates[i];
    if (i > 6) {
      EXPECT_GE(with.frequency_hz(i), with.frequency_hz(i - 1));
    }
  }
  std::printf(" Hz\n");
  const int n = with.size();
  EXPECT_NEAR((with.mass - Eigen::MatrixXd::Identity(n, n)).norm(), 0.0, 1e-14);
  const Eigen::MatrixXd btmb =
      with.invariants.quadratic[0] + with.invariants.quadratic[4] + with.invariants.quadratic[8];
  EXPECT_NEAR((btmb - Eigen::MatrixXd::Identity(n, n)).norm(), 0.0, 1e-8);
  // K_r diagonal with the coordinates' own omega^2.
  const Eigen::VectorXd omega = 2.0 * kPi * with.frequency_hz;
  EXPECT_NEAR((with.stiffness - Eigen::MatrixXd(omega.cwiseProduct(omega).asDiagonal())).norm() /
                  with.stiffness.norm(),
              0.0, 1e-14);
  // The elastic coordinates carry no net momentum: the translational coupling vanishes (mean axes).
  EXPECT_LT(with.invariants.translational.cwiseAbs().maxCoeff(), 1e-8);
}

// The file: written through the contract and read back by common's reader (what solve opens).
TEST(ResidualModes, TheSuperelementFileReadsBack) {
  const Superelement se = condensed(true);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("nvh_residual_" + std::to_string(::getpid()) + ".h5");
  write_superelement(file, se, make_provenance("test", 0, nullptr, {}));
  const SuperelementFile back = read_superelement(file);
  std::filesystem::remove(file);
  EXPECT_EQ(back.method, "modal");
  EXPECT_TRUE(back.orthonormalized);
  ASSERT_EQ(back.size(), 24);
  EXPECT_EQ(back.coordinates.back(), "residual mode 18");
  EXPECT_NEAR((back.frequency_hz - se.frequency_hz).norm(), 0.0, 0.0);
}

// The key is read from the file and refused for the methods that keep the interface DOF.
TEST(ResidualModes, TheKeyIsReadAndRefusedOutsideModal) {
  const std::string text = R"(
[component]
name = "bar"
kind = "beam"
[material.steel]
E = 210e9
nu = 0.3
rho = 7850
[beam]
points = [[0, 0, 0], [1, 0, 0]]
material = "steel"
[[beam.section]]
segments = [1]
A = 7e-4
Iy = 4e-8
Iz = 4e-8
J = 8e-8
[[interface]]
name = "a"
at = [0, 0, 0]
[reduction]
method = "METHOD"
modes = 4
residual_modes = true
)";
  auto with_method = [&](const std::string& m) {
    std::string t = text;
    t.replace(t.find("METHOD"), 6, m);
    return t;
  };
  const Component modal = parse_component(with_method("modal"), "bar.toml");
  EXPECT_TRUE(modal.reduction.residual_modes);
  EXPECT_NO_THROW(check_reduction(modal));
  const Component cb = parse_component(with_method("craig-bampton"), "bar.toml");
  try {
    check_reduction(cb);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("residual_modes"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nvh::condense
