#pragma once
// The mass properties and the modal inertia invariants of a flexible body in a floating frame of reference,
// as plain data: what the superelement file carries in /invariants (docs/hdf5-format.md) and what solve's
// flexible bodies consume. Shabana, Dynamics of Multibody Systems, 3rd ed., 2005, sec. 5.5, eq. 5.99-5.110.
// Their computation from a finite-element model lives in condense (condense/invariants.hpp).
//
// A material point at x (undeformed, component axes, m) moves by u = S(x) q (S: 3 x n shape field):
//   S_bar (3 x n)         = int rho S dV                  translational coupling
//   S_rot (3 x n)         = int rho x~ S dV               rotational coupling (about the origin)
//   I_tilde_kl (n)        = int rho x_k S_l dV            position coupling (S_l: row l of S)
//   S_kl  (n x n)         = int rho S_k^T S_l dV          quadratic (second-order) terms
#include <Eigen/Core>
#include <vector>

namespace nvh {

/// Mass properties of the whole component (independent of supports and of the reduction).
struct RigidBodyInertia {
  double mass = 0.0;               ///< m = int rho dV, kg
  Eigen::Vector3d center_of_mass;  ///< c = (1/m) int rho x dV, m, component axes
  Eigen::Matrix3d inertia;         ///< about the centre of mass, component axes, kg m^2
  Eigen::Matrix3d inertia_origin;  ///< about the component origin, kg m^2
  Eigen::Matrix3d second_moment;   ///< I_kl = int rho x_k x_l dV about the origin, kg m^2
};

/// Integrals of the reduced basis' shape field (they depend on supports and on the reduction).
struct ModalInvariants {
  Eigen::MatrixXd translational;  ///< S_bar, 3 x n, kg m per unit coordinate
  Eigen::MatrixXd rotational;     ///< int rho x~ S dV, 3 x n, kg m^2 per unit coordinate
  /// position[k * 3 + l] = I_tilde_kl (length n), kg m^2 per unit coordinate
  std::vector<Eigen::VectorXd> position;
  /// quadratic[k * 3 + l] = S_kl (n x n), kg m^2 per unit coordinate squared
  std::vector<Eigen::MatrixXd> quadratic;
};

}  // namespace nvh
