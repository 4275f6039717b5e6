#pragma once
// Isoparametric 3D solid (volume) elements with full integration: the 4- and 10-node tetrahedra and the
// 8- and 20-node hexahedra of Abaqus/CalculiX (C3D4, C3D10, C3D8, C3D20), for isotropic linear
// elasticity. Displacement-based: K = int B^T D B dV, consistent mass M = int rho N^T N dV
// (Zienkiewicz, Taylor and Zhu, The Finite Element Method: Its Basis and Fundamentals, 7th ed., 2013:
// the chapters on three-dimensional elasticity, standard shape functions and isoparametric mapping with
// numerical integration).
//
// Node numbering (1-based, as in the Abaqus Analysis User's Guide, "Three-dimensional solid element
// library" (sec. 28.1.4 in version 6.14), and the CalculiX CrunchiX User's Manual, "Element Types"):
//   C3D4   corners 1-4; natural coordinates 1 (0,0,0), 2 (1,0,0), 3 (0,1,0), 4 (0,0,1). Positive volume
//          when node 4 lies on the side of face 1-2-3 to which its right-hand normal points.
//   C3D10  corners 1-4 as C3D4, then the mid-edge nodes 5: 1-2, 6: 2-3, 7: 3-1, 8: 1-4, 9: 2-4, 10: 3-4.
//          NOT gmsh's order: gmsh's 10-node tetrahedron has node 9 on 3-4 and node 10 on 2-4 (swap them).
//   C3D8   corners 1-4 on the face zeta = -1 and 5-8 on zeta = +1, each face counter-clockwise seen from
//          zeta = +1: 1 (-1,-1,-1), 2 (1,-1,-1), 3 (1,1,-1), 4 (-1,1,-1), 5..8 the same with zeta = +1.
//   C3D20  corners 1-8 as C3D8, then the mid-edge nodes 9: 1-2, 10: 2-3, 11: 3-4, 12: 4-1, 13: 5-6,
//          14: 6-7, 15: 7-8, 16: 8-5, 17: 1-5, 18: 2-6, 19: 3-7, 20: 4-8.
//          NOT gmsh's order: 0-based, abaqus[j] = gmsh[p[j]] with p = {0, ..., 8, 11, 13, 9, 16, 18, 19, 17,
//          10, 12, 14, 15} (gmsh's mid-edge nodes are on 1-2, 1-4, 1-5, 2-3, 2-6, 3-4, 3-7, 4-8, 5-6, 5-8,
//          6-7, 7-8). C3D4 and C3D8 are numbered as in gmsh. The Abaqus order is also VTK's.
//
// DOF order of the element matrices: node-major, (u_x, u_y, u_z) of node 1, then node 2, ... (m).
#include <Eigen/Core>
#include <string>
#include <vector>

namespace nvh::condense {

/// The supported solid elements, by their Abaqus/CalculiX names: C3D4, C3D10, C3D8, C3D20.
enum class SolidType { kTet4, kTet10, kHex8, kHex20 };

/// Number of nodes: 4, 10, 8, 20.
int node_count(SolidType type);
/// The Abaqus/CalculiX name: "C3D4", "C3D10", "C3D8", "C3D20".
std::string to_string(SolidType type);
/// Parse "C3D4" | "C3D10" | "C3D8" | "C3D20" (case-insensitive, as Abaqus keywords are). Anything else,
/// including the reduced-integration C3D8R/C3D20R and the other variants (C3D10M, C3D8I, ...), is an
/// nvh::Error that lists the supported types.
SolidType parse_solid_type(const std::string& abaqus_name);

/// Linear isotropic elastic material, SI units.
struct IsotropicMaterial {
  double E;    ///< Young's modulus, Pa
  double nu;   ///< Poisson's ratio, -
  double rho;  ///< density, kg/m^3
};

/// Element matrices on the node-major DOF order described above.
struct SolidElementMatrices {
  Eigen::MatrixXd stiffness;  ///< 3n x 3n, N/m
  Eigen::MatrixXd
      scalar_mass;      ///< n x n: int rho N_i N_j dV (kg); the consistent mass is scalar_mass (x) I_3
  double volume = 0.0;  ///< m^3
};

/// Stiffness and mass of one element. nodes: 3 x n coordinates (m), n = node_count(type), in the node
/// order above. nvh::Error for a wrong node count, an invalid material (E <= 0, nu outside (-1, 0.5),
/// rho < 0), or a Jacobian determinant <= 0 at any integration point ("inverted or degenerate element",
/// with the minimum det J and where it occurs).
/// Integration (full): C3D4 1 point (stiffness), 4 points (mass); C3D10 4 points (stiffness),
/// 14 points, degree 5 (mass); C3D8 2x2x2 Gauss; C3D20 3x3x3 Gauss.
/// How the mass is integrated: exactly (the consistent mass; default), or with the stiffness rule,
/// which is what CalculiX 2.20 does (for C3D10 its 4-point rule is exact only to degree 2, so its
/// mass differs: measured up to 1 % on the 20th mode of a coarse clamped bar, none on C3D20).
enum class MassQuadrature { kExact, kStiffnessRule };

SolidElementMatrices solid_element(SolidType type, const Eigen::Matrix<double, 3, Eigen::Dynamic>& nodes,
                                   const IsotropicMaterial& material,
                                   MassQuadrature mass_quadrature = MassQuadrature::kExact);

/// Stress (geometric) stiffness of one element under the stress of its nodal displacement `displacement`
/// (3n, node-major, m): the linear prestress sigma = D eps(u) at each point of the stiffness rule, and
///   K_G(3i+a, 3j+b) = delta_ab int g_i^T sigma g_j dV,    g_i = dN_i/dx
/// (the second variation of the Green-Lagrange strain under the initial stress: Bathe, Finite Element
/// Procedures, 1996, sec. 6.3.2, the matrix K_NL of the updated Lagrangian form; Cook, Malkus, Plesha and
/// Witt, Concepts and Applications of Finite Element Analysis, 4th ed., 2002, sec. 18.3). The same for every
/// displacement component, so it is returned as its n x n scalar part (N/m). Integrated with the stiffness
/// rule, as CalculiX does (for C3D10 the integrand is cubic on an affine element and the 4-point rule exact
/// to degree 2). nvh::Error as solid_element for bad nodes or material.
Eigen::MatrixXd solid_stress_stiffness(SolidType type, const Eigen::Matrix<double, 3, Eigen::Dynamic>& nodes,
                                       const IsotropicMaterial& material,
                                       const Eigen::VectorXd& displacement);

/// Shape functions N (n) and their derivatives dN/dxi (n x 3) at natural coordinates xi (tets: volume
/// coordinates xi, eta, zeta with L1 = 1 - xi - eta - zeta; hexes: [-1,1]^3). N and dN are resized.
void shape_functions(SolidType type, const Eigen::Vector3d& xi, Eigen::VectorXd& N, Eigen::MatrixXd& dN);

/// A quadrature rule on the reference element (tets: 0 <= xi, eta, zeta, xi + eta + zeta <= 1, volume
/// 1/6; hexes: [-1,1]^3, volume 8): sum_q weights[q] f(points[q]) ~ int f, exact for polynomials of total
/// degree <= `degree` (tets) or of degree <= `degree` in each coordinate (hexes).
struct QuadratureRule {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  int degree = 0;
};
/// What an integral is for: the stiffness (products of derivatives) or the mass (products of N).
enum class Integrand { kStiffness, kMass };
/// The rule solid_element uses for `what` on elements of `type`.
const QuadratureRule& quadrature_rule(SolidType type, Integrand what);

/// Isotropic elasticity matrix D (6 x 6) in Voigt notation, stress = D strain, with the strain vector
/// (e_xx, e_yy, e_zz, gamma_xy, gamma_yz, gamma_zx) of engineering shear strains (Zienkiewicz et al.,
/// 2013, three-dimensional elasticity). Note Abaqus orders the shear terms 12, 13, 23.
Eigen::Matrix<double, 6, 6> isotropic_elasticity(const IsotropicMaterial& material);

}  // namespace nvh::condense
