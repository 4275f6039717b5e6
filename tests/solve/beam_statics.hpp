#pragma once
// Static compliance of a beam superelement (condense's Craig-Bampton of a `kind = "beam"` component) against
// the stepped Timoshenko cantilever by the unit-load method, shared by the flexible rocker's and the flexible
// lever's tests (test_flexible_rocker.cpp, test_flexible_lever.cpp).
//
// Unit-load method (Castigliano; e.g. S. Timoshenko, J. Gere, Mechanics of Materials, deflections by energy
// methods): a straight beam along component x, clamped at x = 0, a unit load across it at x = L and the
// deflection wanted at x = P on the same side: over the segments a <= |x| <= b between the clamp and the
// nearer of the two points (moments M_L = L - |x|, M_P = P - |x|, unit shear in both),
//   delta = sum int_a^b (L - x)(P - x) dx / (E Iz) + (b - a) / (kappa G A)        (bending, shear)
// and along the beam sum (b - a) / (E A). Points on opposite sides of the clamp do not see each other's load.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "common/log.hpp"
#include "condense/component_reader.hpp"
#include "condense/condense.hpp"

namespace nvh::solve::beam_statics {

/// A beam section's properties (m^2, m^4; Cowper's shear factor kappa).
struct Section {
  double A, Iy, Iz, J, kappa;
};

/// A solid rectangle, h along y (in the plane of motion), b along z: J by Roark's Formulas 7th ed.
/// table 10.1, kappa by Cowper (J. Appl. Mech. 33, 1966, table 1) with nu = 0.3.
inline Section rectangle(double h, double b) {
  constexpr double nu = 0.3;
  const double a = std::max(h, b), c = std::min(h, b);
  return {h * b, h * b * b * b / 12, b * h * h * h / 12,
          a * c * c * c * (1.0 / 3 - 0.21 * c / a * (1 - std::pow(c / a, 4) / 12)),
          10 * (1 + nu) / (12 + 11 * nu)};
}

/// A component's beam sections against those from its comments' dimensions, segment by segment: its numbers
/// have 7 significant digits (1e-6), its shear factors 4 decimals.
inline void expect_sections(const condense::Component& c, const std::vector<Section>& expected) {
  ASSERT_EQ(c.beam.segment_sections.size(), expected.size());
  for (std::size_t s = 0; s < expected.size(); ++s) {
    const condense::BeamSection& got = c.beam.segment_sections[s];
    const Section& e = expected[s];
    SCOPED_TRACE("segment " + std::to_string(s + 1));
    EXPECT_NEAR(got.A, e.A, 1e-6 * e.A);
    EXPECT_NEAR(got.Iy, e.Iy, 1e-6 * e.Iy);
    EXPECT_NEAR(got.Iz, e.Iz, 1e-6 * e.Iz);
    EXPECT_NEAR(got.J, e.J, 1e-6 * e.J);
    ASSERT_TRUE(got.shear_factor.has_value());
    EXPECT_NEAR(*got.shear_factor, e.kappa, 5e-5);
  }
}

struct Compliance {
  double bending = 0, shear = 0, axial = 0;  // m/N
  double transverse() const { return bending + shear; }
};

/// The unit-load method above for the component's beam, clamped at x = 0: the deflection at x_point under a
/// unit load at x_load.
inline Compliance cantilever(const condense::Component& c, double x_load, double x_point) {
  Compliance out;
  if (x_load * x_point < 0) return out;
  const condense::Material& steel = c.materials.at(c.beam.material);
  const double E = steel.E, G = steel.shear_modulus(), L = std::abs(x_load), P = std::abs(x_point);
  const double reach = std::min(L, P);
  // int (L - x)(P - x) dx = L P x - (L + P) x^2 / 2 + x^3 / 3
  auto moment_product = [&](double x) { return L * P * x - (L + P) * x * x / 2 + x * x * x / 3; };
  for (std::size_t s = 0; s + 1 < c.beam.points.size(); ++s) {
    const double x0 = c.beam.points[s][0], x1 = c.beam.points[s + 1][0];
    if (x0 * x_load < 0 || x1 * x_load < 0) continue;  // the other side of the clamp
    const double a = std::min(std::abs(x0), std::abs(x1)),
                 b = std::min(std::max(std::abs(x0), std::abs(x1)), reach);
    if (b <= a) continue;
    const condense::BeamSection& sec = c.beam.segment_sections[s];
    out.bending += (moment_product(b) - moment_product(a)) / (E * sec.Iz);
    out.shear += (b - a) / (sec.shear_factor.value() * G * sec.A);
    out.axial += (b - a) / (E * sec.A);
  }
  return out;
}
inline Compliance cantilever(const condense::Component& c, double x_load) {
  return cantilever(c, x_load, x_load);
}

inline condense::Superelement condense_quietly(const condense::Component& c) {
  std::ostringstream quiet;
  const Logger log(quiet, "test", Verbosity::kQuiet);
  return condense::condense_component(c, condense::EigenBackend::kBlockLanczos, log);
}

/// Displacement [u; theta] of interface point p per unit of z = [a (3), phi (3), eta (n)]: the rigid motion
/// (translation a of the origin, small rotation phi: u = a + phi x r_p) the orthonormalized basis leaves to
/// the floating frame, and its elastic coordinates.
inline Eigen::MatrixXd point_map(const condense::Superelement& se, int p) {
  const int n = se.size();
  const Eigen::Vector3d r = se.interfaces.position.row(p).transpose();
  Eigen::Matrix3d rx;
  rx << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(6, 6 + n);
  b.block<3, 3>(0, 0).setIdentity();
  b.block<3, 3>(0, 3) = -rx;
  b.block<3, 3>(3, 3).setIdentity();
  b.rightCols(n) = se.interfaces.shapes[p];
  return b;
}

inline int point_index(const condense::Superelement& se, const std::string& name) {
  for (std::size_t k = 0; k < se.interfaces.names.size(); ++k)
    if (se.interfaces.names[k] == name) return static_cast<int>(k);
  ADD_FAILURE() << "no interface point " << name;
  return 0;
}

/// Displacement of `point` along component axis `dof` (0 x, 1 y) under a unit force along it at `load`, the
/// six DOF of `clamp` held: K z = B_load^T f with B_clamp z = 0 (Lagrange multipliers), K = diag(0 (rigid),
/// K_reduced).
inline double static_compliance(const condense::Superelement& se, const std::string& clamp,
                                const std::string& load, const std::string& point, int dof) {
  const int n = se.size(), m = 6 + n;
  const Eigen::MatrixXd bc = point_map(se, point_index(se, clamp)), bl = point_map(se, point_index(se, load)),
                        bq = point_map(se, point_index(se, point));
  Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(m + 6, m + 6);
  kkt.block(6, 6, n, n) = se.stiffness;
  kkt.block(m, 0, 6, m) = bc;
  kkt.block(0, m, m, 6) = bc.transpose();
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m + 6);
  rhs.head(m) = bl.row(dof).transpose();
  const Eigen::VectorXd z = kkt.fullPivLu().solve(rhs);
  return bq.row(dof).dot(z.head(m));
}

}  // namespace nvh::solve::beam_statics
