#pragma once
// Inertia invariants of a flexible body in a floating frame of reference, in Shabana's formulation
// (A. A. Shabana, Dynamics of Multibody Systems, 3rd ed., Cambridge 2005, sec. 5.5, eq. 5.99-5.110),
// computed from the consistent mass matrix and its section-resolved parts (beams) or from the scalar
// consistent mass m_ij = int rho N_i N_j dV (solids), never from lumped masses.
//
// A material point at x (undeformed, component axes, m) moves by u = S(x) q, with S = N B the shape
// field of the reduced basis B. The invariants are:
//   m                     = int rho dV                                      (kg)
//   m c                   = int rho x dV                                    (kg m)
//   J_c                   inertia tensor about the centre of mass          (kg m^2)
//   I_kl  (3x3)           = int rho x_k x_l dV                              (kg m^2)
//   S_bar (3 x n)         = int rho S dV                  translational coupling
//   S_rot (3 x n)         = int rho x~ S dV               rotational coupling (about the origin)
//   I_tilde_kl (3x3 x n)  = int rho x_k S_l dV            position coupling
//   S_kl  (3x3 x n x n)   = int rho S_k^T S_l dV          quadratic (second-order) terms
// With them the mass matrix of the body in its frame is exact for any q (Shabana eq. 5.115).
#include <Eigen/Core>
#include <vector>

#include "common/inertia_invariants.hpp"
#include "condense/fe_model.hpp"

namespace nvh::condense {

// The plain-data results are the superelement file's (common/inertia_invariants.hpp).
using nvh::ModalInvariants;
using nvh::RigidBodyInertia;

/// Mass, centre of mass and inertia from the 6x6 rigid-body mass R^T M R (R about the origin).
RigidBodyInertia rigid_body_inertia(const Eigen::Matrix<double, 6, 6>& rigid_mass);

/// The rigid-body inertia of a model from its consistent mass (supports ignored): R^T M_all R for a
/// beam model, the moments 1^T m 1, 1^T m x_k, x_k^T m x_l of the scalar mass for a volume model.
RigidBodyInertia rigid_body_inertia(const FeModel& model);

/// Modal invariants for nodal shapes `shapes` (6N x n, i.e. T * basis): from mass_all and its
/// section-resolved parts for a beam model; from the scalar mass and the shapes' translations for a
/// volume model (the same integrals, with M_all = m (x) I_3 written out; see invariants.cpp).
ModalInvariants modal_invariants(const FeModel& model, const Eigen::MatrixXd& shapes);

}  // namespace nvh::condense
