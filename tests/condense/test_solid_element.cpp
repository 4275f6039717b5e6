// The isoparametric solid elements (C3D4, C3D10, C3D8, C3D20) against closed forms.
//
// References (none computed with the code under test):
// - Node positions in natural coordinates: Abaqus Analysis User's Guide, "Three-dimensional solid
//   element library" (tables below typed from it).
// - Monomial integrals: over the unit tetrahedron int x^a y^b z^c = a! b! c! / (a + b + c + 3)!; over
//   [-1,1]^3 the product of int_{-1}^{1} x^a dx = 2 / (a + 1) (a even), 0 (a odd).
// - Volumes: tetrahedron det[x2 - x1, x3 - x1, x4 - x1] / 6; a square frustum h (a^2 + a b + b^2) / 3,
//   times det A under an affine map x -> A x + c.
// - C3D4 on the unit right tetrahedron: K = V B^T D B with B typed by hand (Zienkiewicz, Taylor and Zhu,
//   The Finite Element Method: Its Basis and Fundamentals, 7th ed., 2013, the constant-strain tetrahedron).
// - C3D8 on a cube: M = rho V / 216 [8 (self), 4 (edge neighbour), 2 (face diagonal), 1 (body diagonal)],
//   the tensor product of the 1D linear-element mass h/6 [2 1; 1 2].
// - C3D10 on a straight-sided tetrahedron: M = rho V / 420 x [corner-corner 6 (self) and 1; corner-mid
//   -4 (on an edge of the corner) and -6 (opposite); mid-mid 32 (self), 16 (sharing a corner), 8
//   (opposite edges)], from int L1^a L2^b L3^c L4^d dV = 6 V a! b! c! d! / (a + b + c + d + 3)! with
//   N_corner = L (2 L - 1) and N_mid = 4 L_i L_j (e.g. corner-corner self: 4/35 - 4/20 + 1/10 = 6/420).
//   Checked here a second time with a collapsed (Duffy) Gauss-Legendre product rule.
// - Patch test: a linear displacement u = A x + c has the constant strain eps(A); its strain energy is
//   V eps^T D eps / 2 exactly, rigid motions have none.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "condense/solid_element.hpp"

namespace nvh::condense {
namespace {

using Nodes = Eigen::Matrix<double, 3, Eigen::Dynamic>;

constexpr SolidType kAllTypes[] = {SolidType::kTet4, SolidType::kTet10, SolidType::kHex8, SolidType::kHex20};
const IsotropicMaterial kSteel{210e9, 0.3, 7850.0};

bool is_tet(SolidType t) {
  return t == SolidType::kTet4 || t == SolidType::kTet10;
}

/// Natural coordinates of the nodes, typed from the Abaqus manual's figures.
Nodes natural_nodes(SolidType type) {
  Nodes x(3, node_count(type));
  switch (type) {
    case SolidType::kTet4:
      x << 0, 1, 0, 0,  //
          0, 0, 1, 0,   //
          0, 0, 0, 1;
      break;
    case SolidType::kTet10:
      // 5: 1-2, 6: 2-3, 7: 3-1, 8: 1-4, 9: 2-4, 10: 3-4.
      x << 0, 1, 0, 0, 0.5, 0.5, 0, 0, 0.5, 0,  //
          0, 0, 1, 0, 0, 0.5, 0.5, 0, 0, 0.5,   //
          0, 0, 0, 1, 0, 0, 0, 0.5, 0.5, 0.5;
      break;
    case SolidType::kHex8:
      x << -1, 1, 1, -1, -1, 1, 1, -1,  //
          -1, -1, 1, 1, -1, -1, 1, 1,   //
          -1, -1, -1, -1, 1, 1, 1, 1;
      break;
    case SolidType::kHex20:
      // Corners, then 9: 1-2, 10: 2-3, 11: 3-4, 12: 4-1, 13: 5-6, 14: 6-7, 15: 7-8, 16: 8-5,
      // 17: 1-5, 18: 2-6, 19: 3-7, 20: 4-8.
      x << -1, 1, 1, -1, -1, 1, 1, -1, 0, 1, 0, -1, 0, 1, 0, -1, -1, 1, 1, -1,  //
          -1, -1, 1, 1, -1, -1, 1, 1, -1, 0, 1, 0, -1, 0, 1, 0, -1, -1, 1, 1,   //
          -1, -1, -1, -1, 1, 1, 1, 1, -1, -1, -1, -1, 1, 1, 1, 1, 0, 0, 0, 0;
      break;
  }
  return x;
}

/// Mid-edge nodes as pairs of corners (0-based), typed from the Abaqus manual.
std::vector<std::pair<int, int>> mid_edges(SolidType type) {
  if (type == SolidType::kTet10) return {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  if (type == SolidType::kHex20) {
    return {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  }
  return {};
}

/// A portable uniform number in [-1, 1) from a fixed-seed mt19937 (whose output sequence is specified).
struct Random {
  std::mt19937 gen{12345u};
  double operator()() { return 2.0 * (static_cast<double>(gen()) / 4294967296.0) - 1.0; }
};

/// Corners of a distorted element: tets an arbitrary tetrahedron; hexes the unit-ish box with every
/// corner moved by up to `wobble` (non-planar faces). Quadratic types get mid-edge nodes at the edge
/// midpoints plus up to `curve` of random offset (curved edges).
Nodes distorted(SolidType type, double wobble, double curve, Random& rnd) {
  const int corners = is_tet(type) ? 4 : 8;
  Nodes x(3, node_count(type));
  if (is_tet(type)) {
    x.leftCols(4) << 0.1, 1.3, 0.3, 0.2,  //
        0.05, 0.2, 0.9, 0.35,             //
        -0.02, 0.1, -0.1, 1.1;
  } else {
    const Nodes ref = natural_nodes(SolidType::kHex8);
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d scale(0.5, 0.4, 0.6);
      x.col(i) = scale.cwiseProduct(ref.col(i)) + Eigen::Vector3d(1.0, 2.0, 3.0);
    }
  }
  for (int i = 0; i < corners; ++i) {
    for (int k = 0; k < 3; ++k) x(k, i) += wobble * rnd();
  }
  const auto edges = mid_edges(type);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const int col = corners + static_cast<int>(e);
    x.col(col) = 0.5 * (x.col(edges[e].first) + x.col(edges[e].second));
    for (int k = 0; k < 3; ++k) x(k, col) += curve * rnd();
  }
  return x;
}

/// An affine image A xi + c of the natural element: straight-sided, constant Jacobian (tets) or a
/// parallelepiped (hexes). Returns the volume through `volume`: det A / 6 or 8 det A.
Nodes affine(SolidType type, const Eigen::Matrix3d& A, const Eigen::Vector3d& c, double* volume) {
  const Nodes ref = natural_nodes(type);
  Nodes x(3, ref.cols());
  for (int i = 0; i < ref.cols(); ++i) x.col(i) = A * ref.col(i) + c;
  *volume = A.determinant() * (is_tet(type) ? 1.0 / 6.0 : 8.0);
  return x;
}

/// An affinely mapped square frustum (bottom side a at z = 0, top side b at z = h): planar faces, so
/// the trilinear (and, with mid-edge nodes at midpoints, the serendipity) map reproduces it exactly.
Nodes frustum(SolidType type, double a, double b, double h, const Eigen::Matrix3d& A, double* volume) {
  Nodes x(3, node_count(type));
  const Nodes ref = natural_nodes(SolidType::kHex8);
  for (int i = 0; i < 8; ++i) {
    const double side = ref(2, i) < 0 ? a : b;
    const Eigen::Vector3d p(0.5 * side * ref(0, i), 0.5 * side * ref(1, i), ref(2, i) < 0 ? 0.0 : h);
    x.col(i) = A * p + Eigen::Vector3d(0.3, -0.2, 0.1);
  }
  const auto edges = mid_edges(type);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    x.col(8 + static_cast<int>(e)) = 0.5 * (x.col(edges[e].first) + x.col(edges[e].second));
  }
  *volume = A.determinant() * h * (a * a + a * b + b * b) / 3.0;
  return x;
}

/// A general, well-conditioned 3x3 matrix with positive determinant.
Eigen::Matrix3d shear_map() {
  Eigen::Matrix3d A;
  A << 1.1, 0.2, -0.15,  //
      0.1, 0.9, 0.25,    //
      -0.05, 0.3, 1.2;
  return A;
}

/// The isotropic D in Voigt notation (xx, yy, zz, gamma_xy, gamma_yz, gamma_zx), typed independently.
Eigen::Matrix<double, 6, 6> reference_D(const IsotropicMaterial& m) {
  const double c = m.E / ((1.0 + m.nu) * (1.0 - 2.0 * m.nu));
  const double d = c * (1.0 - m.nu), o = c * m.nu, g = m.E / (2.0 * (1.0 + m.nu));
  Eigen::Matrix<double, 6, 6> D;
  D << d, o, o, 0, 0, 0,  //
      o, d, o, 0, 0, 0,   //
      o, o, d, 0, 0, 0,   //
      0, 0, 0, g, 0, 0,   //
      0, 0, 0, 0, g, 0,   //
      0, 0, 0, 0, 0, g;
  return D;
}

/// Gauss-Legendre nodes and weights on [-1, 1] by Newton's method on P_n (independent of the library).
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(n, 0.0);
  w.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    double t = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
    double dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = t;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * t * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (t * p1 - p0) / (t * t - 1.0);
      const double dt = p1 / dp;
      t -= dt;
      if (std::abs(dt) < 1e-16) break;
    }
    x[i] = t;
    w[i] = 2.0 / ((1.0 - t * t) * dp * dp);
  }
}

double factorial(int n) {
  return n <= 1 ? 1.0 : n * factorial(n - 1);
}

// ------------------------------------------------------------------------------------------------

TEST(SolidElement, NamesAndNodeCounts) {
  EXPECT_EQ(node_count(SolidType::kTet4), 4);
  EXPECT_EQ(node_count(SolidType::kTet10), 10);
  EXPECT_EQ(node_count(SolidType::kHex8), 8);
  EXPECT_EQ(node_count(SolidType::kHex20), 20);
  for (SolidType t : kAllTypes) EXPECT_EQ(parse_solid_type(to_string(t)), t);
  EXPECT_EQ(to_string(SolidType::kTet10), "C3D10");
  EXPECT_EQ(parse_solid_type("c3d20"), SolidType::kHex20);
  EXPECT_EQ(parse_solid_type(" C3D8"), SolidType::kHex8);
  for (const std::string bad : {"C3D8R", "C3D20R"}) {
    try {
      parse_solid_type(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("reduced integration"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("C3D4, C3D10, C3D8 and C3D20"), std::string::npos) << e.what();
    }
  }
  for (const std::string bad : {"C3D6", "C3D10M", "C3D8I", "S4", ""}) {
    try {
      parse_solid_type(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("C3D4, C3D10, C3D8 and C3D20"), std::string::npos) << e.what();
    }
  }
}

TEST(SolidElement, ShapeFunctionsInterpolateAndSumToOne) {
  Random rnd;
  for (SolidType t : kAllTypes) {
    SCOPED_TRACE(to_string(t));
    const Nodes xi_nodes = natural_nodes(t);
    const int n = node_count(t);
    Eigen::VectorXd N;
    Eigen::MatrixXd dN;
    double max_err = 0.0;
    for (int j = 0; j < n; ++j) {
      shape_functions(t, xi_nodes.col(j), N, dN);
      ASSERT_EQ(N.size(), n);
      ASSERT_EQ(dN.rows(), n);
      ASSERT_EQ(dN.cols(), 3);
      max_err = std::max(max_err, (N - Eigen::VectorXd::Unit(n, j)).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(max_err, 1e-15);
    // Inside: partition of unity, derivatives sum to zero, linear completeness sum N_i xi_i = xi, and
    // dN/dxi against central differences.
    double pu = 0.0, lin = 0.0, fd = 0.0;
    for (int s = 0; s < 20; ++s) {
      Eigen::Vector3d xi(rnd(), rnd(), rnd());
      if (is_tet(t)) xi = 0.25 * (xi.array() + 1.0);  // in [0, 0.5)^3 (identities hold anywhere)
      shape_functions(t, xi, N, dN);
      pu = std::max(pu, std::abs(N.sum() - 1.0));
      pu = std::max(pu, dN.colwise().sum().cwiseAbs().maxCoeff());
      lin = std::max(lin, (xi_nodes * N - xi).cwiseAbs().maxCoeff());
      lin = std::max(lin, (xi_nodes * dN - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff());
      const double h = 1e-6;
      for (int k = 0; k < 3; ++k) {
        Eigen::VectorXd Np, Nm;
        Eigen::MatrixXd dummy;
        shape_functions(t, xi + h * Eigen::Vector3d::Unit(k), Np, dummy);
        shape_functions(t, xi - h * Eigen::Vector3d::Unit(k), Nm, dummy);
        fd = std::max(fd, ((Np - Nm) / (2.0 * h) - dN.col(k)).cwiseAbs().maxCoeff());
      }
    }
    EXPECT_LT(pu, 1e-14);
    EXPECT_LT(lin, 1e-14);
    EXPECT_LT(fd, 1e-8);
    std::printf(
        "[ measured ] %-5s N_i(x_j) - delta_ij %.1e, partition of unity %.1e, linear %.1e, dN vs FD %.1e\n",
        to_string(t).c_str(), max_err, pu, lin, fd);
  }
}

TEST(SolidElement, QuadratureRulesIntegrateMonomialsExactly) {
  for (SolidType t : kAllTypes) {
    for (Integrand what : {Integrand::kStiffness, Integrand::kMass}) {
      const QuadratureRule& r = quadrature_rule(t, what);
      SCOPED_TRACE(to_string(t) + (what == Integrand::kMass ? " mass" : " stiffness"));
      ASSERT_EQ(r.points.size(), r.weights.size());
      const int p = r.degree;
      auto integrate = [&](int a, int b, int c) {
        double s = 0.0;
        for (std::size_t q = 0; q < r.points.size(); ++q) {
          const Eigen::Vector3d& x = r.points[q];
          s += r.weights[q] * std::pow(x(0), a) * std::pow(x(1), b) * std::pow(x(2), c);
        }
        return s;
      };
      double max_err = 0.0;
      if (is_tet(t)) {
        for (const Eigen::Vector3d& x : r.points) {
          EXPECT_GE(x.minCoeff(), 0.0);
          EXPECT_LE(x.sum(), 1.0);
        }
        auto exact = [](int a, int b, int c) {
          return factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3);
        };
        for (int a = 0; a <= p; ++a)
          for (int b = 0; a + b <= p; ++b)
            for (int c = 0; a + b + c <= p; ++c)
              max_err = std::max(max_err, std::abs(integrate(a, b, c) - exact(a, b, c)));
        // Not exact one degree higher: the stated degree is the real one.
        double above = 0.0;
        for (int a = 0; a <= p + 1; ++a)
          for (int b = 0; a + b <= p + 1; ++b) {
            const int c = p + 1 - a - b;
            above = std::max(above, std::abs(integrate(a, b, c) - exact(a, b, c)));
          }
        EXPECT_GT(above, 1e-7);
      } else {
        auto exact1 = [](int a) { return a % 2 ? 0.0 : 2.0 / (a + 1); };
        for (int a = 0; a <= p; ++a)
          for (int b = 0; b <= p; ++b)
            for (int c = 0; c <= p; ++c)
              max_err = std::max(max_err, std::abs(integrate(a, b, c) - exact1(a) * exact1(b) * exact1(c)));
        EXPECT_GT(std::abs(integrate(p + 1, 0, 0) - exact1(p + 1) * 4.0), 1e-6);
      }
      EXPECT_LT(max_err, 1e-14);  // integrals up to 8 (hexes)
      std::printf("[ measured ] %-5s %-9s rule: %2zu points, degree %d, max monomial error %.1e\n",
                  to_string(t).c_str(), what == Integrand::kMass ? "mass" : "stiffness", r.points.size(), p,
                  max_err);
    }
  }
  EXPECT_EQ(quadrature_rule(SolidType::kTet4, Integrand::kStiffness).points.size(), 1u);
  EXPECT_EQ(quadrature_rule(SolidType::kTet4, Integrand::kMass).points.size(), 4u);
  EXPECT_EQ(quadrature_rule(SolidType::kTet10, Integrand::kStiffness).points.size(), 4u);
  EXPECT_EQ(quadrature_rule(SolidType::kTet10, Integrand::kMass).points.size(), 14u);
  EXPECT_GE(quadrature_rule(SolidType::kTet10, Integrand::kMass).degree, 4);
  EXPECT_EQ(quadrature_rule(SolidType::kHex8, Integrand::kStiffness).points.size(), 8u);
  EXPECT_EQ(quadrature_rule(SolidType::kHex20, Integrand::kMass).points.size(), 27u);
}

TEST(SolidElement, MassAndVolumeOfDistortedElements) {
  const double rho = kSteel.rho;
  struct Case {
    SolidType type;
    Nodes x;
    double volume;
    std::string what;
  };
  std::vector<Case> cases;
  for (SolidType t : kAllTypes) {
    double v = 0.0;
    Nodes x = affine(t, 0.3 * shear_map(), Eigen::Vector3d(1, -2, 0.5), &v);
    cases.push_back({t, x, v, "affine"});
    if (!is_tet(t)) {
      x = frustum(t, 0.4, 0.25, 0.3, shear_map(), &v);
      cases.push_back({t, x, v, "frustum"});
    }
  }
  for (const Case& c : cases) {
    SCOPED_TRACE(to_string(c.type) + " " + c.what);
    const SolidElementMatrices m = solid_element(c.type, c.x, kSteel);
    const double err_v = std::abs(m.volume - c.volume) / c.volume;
    const double err_m = std::abs(m.scalar_mass.sum() - rho * c.volume) / (rho * c.volume);
    EXPECT_LT(err_v, 1e-14);
    EXPECT_LT(err_m, 1e-14);
    EXPECT_LT((m.scalar_mass - m.scalar_mass.transpose()).cwiseAbs().maxCoeff(),
              1e-14 * m.scalar_mass.norm());
    std::printf("[ measured ] %-5s %-7s rel. error volume %.1e, total mass %.1e\n", to_string(c.type).c_str(),
                c.what.c_str(), err_v, err_m);
  }
}

TEST(SolidElement, StiffnessHasExactlySixRigidBodyModes) {
  Random rnd;
  for (SolidType t : kAllTypes) {
    for (double curve : {0.0, 0.05}) {
      if (curve > 0.0 && (t == SolidType::kTet4 || t == SolidType::kHex8)) continue;
      SCOPED_TRACE(to_string(t) + (curve > 0 ? " curved" : " straight"));
      const Nodes x = distorted(t, 0.08, curve, rnd);
      const SolidElementMatrices m = solid_element(t, x, kSteel);
      const Eigen::MatrixXd& K = m.stiffness;
      EXPECT_LT((K - K.transpose()).cwiseAbs().maxCoeff(), 1e-14 * K.cwiseAbs().maxCoeff());
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(K);
      const Eigen::VectorXd lambda = eig.eigenvalues();  // ascending
      const double lmax = lambda.maxCoeff();
      const double zero = lambda.head(6).cwiseAbs().maxCoeff() / lmax;
      const double first = lambda(6) / lmax;
      EXPECT_LT(zero, 1e-12);
      EXPECT_GT(first, 1e-4);
      // The rigid motions u = c + omega x X are in the null space.
      const int n = node_count(t);
      double rigid = 0.0;
      for (int k = 0; k < 6; ++k) {
        Eigen::VectorXd u(3 * n);
        for (int a = 0; a < n; ++a) {
          const Eigen::Vector3d X = x.col(a);
          u.segment<3>(3 * a) = k < 3 ? Eigen::Vector3d::Unit(k) : Eigen::Vector3d::Unit(k - 3).cross(X);
        }
        rigid = std::max(rigid, (K * u).norm() / (lmax * u.norm()));
      }
      EXPECT_LT(rigid, 1e-13);
      std::printf(
          "[ measured ] %-5s %-8s |lambda_1..6|/lambda_max %.1e, lambda_7/lambda_max %.2e, |K u_rigid| "
          "%.1e\n",
          to_string(t).c_str(), curve > 0 ? "curved" : "straight", zero, first, rigid);
    }
  }
}

TEST(SolidElement, PatchTestLinearFieldStrainEnergy) {
  Random rnd;
  const Eigen::Matrix<double, 6, 6> D = reference_D(kSteel);
  for (SolidType t : kAllTypes) {
    std::vector<std::pair<Nodes, double>> shapes;
    double v = 0.0;
    Nodes x = affine(t, 0.3 * shear_map(), Eigen::Vector3d(1, -2, 0.5), &v);
    shapes.emplace_back(x, v);
    if (!is_tet(t)) {
      x = frustum(t, 0.4, 0.25, 0.3, shear_map(), &v);
      shapes.emplace_back(x, v);
    }
    if (!is_tet(t)) {
      // Non-planar faces (and curved edges): no closed-form volume, but the same rule integrates the
      // stiffness and the volume, so the patch test still holds to round-off with the element's volume.
      Random shape_rnd;
      x = distorted(t, 0.08, t == SolidType::kHex20 ? 0.05 : 0.0, shape_rnd);
      shapes.emplace_back(x, solid_element(t, x, kSteel).volume);
    }
    for (const auto& [nodes, volume] : shapes) {
      SCOPED_TRACE(to_string(t));
      const SolidElementMatrices m = solid_element(t, nodes, kSteel);
      double max_err = 0.0;
      for (int trial = 0; trial < 5; ++trial) {
        Eigen::Matrix3d A;
        for (int i = 0; i < 9; ++i) A(i) = 1e-3 * rnd();
        const Eigen::Vector3d c = 1e-3 * Eigen::Vector3d(rnd(), rnd(), rnd());
        Eigen::VectorXd u(3 * nodes.cols());
        for (int a = 0; a < nodes.cols(); ++a) u.segment<3>(3 * a) = A * nodes.col(a) + c;
        Eigen::Matrix<double, 6, 1> eps;
        eps << A(0, 0), A(1, 1), A(2, 2), A(0, 1) + A(1, 0), A(1, 2) + A(2, 1), A(2, 0) + A(0, 2);
        const double energy = 0.5 * u.dot(m.stiffness * u);
        const double reference = 0.5 * volume * eps.dot(D * eps);
        max_err = std::max(max_err, std::abs(energy - reference) / reference);
      }
      EXPECT_LT(max_err, 1e-12);
      std::printf("[ measured ] %-5s patch test: rel. error of u^T K u / 2 vs V eps^T D eps / 2: %.1e\n",
                  to_string(t).c_str(), max_err);
    }
  }
}

TEST(SolidElement, Tet4StiffnessOfUnitRightTetrahedron) {
  Nodes x(3, 4);
  x << 0, 1, 0, 0,  //
      0, 0, 1, 0,   //
      0, 0, 0, 1;
  // dN/dx of N1 = 1 - x - y - z, N2 = x, N3 = y, N4 = z: (-1,-1,-1), (1,0,0), (0,1,0), (0,0,1).
  Eigen::Matrix<double, 6, 12> B;
  B << -1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0,  // e_xx
      0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0,   // e_yy
      0, 0, -1, 0, 0, 0, 0, 0, 0, 0, 0, 1,   // e_zz
      -1, -1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 0,  // gamma_xy = du/dy + dv/dx
      0, -1, -1, 0, 0, 0, 0, 0, 1, 0, 1, 0,  // gamma_yz = dv/dz + dw/dy
      -1, 0, -1, 0, 0, 1, 0, 0, 0, 1, 0, 0;  // gamma_zx = dw/dx + du/dz
  const Eigen::MatrixXd K_ref = (1.0 / 6.0) * B.transpose() * reference_D(kSteel) * B;
  const SolidElementMatrices m = solid_element(SolidType::kTet4, x, kSteel);
  const double err = (m.stiffness - K_ref).cwiseAbs().maxCoeff() / K_ref.cwiseAbs().maxCoeff();
  EXPECT_LT(err, 1e-15);
  EXPECT_NEAR(m.volume, 1.0 / 6.0, 1e-16);
  // Tet4 mass: rho V / 20 (2 on the diagonal, 1 off it).
  Eigen::Matrix4d M_ref = Eigen::Matrix4d::Constant(1.0) + Eigen::Matrix4d::Identity();
  M_ref *= kSteel.rho / 6.0 / 20.0;
  const double err_m = (m.scalar_mass - M_ref).cwiseAbs().maxCoeff() / M_ref.maxCoeff();
  EXPECT_LT(err_m, 1e-14);
  std::printf("[ measured ] C3D4 unit tet: rel. error K vs V B^T D B %.1e, M vs rho V/20 [2 1] %.1e\n", err,
              err_m);
}

TEST(SolidElement, Hex8CubeConsistentMass) {
  const double a = 0.5;  // side, m
  double v = 0.0;
  const Nodes x =
      affine(SolidType::kHex8, 0.5 * a * Eigen::Matrix3d::Identity(), Eigen::Vector3d(2, 1, -1), &v);
  ASSERT_NEAR(v, a * a * a, 1e-15);
  const SolidElementMatrices m = solid_element(SolidType::kHex8, x, kSteel);
  const Nodes xi = natural_nodes(SolidType::kHex8);
  const double weight[4] = {8.0, 4.0, 2.0, 1.0};  // by the number of differing natural coordinates
  double err = 0.0;
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j) {
      const int d = static_cast<int>((xi.col(i) - xi.col(j)).cwiseAbs().cast<bool>().count());
      const double ref = kSteel.rho * v / 216.0 * weight[d];
      err = std::max(err, std::abs(m.scalar_mass(i, j) - ref) / ref);
    }
  }
  EXPECT_LT(err, 1e-14);
  std::printf("[ measured ] C3D8 cube mass vs rho V/216 [8 4 2 1]: max rel. error %.1e\n", err);
}

/// int over the reference tetrahedron by the collapsed (Duffy) map of [0,1]^3: xi = u,
/// eta = (1 - u) v, zeta = (1 - u)(1 - v) w, dxi deta dzeta = (1 - u)^2 (1 - v) du dv dw, with n-point
/// Gauss-Legendre in each direction.
template <class F>
Eigen::MatrixXd duffy_integral(int n, F f) {
  std::vector<double> g, w;
  gauss_legendre(n, g, w);
  Eigen::MatrixXd sum;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const double u = 0.5 * (g[i] + 1), v = 0.5 * (g[j] + 1), s = 0.5 * (g[k] + 1);
        const double jac = (1 - u) * (1 - u) * (1 - v) * 0.125 * w[i] * w[j] * w[k];
        const Eigen::MatrixXd val = jac * f(Eigen::Vector3d(u, (1 - u) * v, (1 - u) * (1 - v) * s));
        if (sum.size() == 0) {
          sum = val;
        } else {
          sum += val;
        }
      }
  return sum;
}

TEST(SolidElement, Tet10ConsistentMassOfStraightTetrahedron) {
  // A general straight-sided tetrahedron of unit volume: det[x2 - x1, x3 - x1, x4 - x1] = 6.
  Nodes x(3, 10);
  x.leftCols(4) << 0.2, 2.2, 0.7, 0.5,  //
      -0.1, -0.1, 1.4, 0.3,             //
      0.3, 0.3, 0.3, 2.3;
  const auto edges = mid_edges(SolidType::kTet10);
  for (int e = 0; e < 6; ++e) x.col(4 + e) = 0.5 * (x.col(edges[e].first) + x.col(edges[e].second));
  const double V = 1.0;
  const SolidElementMatrices m = solid_element(SolidType::kTet10, x, kSteel);
  EXPECT_NEAR(m.volume, V, 1e-14);

  // The closed form, rho V / 420 x pattern.
  Eigen::MatrixXd M_ref(10, 10);
  auto on_edge = [&](int corner, int e) { return edges[e].first == corner || edges[e].second == corner; };
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j) {
      double p = 0.0;
      if (i < 4 && j < 4) {
        p = i == j ? 6.0 : 1.0;
      } else if (i < 4 || j < 4) {
        const int c = std::min(i, j), e = std::max(i, j) - 4;
        p = on_edge(c, e) ? -4.0 : -6.0;
      } else {
        const int e = i - 4, f = j - 4;
        const bool share = on_edge(edges[e].first, f) || on_edge(edges[e].second, f);
        p = e == f ? 32.0 : (share ? 16.0 : 8.0);
      }
      M_ref(i, j) = kSteel.rho * V / 420.0 * p;
    }
  }
  EXPECT_NEAR(M_ref.sum(), kSteel.rho * V, 1e-12 * kSteel.rho);
  const double err = (m.scalar_mass - M_ref).cwiseAbs().maxCoeff() / M_ref.cwiseAbs().maxCoeff();
  EXPECT_LT(err, 1e-14);

  // Independently: the shape-function products by a 6x6x6 collapsed Gauss rule (exact to degree 11 in
  // each direction), times det J = 6 V.
  const Eigen::MatrixXd M_duffy = duffy_integral(6,
                                                 [](const Eigen::Vector3d& xi) -> Eigen::MatrixXd {
                                                   Eigen::VectorXd N;
                                                   Eigen::MatrixXd dN;
                                                   shape_functions(SolidType::kTet10, xi, N, dN);
                                                   return N * N.transpose();
                                                 }) *
                                  (kSteel.rho * 6.0 * V);
  const double err_duffy = (M_duffy - M_ref).cwiseAbs().maxCoeff() / M_ref.cwiseAbs().maxCoeff();
  EXPECT_LT(err_duffy, 1e-13);
  std::printf("[ measured ] C3D10 mass vs rho V/420 pattern: %.1e; Duffy 6^3 rule vs pattern: %.1e\n", err,
              err_duffy);
}

TEST(SolidElement, Hex20MassAndStiffnessAgainstHigherOrderGauss) {
  // On a parallelepiped 3x3x3 Gauss is exact for both matrices; compare with 5x5x5 computed here.
  double v = 0.0;
  const Nodes x = affine(SolidType::kHex20, 0.25 * shear_map(), Eigen::Vector3d(0, 0, 1), &v);
  const SolidElementMatrices m = solid_element(SolidType::kHex20, x, kSteel);
  std::vector<double> g, w;
  gauss_legendre(5, g, w);
  const Eigen::Matrix<double, 6, 6> D = reference_D(kSteel);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(20, 20), K = Eigen::MatrixXd::Zero(60, 60);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k) {
        Eigen::VectorXd N;
        Eigen::MatrixXd dN;
        shape_functions(SolidType::kHex20, Eigen::Vector3d(g[i], g[j], g[k]), N, dN);
        const Eigen::Matrix3d J = x * dN;
        const double dV = w[i] * w[j] * w[k] * J.determinant();
        M += kSteel.rho * dV * N * N.transpose();
        const Eigen::MatrixXd dx = dN * J.inverse();
        Eigen::MatrixXd B = Eigen::MatrixXd::Zero(6, 60);
        for (int a = 0; a < 20; ++a) {
          B(0, 3 * a) = B(3, 3 * a + 1) = B(5, 3 * a + 2) = dx(a, 0);
          B(1, 3 * a + 1) = B(3, 3 * a) = B(4, 3 * a + 2) = dx(a, 1);
          B(2, 3 * a + 2) = B(4, 3 * a + 1) = B(5, 3 * a) = dx(a, 2);
        }
        K += dV * B.transpose() * D * B;
      }
  const double err_m = (m.scalar_mass - M).cwiseAbs().maxCoeff() / M.cwiseAbs().maxCoeff();
  const double err_k = (m.stiffness - K).cwiseAbs().maxCoeff() / K.cwiseAbs().maxCoeff();
  EXPECT_LT(err_m, 1e-13);
  EXPECT_LT(err_k, 1e-13);
  // Row sums int rho N_i dV: -rho V / 8 at the corners and rho V / 6 at the mid-edge nodes (the known
  // negative corner "masses" of the serendipity element; int over [-1,1]^3 of its N_i = -1 and 4/3).
  double err_rows = 0.0;
  for (int a = 0; a < 20; ++a) {
    const double ref = kSteel.rho * v * (a < 8 ? -1.0 / 8.0 : 1.0 / 6.0);
    err_rows = std::max(err_rows, std::abs(m.scalar_mass.row(a).sum() - ref) / std::abs(ref));
  }
  EXPECT_LT(err_rows, 1e-13);
  std::printf("[ measured ] C3D20 parallelepiped vs 5x5x5 Gauss: mass %.1e, stiffness %.1e; row sums %.1e\n",
              err_m, err_k, err_rows);
}

TEST(SolidElement, InvertedElementIsAnError) {
  Random rnd;
  for (SolidType t : kAllTypes) {
    SCOPED_TRACE(to_string(t));
    Nodes x = distorted(t, 0.0, 0.0, rnd);
    EXPECT_NO_THROW(solid_element(t, x, kSteel));
    if (is_tet(t)) {
      x.col(1).swap(x.col(2));  // mirrored: det J < 0 everywhere (C3D10: mid-edge nodes now misplaced too)
    } else {
      // Faces zeta = -1 and +1 swapped (corners 1-4 <-> 5-8, mid-edge 9-12 <-> 13-16): mirrored.
      for (int i = 0; i < 4; ++i) x.col(i).swap(x.col(i + 4));
      if (t == SolidType::kHex20) {
        for (int i = 8; i < 12; ++i) x.col(i).swap(x.col(i + 4));
      }
    }
    try {
      solid_element(t, x, kSteel);
      ADD_FAILURE() << "inverted element accepted";
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("inverted"), std::string::npos) << msg;
      EXPECT_NE(msg.find("min det J"), std::string::npos) << msg;
      EXPECT_NE(msg.find(to_string(t)), std::string::npos) << msg;
      if (t == SolidType::kHex20) std::printf("[ message  ] %s\n", msg.c_str());
    }
  }
  // Two adjacent corners of a hex swapped: a bow-tie, det J < 0 at some points only.
  Nodes x = distorted(SolidType::kHex8, 0.0, 0.0, rnd);
  x.col(0).swap(x.col(1));
  EXPECT_THROW(solid_element(SolidType::kHex8, x, kSteel), Error);
  // A flat tetrahedron is degenerate.
  Nodes flat(3, 4);
  flat << 0, 1, 0, 1,  //
      0, 0, 1, 1,      //
      0, 0, 0, 0;
  EXPECT_THROW(solid_element(SolidType::kTet4, flat, kSteel), Error);
}

TEST(SolidElement, BadInputIsAnError) {
  Random rnd;
  const Nodes x = distorted(SolidType::kHex8, 0.0, 0.0, rnd);
  EXPECT_THROW(solid_element(SolidType::kHex20, x, kSteel), Error);  // 8 nodes for a C3D20
  EXPECT_THROW(solid_element(SolidType::kHex8, x, {-1.0, 0.3, 1.0}), Error);
  EXPECT_THROW(solid_element(SolidType::kHex8, x, {1.0, 0.5, 1.0}), Error);
  EXPECT_THROW(solid_element(SolidType::kHex8, x, {1.0, 0.3, -1.0}), Error);
}

}  // namespace
}  // namespace nvh::condense
