#pragma once
// Geometric (stress) stiffening of a spinning component: the centrifugal prestress and the stiffness it
// adds, as matrices per product of the angular velocity's components.
//
// In a frame spinning with angular velocity omega (component axes, about the component origin) a material
// point at x carries the centrifugal body force density
//   b = -rho omega~ omega~ x = rho (|omega|^2 x - omega (omega . x)),
// quadratic in omega: b = sum_{a <= b} omega_a omega_b b_ab with
//   b_aa = rho (x - e_a x_a)            the centrifugal load of a unit spin about axis a,
//   b_ab = -rho (e_a x_b + e_b x_a)     (a < b).
// The prestress is linear in the load, and so is the geometric stiffness it causes:
//   K_G(omega) = sum_{a <= b} omega_a omega_b K_ab,
// K_ab the geometric stiffness of the static (inertia-relief) deflection under b_ab (static_solve.hpp).
// This is the linear prestress of a small-deformation model (Wallrapp, Mech. Struct. Mach. 22(3), 1994:
// the Standard Input Data's geometric stiffness by load cases; Kane, Ryan and Banerjee, J. Guidance 10(2),
// 1987, for why a floating frame needs it). The other half of a spinning body's rotating-frame stiffness,
// the spin softening omega~ omega~ M, is not here: a floating frame of reference (solve) has it in its
// inertia terms.
//
// Elements: beams (the axial force of each element, timoshenko_beam.hpp's local_geometric_stiffness) and
// solids (the stress at each integration point, solid_element.hpp's solid_stress_stiffness).
#include <array>

#include "common/superelement.hpp"
#include "condense/fe_model.hpp"
#include "condense/sparse_cholesky.hpp"

namespace nvh::condense {

/// The products omega_a omega_b in the order of the matrices (xx, yy, zz, xy, yz, zx): the file's.
using nvh::kSpinProductNames;
using nvh::kSpinProducts;

using nvh::spin_products;

/// The geometric stiffness of the model's elements under the linear prestress of the nodal displacement u
/// (all nodal DOF, 6N): on all nodal DOF, both triangles, N/m (and N m/rad on beam rotations).
SparseMatrix prestress_stiffness(const FeModel& model, const Eigen::VectorXd& u);

/// The six K_ab on the free DOF (both triangles), N/m per (rad/s)^2 (and N m/rad per (rad/s)^2 on the
/// rotations). K and M: the model's free-DOF matrices, whole or as lower triangles (`lower`).
/// `rigid_body_modes`: the model's count (count_rigid_body_modes); the static solutions use inertia
/// relief when it is not zero. nvh::Error for a model without element records (a volume model built
/// without geometric_stiffening).
std::array<SparseMatrix, 6> centrifugal_geometric_stiffness(const FeModel& model, const SparseMatrix& K,
                                                            const SparseMatrix& M, bool lower,
                                                            int rigid_body_modes, Ordering ordering);

/// The geometric stiffness of a static preload on the free DOF (both triangles): the deflection under the
/// nodal load `load` (all nodal DOF, N and N m; inertia relief for a free part, as above) and the
/// prestress stiffness of its stress.
SparseMatrix preload_geometric_stiffness(const FeModel& model, const SparseMatrix& K, const SparseMatrix& M,
                                         bool lower, int rigid_body_modes, Ordering ordering,
                                         const Eigen::VectorXd& load);

}  // namespace nvh::condense
