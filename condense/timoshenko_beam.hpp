#pragma once
// The 2-node, 12-DOF 3D Timoshenko beam element: axial, torsion and bending in two principal planes,
// each with shear deformation and rotary inertia. Euler-Bernoulli is its limit for kappa -> infinity
// (shear parameter Phi = 0).
//
// Local frame: x along the element from node 1 to node 2, y and z the principal axes of the section.
// Local DOF order: [u1 v1 w1 rx1 ry1 rz1  u2 v2 w2 rx2 ry2 rz2] (displacements in m, rotations in rad).
//
// Stiffness: the exact Timoshenko stiffness (Przemieniecki, Theory of Matrix Structural Analysis, 1968,
// sec. 5.6), with Phi = 12 E I / (kappa G A L^2).
// Mass: consistent, from the interdependent interpolation of Friedman and Kosmatka (Computers &
// Structures 47(3), 1993, eq. 15-16), integrated exactly by 4-point Gauss quadrature. The same
// integration gives the section-resolved "component" mass matrices int rho N_a^T N_b dV (a, b = x, y, z)
// and the position moments int rho x_k N_a dV that the floating-frame inertia invariants need.
#include <Eigen/Core>
#include <array>

namespace nvh::condense {

using Matrix12 = Eigen::Matrix<double, 12, 12>;
using Vector12 = Eigen::Matrix<double, 12, 1>;

/// Everything the element needs, in SI units.
struct BeamElementData {
  double L = 0.0;              ///< length, m
  double E = 0.0, G = 0.0;     ///< Young's and shear modulus, Pa
  double rho = 0.0;            ///< density, kg/m^3
  double A = 0.0;              ///< area, m^2
  double Iy = 0.0, Iz = 0.0;   ///< second moments about local y and z, m^4
  double J = 0.0;              ///< torsion constant, m^4
  double shear_factor = 0.0;   ///< kappa; 0 = no shear deformation (Euler-Bernoulli)
  bool rotary_inertia = true;  ///< rotary inertia of bending (Rayleigh); torsional inertia is always kept

  double phi_y() const;  ///< shear parameter of bending in the x-z plane (about y): 12 E Iy / (kappa G A L^2)
  double phi_z() const;  ///< shear parameter of bending in the x-y plane (about z)
};

/// Local stiffness matrix.
Matrix12 local_stiffness(const BeamElementData& e);
/// Axial force N (N, tension positive) of the element under local nodal displacements u_local: E A (u2 - u1) / L.
double axial_force(const BeamElementData& e, const Vector12& u_local);
/// Local geometric (stress) stiffness under the axial force N (N, tension positive):
///   K_G = N int_0^L (v'^T v' + w'^T w' + (Iy + Iz) / A rx'^T rx') dx
/// with the slopes of the element's own deflection interpolation (for Phi = 0 the classical
/// N / (30 L) [36, 3L, -36, 3L; 3L, 4L^2, -3L, -L^2; ...] of Przemieniecki 1968, ch. 15), and the
/// torsional (Wagner) term of a section whose shear centre is its centroid.
Matrix12 local_geometric_stiffness(const BeamElementData& e, double N);
/// Local consistent mass matrix (translational + rotary + torsional inertia).
Matrix12 local_mass(const BeamElementData& e);

/// Section-resolved mass integrals of one element in local axes:
///   component[a][b] = int_V rho N_a^T N_b dV   (a, b = local x, y, z displacement components)
/// so that local_mass = component[0][0] + component[1][1] + component[2][2];
///   position[k][a]  = int_V rho x_k N_a dV     (x_k: global coordinate k of the material point)
/// for an element whose node 1 lies at `origin` and whose local axes are the rows of `axes`.
struct BeamMassIntegrals {
  std::array<std::array<Matrix12, 3>, 3> component;
  std::array<std::array<Vector12, 3>, 3> position;
};
BeamMassIntegrals mass_integrals(const BeamElementData& e, const Eigen::Vector3d& origin,
                                 const Eigen::Matrix3d& axes);

/// Rows = unit local axes (x, y, z) in global coordinates, for an element from p1 to p2.
/// `y_hint` fixes local y (projected normal to x); a zero hint picks global Y, or global Z when the
/// element is nearly parallel to Y. nvh::Error if the hint is parallel to the element.
Eigen::Matrix3d beam_axes(const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                          const Eigen::Vector3d& y_hint);

/// 12x12 transformation from global to local DOF: u_local = T u_global (blockdiag of `axes`, 4 times).
Matrix12 local_from_global(const Eigen::Matrix3d& axes);

}  // namespace nvh::condense
