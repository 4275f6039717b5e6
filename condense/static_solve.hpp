#pragma once
// Static solutions of a structural model (K, M on its free DOF), with inertia relief for a component
// that is free or only partly supported, and the small sparse helpers they share with the reduction.
//
// Inertia relief (Craig and Kurdila, Fundamentals of Structural Dynamics, 2nd ed. 2006, ch. 17): a load F
// on a component with rigid-body modes Phi_r (M-orthonormal) is balanced by the d'Alembert forces of the
// rigid-body acceleration it causes, P F = F - M Phi_r Phi_r^T F, which is self-equilibrated
// (Phi_r^T P F = 0). Its elastic deformation is u = P^T K_c^-1 P F, K_c being K with r statically
// determinate DOF held (K_c^-1 padded with zeros on them) and P^T u = u - Phi_r Phi_r^T M u removing the
// rigid-body part; u is independent of which determinate DOF are held. For a supported component
// (no Phi_r) this is plain K^-1 F.
#include <Eigen/Core>
#include <vector>

#include "condense/constrained_factor.hpp"

namespace nvh::condense {

/// Rows/columns `rows` x `cols` of a sparse matrix (index lists in ascending order).
SparseMatrix submatrix(const SparseMatrix& a, const std::vector<int>& rows, const std::vector<int>& cols);

/// A x for a symmetric sparse A stored whole or as its lower triangle.
Eigen::MatrixXd symmetric_times(const SparseMatrix& a, bool lower, const Eigen::MatrixXd& x);

/// The inertia-relief static deflections u (n x k) under the loads F (n x k), M-orthogonal to Phi_r.
/// K and M whole or as lower triangles (`lower`); Phi_r n x r, M-orthonormal (r may be 0). The cost of
/// the one factorization is added to `stats` when given. nvh::Error when K with the determinate DOF held
/// is not positive definite (a mechanism, or more rigid-body modes than Phi_r holds).
Eigen::MatrixXd inertia_relief_solve(const SparseMatrix& K, const SparseMatrix& M, bool lower,
                                     const Eigen::MatrixXd& F, const Eigen::MatrixXd& phi_r,
                                     Ordering ordering, FactorStats* stats = nullptr);

}  // namespace nvh::condense
