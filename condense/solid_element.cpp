#include "condense/solid_element.hpp"

#include <Eigen/LU>
#include <array>
#include <cctype>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "common/error.hpp"

namespace nvh::condense {
namespace {

// ---------------------------------------------------------------------------------------------------
// Reference elements and shape functions (Zienkiewicz, Taylor and Zhu 2013, standard shape functions).
// ---------------------------------------------------------------------------------------------------

/// The tetrahedra's mid-edge nodes as pairs of 0-based corners: C3D10 nodes 5..10 on edges 1-2, 2-3,
/// 3-1, 1-4, 2-4, 3-4 (Abaqus/CalculiX numbering).
constexpr int kTetEdges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};

/// Natural coordinates of the C3D20 nodes (C3D8: the first 8): corners 1-4 on zeta = -1 and 5-8 on
/// zeta = +1, then mid-edge nodes 9-12 (edges 1-2, 2-3, 3-4, 4-1), 13-16 (5-6, 6-7, 7-8, 8-5) and
/// 17-20 (1-5, 2-6, 3-7, 4-8).
constexpr double kHexNodes[20][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},  // 1-4
                                     {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1},   // 5-8
                                     {0, -1, -1},  {1, 0, -1},  {0, 1, -1}, {-1, 0, -1},  // 9-12
                                     {0, -1, 1},   {1, 0, 1},   {0, 1, 1},  {-1, 0, 1},   // 13-16
                                     {-1, -1, 0},  {1, -1, 0},  {1, 1, 0},  {-1, 1, 0}};  // 17-20

/// Volume coordinates L1..L4 and their (constant) derivatives with respect to (xi, eta, zeta).
void volume_coordinates(const Eigen::Vector3d& xi, Eigen::Vector4d& L, Eigen::Matrix<double, 4, 3>& dL) {
  L << 1.0 - xi.sum(), xi(0), xi(1), xi(2);
  dL << -1, -1, -1,  //
      1, 0, 0,       //
      0, 1, 0,       //
      0, 0, 1;
}

/// C3D4: N_i = L_i.
void tet4_shape(const Eigen::Vector3d& xi, Eigen::VectorXd& N, Eigen::MatrixXd& dN) {
  Eigen::Vector4d L;
  Eigen::Matrix<double, 4, 3> dL;
  volume_coordinates(xi, L, dL);
  N = L;
  dN = dL;
}

/// C3D10: corners N_i = L_i (2 L_i - 1), mid-edge nodes N_ij = 4 L_i L_j.
void tet10_shape(const Eigen::Vector3d& xi, Eigen::VectorXd& N, Eigen::MatrixXd& dN) {
  Eigen::Vector4d L;
  Eigen::Matrix<double, 4, 3> dL;
  volume_coordinates(xi, L, dL);
  N.resize(10);
  dN.resize(10, 3);
  for (int i = 0; i < 4; ++i) {
    N(i) = L(i) * (2.0 * L(i) - 1.0);
    dN.row(i) = (4.0 * L(i) - 1.0) * dL.row(i);
  }
  for (int e = 0; e < 6; ++e) {
    const int a = kTetEdges[e][0], b = kTetEdges[e][1];
    N(4 + e) = 4.0 * L(a) * L(b);
    dN.row(4 + e) = 4.0 * (L(b) * dL.row(a) + L(a) * dL.row(b));
  }
}

/// C3D8: N_i = (1 + xi xi_i)(1 + eta eta_i)(1 + zeta zeta_i) / 8.
void hex8_shape(const Eigen::Vector3d& xi, Eigen::VectorXd& N, Eigen::MatrixXd& dN) {
  N.resize(8);
  dN.resize(8, 3);
  for (int i = 0; i < 8; ++i) {
    const double* c = kHexNodes[i];
    const double f[3] = {1.0 + xi(0) * c[0], 1.0 + xi(1) * c[1], 1.0 + xi(2) * c[2]};
    N(i) = 0.125 * f[0] * f[1] * f[2];
    dN(i, 0) = 0.125 * c[0] * f[1] * f[2];
    dN(i, 1) = 0.125 * f[0] * c[1] * f[2];
    dN(i, 2) = 0.125 * f[0] * f[1] * c[2];
  }
}

/// C3D20 (serendipity): corners N_i = (1 + xi xi_i)(1 + eta eta_i)(1 + zeta zeta_i)
/// (xi xi_i + eta eta_i + zeta zeta_i - 2) / 8; a mid-edge node with xi_i = 0 has
/// N_i = (1 - xi^2)(1 + eta eta_i)(1 + zeta zeta_i) / 4, and likewise for eta_i = 0 or zeta_i = 0.
void hex20_shape(const Eigen::Vector3d& xi, Eigen::VectorXd& N, Eigen::MatrixXd& dN) {
  N.resize(20);
  dN.resize(20, 3);
  for (int i = 0; i < 8; ++i) {
    const double* c = kHexNodes[i];
    const double f[3] = {1.0 + xi(0) * c[0], 1.0 + xi(1) * c[1], 1.0 + xi(2) * c[2]};
    const double s = xi(0) * c[0] + xi(1) * c[1] + xi(2) * c[2] - 2.0;
    N(i) = 0.125 * f[0] * f[1] * f[2] * s;
    // d/dxi_k [f_k s] = c_k s + f_k c_k = c_k (s + f_k).
    dN(i, 0) = 0.125 * c[0] * (s + f[0]) * f[1] * f[2];
    dN(i, 1) = 0.125 * c[1] * (s + f[1]) * f[0] * f[2];
    dN(i, 2) = 0.125 * c[2] * (s + f[2]) * f[0] * f[1];
  }
  for (int i = 8; i < 20; ++i) {
    const double* c = kHexNodes[i];
    // Factor per direction: 1 - x^2 along the edge (c = 0), 1 + x c across it.
    double f[3], df[3];
    for (int k = 0; k < 3; ++k) {
      if (c[k] == 0.0) {
        f[k] = 1.0 - xi(k) * xi(k);
        df[k] = -2.0 * xi(k);
      } else {
        f[k] = 1.0 + xi(k) * c[k];
        df[k] = c[k];
      }
    }
    N(i) = 0.25 * f[0] * f[1] * f[2];
    dN(i, 0) = 0.25 * df[0] * f[1] * f[2];
    dN(i, 1) = 0.25 * f[0] * df[1] * f[2];
    dN(i, 2) = 0.25 * f[0] * f[1] * df[2];
  }
}

// ---------------------------------------------------------------------------------------------------
// Quadrature rules.
// ---------------------------------------------------------------------------------------------------

/// A point of a tetrahedral rule given by its volume coordinates (L1, L2, L3, L4): xi = (L2, L3, L4).
Eigen::Vector3d tet_point(double L2, double L3, double L4) {
  return Eigen::Vector3d(L2, L3, L4);
}

/// The 4 points with volume coordinates (b, a, a, a) and its permutations (a, b, a, a), ...
void add_tet_orbit4(QuadratureRule& r, double a, double weight) {
  const double b = 1.0 - 3.0 * a;
  r.points.push_back(tet_point(a, a, a));  // L1 = b
  r.points.push_back(tet_point(b, a, a));
  r.points.push_back(tet_point(a, b, a));
  r.points.push_back(tet_point(a, a, b));
  r.weights.insert(r.weights.end(), 4, weight);
}

/// The 6 points with volume coordinates the permutations of (a, a, b, b), b = 1/2 - a.
void add_tet_orbit6(QuadratureRule& r, double a, double weight) {
  const double b = 0.5 - a;
  // L1 = a: two of (L2, L3, L4) are b and one a; L1 = b: one of them is b and two a.
  r.points.push_back(tet_point(a, b, b));
  r.points.push_back(tet_point(b, a, b));
  r.points.push_back(tet_point(b, b, a));
  r.points.push_back(tet_point(b, a, a));
  r.points.push_back(tet_point(a, b, a));
  r.points.push_back(tet_point(a, a, b));
  r.weights.insert(r.weights.end(), 6, weight);
}

/// Tetrahedron, 1 point at the centroid, weight = volume 1/6: degree 1.
QuadratureRule tet_rule_1() {
  QuadratureRule r;
  r.points.push_back(tet_point(0.25, 0.25, 0.25));
  r.weights.push_back(1.0 / 6.0);
  r.degree = 1;
  return r;
}

/// Tetrahedron, 4 points (b, a, a, a) and permutations, a = (5 - sqrt 5)/20, b = (5 + 3 sqrt 5)/20,
/// weights 1/24: degree 2 (Zienkiewicz, Taylor and Zhu 2013, table of tetrahedral integration
/// formulae; Keast, Comput. Methods Appl. Mech. Eng. 55, 1986, 339-348).
QuadratureRule tet_rule_4() {
  QuadratureRule r;
  add_tet_orbit4(r, (5.0 - std::sqrt(5.0)) / 20.0, 1.0 / 24.0);
  r.degree = 2;
  return r;
}

/// Tetrahedron, 14 points, all weights positive: degree 5. N. J. Walkington, "Quadrature on simplices
/// of arbitrary dimension", Carnegie Mellon Univ. tech. report 00-CNA-023, 2000 (the same rule is the
/// 14-point degree-5 rule of Witherden and Vincent, Comput. Math. Appl. 69, 2015, 1232-1241). Points
/// and weights (for volume 1/6) re-derived to 20 digits by Newton's method on the six symmetric moment
/// equations of degree <= 5; the test checks all monomials up to degree 5.
QuadratureRule tet_rule_14() {
  QuadratureRule r;
  add_tet_orbit4(r, 0.0927352503108912264, 0.0122488405193936583);
  add_tet_orbit4(r, 0.3108859192633006098, 0.0187813209530026418);
  add_tet_orbit6(r, 0.4544962958743503505, 0.0070910034628469111);
  r.degree = 5;
  return r;
}

/// Gauss-Legendre product rule on [-1,1]^3 with n = 2 (degree 3 per coordinate) or 3 (degree 5).
QuadratureRule gauss_hex_rule(int n) {
  std::array<double, 3> x{}, w{};
  if (n == 2) {
    x = {-1.0 / std::sqrt(3.0), 1.0 / std::sqrt(3.0), 0.0};
    w = {1.0, 1.0, 0.0};
  } else {
    x = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
    w = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  }
  QuadratureRule r;
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        r.points.emplace_back(x[i], x[j], x[k]);
        r.weights.push_back(w[i] * w[j] * w[k]);
      }
    }
  }
  r.degree = 2 * n - 1;
  return r;
}

// ---------------------------------------------------------------------------------------------------
// Element integration.
// ---------------------------------------------------------------------------------------------------

void check_material(const IsotropicMaterial& m) {
  if (!(std::isfinite(m.E) && m.E > 0.0)) {
    throw Error("solid element: Young's modulus must be positive (got " + std::to_string(m.E) + " Pa)");
  }
  if (!(std::isfinite(m.nu) && m.nu > -1.0 && m.nu < 0.5)) {
    throw Error("solid element: Poisson's ratio must lie in (-1, 0.5) (got " + std::to_string(m.nu) + ")");
  }
  if (!(std::isfinite(m.rho) && m.rho >= 0.0)) {
    throw Error("solid element: the density must be >= 0 (got " + std::to_string(m.rho) + " kg/m^3)");
  }
}

std::string format_vector(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s << std::setprecision(6) << '(' << v(0) << ", " << v(1) << ", " << v(2) << ')';
  return s.str();
}

/// The shape functions and their natural derivatives at the points of a rule: the same for every
/// element of a type, so computed once per type and rule (not per element and point).
struct ShapeTable {
  std::vector<Eigen::VectorXd> N;       ///< per point: n
  std::vector<Eigen::MatrixXd> dN_dxi;  ///< per point: n x 3
};
const ShapeTable& shape_table(SolidType type, Integrand what) {
  static const std::array<ShapeTable, 8> tables = [] {
    std::array<ShapeTable, 8> t;
    for (SolidType ty : {SolidType::kTet4, SolidType::kTet10, SolidType::kHex8, SolidType::kHex20}) {
      for (Integrand w : {Integrand::kStiffness, Integrand::kMass}) {
        ShapeTable& table = t[2 * static_cast<int>(ty) + static_cast<int>(w)];
        for (const Eigen::Vector3d& xi : quadrature_rule(ty, w).points) {
          table.N.emplace_back();
          table.dN_dxi.emplace_back();
          shape_functions(ty, xi, table.N.back(), table.dN_dxi.back());
        }
      }
    }
    return t;
  }();
  return tables[2 * static_cast<int>(type) + static_cast<int>(what)];
}

/// The Jacobian J = dx/dxi (J_ik = sum_a x_i^a dN_a/dxi_k) at one point.
Eigen::Matrix3d jacobian(const Eigen::Matrix<double, 3, Eigen::Dynamic>& nodes,
                         const Eigen::MatrixXd& dN_dxi) {
  return nodes * dN_dxi;
}

/// Throws unless det J is positive at every integration point of both rules. A determinant below
/// 1e-12 of the bounding-box diagonal cubed counts as zero (a numerically flat element).
void check_jacobian(SolidType type, const Eigen::Matrix<double, 3, Eigen::Dynamic>& nodes) {
  const double size = (nodes.rowwise().maxCoeff() - nodes.rowwise().minCoeff()).norm();
  const double tolerance = 1e-12 * size * size * size;
  double min_det = std::numeric_limits<double>::infinity();
  Eigen::Vector3d min_xi = Eigen::Vector3d::Zero();
  int bad = 0, total = 0;
  const QuadratureRule& stiffness_rule = quadrature_rule(type, Integrand::kStiffness);
  const QuadratureRule& mass_rule = quadrature_rule(type, Integrand::kMass);
  std::vector<Integrand> rules = {Integrand::kStiffness};
  if (&mass_rule != &stiffness_rule) rules.push_back(Integrand::kMass);  // hexes: one rule for both
  for (const Integrand what : rules) {
    const QuadratureRule& rule = quadrature_rule(type, what);
    const ShapeTable& table = shape_table(type, what);
    for (std::size_t q = 0; q < rule.points.size(); ++q) {
      const double det = jacobian(nodes, table.dN_dxi[q]).determinant();
      ++total;
      if (!(det > tolerance)) ++bad;
      if (det < min_det || std::isnan(det)) {
        min_det = det;
        min_xi = rule.points[q];
      }
    }
  }
  if (bad == 0) return;
  Eigen::VectorXd N;
  Eigen::MatrixXd dN;
  shape_functions(type, min_xi, N, dN);
  std::ostringstream msg;
  msg << std::setprecision(6) << "inverted or degenerate " << to_string(type)
      << " element: the Jacobian determinant is <= 0 at " << bad << " of " << total
      << " integration points; min det J = " << min_det << " m^3 at natural coordinates "
      << format_vector(min_xi) << ", x = " << format_vector(nodes * N)
      << " m (check the node order against the Abaqus/CalculiX numbering)";
  throw Error(msg.str());
}

}  // namespace

int node_count(SolidType type) {
  switch (type) {
    case SolidType::kTet4:
      return 4;
    case SolidType::kTet10:
      return 10;
    case SolidType::kHex8:
      return 8;
    case SolidType::kHex20:
      return 20;
  }
  throw Error("unknown solid element type");
}

std::string to_string(SolidType type) {
  switch (type) {
    case SolidType::kTet4:
      return "C3D4";
    case SolidType::kTet10:
      return "C3D10";
    case SolidType::kHex8:
      return "C3D8";
    case SolidType::kHex20:
      return "C3D20";
  }
  throw Error("unknown solid element type");
}

SolidType parse_solid_type(const std::string& abaqus_name) {
  std::string name;
  for (char ch : abaqus_name) {
    if (!std::isspace(static_cast<unsigned char>(ch))) {
      name += static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    }
  }
  for (SolidType t : {SolidType::kTet4, SolidType::kTet10, SolidType::kHex8, SolidType::kHex20}) {
    if (name == to_string(t)) return t;
  }
  const std::string supported =
      "supported are C3D4, C3D10, C3D8 and C3D20 (fully integrated isoparametric tetrahedra and hexahedra)";
  if (name == "C3D8R" || name == "C3D20R") {
    throw Error("solid element type '" + abaqus_name + "': reduced integration is not supported; " +
                supported);
  }
  throw Error("unsupported solid element type '" + abaqus_name + "'; " + supported);
}

void shape_functions(SolidType type, const Eigen::Vector3d& xi, Eigen::VectorXd& N, Eigen::MatrixXd& dN) {
  switch (type) {
    case SolidType::kTet4:
      return tet4_shape(xi, N, dN);
    case SolidType::kTet10:
      return tet10_shape(xi, N, dN);
    case SolidType::kHex8:
      return hex8_shape(xi, N, dN);
    case SolidType::kHex20:
      return hex20_shape(xi, N, dN);
  }
  throw Error("unknown solid element type");
}

const QuadratureRule& quadrature_rule(SolidType type, Integrand what) {
  // Full integration: exact for the stiffness and mass of undistorted (affine) elements.
  //   C3D4:  B constant -> 1 point; N_i N_j of degree 2 -> 4 points.
  //   C3D10: B linear, B^T D B of degree 2 -> 4 points; N_i N_j of degree 4 -> 14 points (degree 5).
  //   C3D8:  2x2x2 Gauss (as Abaqus/CalculiX C3D8) for both.
  //   C3D20: 3x3x3 Gauss (as C3D20) for both; N_i N_j has degree 4 in each coordinate.
  static const QuadratureRule tet1 = tet_rule_1();
  static const QuadratureRule tet4 = tet_rule_4();
  static const QuadratureRule tet14 = tet_rule_14();
  static const QuadratureRule hex2 = gauss_hex_rule(2);
  static const QuadratureRule hex3 = gauss_hex_rule(3);
  const bool mass = what == Integrand::kMass;
  switch (type) {
    case SolidType::kTet4:
      return mass ? tet4 : tet1;
    case SolidType::kTet10:
      return mass ? tet14 : tet4;
    case SolidType::kHex8:
      return hex2;
    case SolidType::kHex20:
      return hex3;
  }
  throw Error("unknown solid element type");
}

Eigen::Matrix<double, 6, 6> isotropic_elasticity(const IsotropicMaterial& m) {
  // Lame constants: lambda = E nu / ((1 + nu)(1 - 2 nu)), G = E / (2 (1 + nu)).
  const double lambda = m.E * m.nu / ((1.0 + m.nu) * (1.0 - 2.0 * m.nu));
  const double G = m.E / (2.0 * (1.0 + m.nu));
  Eigen::Matrix<double, 6, 6> D = Eigen::Matrix<double, 6, 6>::Zero();
  D.topLeftCorner<3, 3>().setConstant(lambda);
  for (int i = 0; i < 3; ++i) {
    D(i, i) = lambda + 2.0 * G;
    D(3 + i, 3 + i) = G;
  }
  return D;
}

SolidElementMatrices solid_element(SolidType type, const Eigen::Matrix<double, 3, Eigen::Dynamic>& nodes,
                                   const IsotropicMaterial& material, MassQuadrature mass_quadrature) {
  const int n = node_count(type);
  if (nodes.cols() != n) {
    throw Error(to_string(type) + " element needs " + std::to_string(n) + " nodes, got " +
                std::to_string(nodes.cols()));
  }
  if (!nodes.allFinite()) throw Error(to_string(type) + " element: node coordinates are not finite");
  check_material(material);
  check_jacobian(type, nodes);

  SolidElementMatrices out;
  // K = int B^T D B dV with the isotropic D (Lame constants lambda, mu): the 3 x 3 block of nodes i, j
  // is, with the gradients g_i = dN_i/dx = J^-T dN_i/dxi,
  //   K_ij = int lambda g_i g_j^T + mu g_j g_i^T + mu (g_i . g_j) 1 dV
  // (the same as B_i^T D B_j written out, without the zeros of B), summed as sum_q w_q det J (...).
  const Eigen::Matrix<double, 6, 6> D = isotropic_elasticity(material);
  const double lambda = D(0, 1), mu = D(3, 3);
  out.stiffness = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  const QuadratureRule& stiffness_rule = quadrature_rule(type, Integrand::kStiffness);
  const ShapeTable& stiffness_shapes = shape_table(type, Integrand::kStiffness);
  Eigen::Matrix<double, Eigen::Dynamic, 3> g(n, 3);
  for (std::size_t q = 0; q < stiffness_rule.points.size(); ++q) {
    const Eigen::Matrix3d J = jacobian(nodes, stiffness_shapes.dN_dxi[q]);
    const double w = stiffness_rule.weights[q] * J.determinant();
    g.noalias() = stiffness_shapes.dN_dxi[q] * J.inverse();
    for (int j = 0; j < n; ++j) {
      const Eigen::RowVector3d gj = w * g.row(j);
      for (int i = 0; i <= j; ++i) {  // upper blocks; the lower ones are mirrored below
        const Eigen::RowVector3d gi = g.row(i);
        Eigen::Matrix3d k = lambda * gi.transpose() * gj + mu * gj.transpose() * gi;
        k.diagonal().array() += mu * gi.dot(gj);
        out.stiffness.block<3, 3>(3 * i, 3 * j) += k;
      }
    }
  }
  // Exactly symmetric (the diagonal blocks' products above were rounded in different orders).
  for (int c = 0; c < 3 * n; ++c)
    for (int r = c + 1; r < 3 * n; ++r) out.stiffness(r, c) = out.stiffness(c, r);

  // M_ij = int rho N_i N_j dV and V = int dV, with the (higher-order) mass rule.
  out.scalar_mass = Eigen::MatrixXd::Zero(n, n);
  const Integrand mass_integrand =
      mass_quadrature == MassQuadrature::kExact ? Integrand::kMass : Integrand::kStiffness;
  const QuadratureRule& mass_rule = quadrature_rule(type, mass_integrand);
  const ShapeTable& mass_shapes = shape_table(type, mass_integrand);
  for (std::size_t q = 0; q < mass_rule.points.size(); ++q) {
    const double dV = mass_rule.weights[q] * jacobian(nodes, mass_shapes.dN_dxi[q]).determinant();
    const Eigen::VectorXd& N = mass_shapes.N[q];
    out.scalar_mass.noalias() += (material.rho * dV) * (N * N.transpose());
    out.volume += dV;
  }
  return out;
}

Eigen::MatrixXd solid_stress_stiffness(SolidType type, const Eigen::Matrix<double, 3, Eigen::Dynamic>& nodes,
                                       const IsotropicMaterial& material,
                                       const Eigen::VectorXd& displacement) {
  const int n = node_count(type);
  if (nodes.cols() != n || displacement.size() != 3 * n) {
    throw Error(to_string(type) + " element needs " + std::to_string(n) + " nodes and " +
                std::to_string(3 * n) + " displacements");
  }
  check_material(material);
  check_jacobian(type, nodes);
  const Eigen::Matrix<double, 6, 6> D = isotropic_elasticity(material);
  const double lambda = D(0, 1), mu = D(3, 3);
  // u as 3 x n (column i: node i's displacement).
  const Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic>> u(displacement.data(), 3, n);
  Eigen::MatrixXd kg = Eigen::MatrixXd::Zero(n, n);
  const QuadratureRule& rule = quadrature_rule(type, Integrand::kStiffness);
  const ShapeTable& shapes = shape_table(type, Integrand::kStiffness);
  Eigen::Matrix<double, Eigen::Dynamic, 3> g(n, 3);
  for (std::size_t q = 0; q < rule.points.size(); ++q) {
    const Eigen::Matrix3d J = jacobian(nodes, shapes.dN_dxi[q]);
    const double w = rule.weights[q] * J.determinant();
    g.noalias() = shapes.dN_dxi[q] * J.inverse();
    // grad u (row a: du_a/dx), eps = sym(grad u), sigma = lambda tr(eps) 1 + 2 mu eps.
    const Eigen::Matrix3d grad = u * g;
    const Eigen::Matrix3d eps = 0.5 * (grad + grad.transpose());
    Eigen::Matrix3d sigma = 2.0 * mu * eps;
    sigma.diagonal().array() += lambda * eps.trace();
    kg.noalias() += w * (g * sigma * g.transpose());
  }
  return 0.5 * (kg + kg.transpose());
}

}  // namespace nvh::condense
