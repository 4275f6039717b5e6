#include "condense/geometric_stiffness.hpp"

#include <Eigen/Cholesky>

#include "common/error.hpp"
#include "condense/static_solve.hpp"

namespace nvh::condense {
namespace {

/// The centrifugal loads b_ab on all nodal DOF (6N x 6), from the beams' position moments:
/// int rho N_A^T x_k dV is column 3k+A of position_moment_all, and (b_ab)_A = rho sum_k B_Ak x_k with
/// B = 1 - e_a e_a^T (a = b) or -(e_a e_b^T + e_b e_a^T) (a < b).
Eigen::MatrixXd centrifugal_loads(const FeModel& model) {
  Eigen::MatrixXd f = Eigen::MatrixXd::Zero(model.all_dofs(), 6);
  for (int p = 0; p < 6; ++p) {
    const int a = kSpinProducts[p][0], b = kSpinProducts[p][1];
    Eigen::Matrix3d B;
    if (a == b) {
      B = Eigen::Matrix3d::Identity();
      B(a, a) = 0.0;
    } else {
      B.setZero();
      B(a, b) = B(b, a) = -1.0;
    }
    for (int A = 0; A < 3; ++A)
      for (int k = 0; k < 3; ++k)
        if (B(A, k) != 0.0) f.col(p) += B(A, k) * model.position_moment_all.col(3 * k + A);
  }
  return f;
}

/// The model's rigid-body modes on the free DOF, M-orthonormal (free x r): the rigid fields that the
/// supports leave free, restricted to the master DOF (a slave follows its master rigidly).
Eigen::MatrixXd free_rigid_body_modes(const FeModel& model, const SparseMatrix& M, bool lower, int rigid) {
  const int n = model.free_dofs();
  if (rigid == 0) return Eigen::MatrixXd(n, 0);
  const Eigen::MatrixXd field = model.rigid_body_field();
  const std::vector<int> free = model.free_index();
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(n, 6);
  for (int d = 0; d < model.all_dofs(); ++d)
    if (free[d] >= 0) r.row(free[d]) = field.row(d);
  const Eigen::MatrixXd phi = r * model.unsupported_rigid_motions();
  const Eigen::MatrixXd gram = phi.transpose() * symmetric_times(M, lower, phi);
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (gram + gram.transpose()));
  if (llt.info() != Eigen::Success || phi.cols() != rigid)
    throw Error("geometric stiffness: the rigid-body modes have no mass, or do not match the count");
  // phi L^-T: M-orthonormal.
  return llt.matrixU().solve<Eigen::OnTheRight>(phi);
}

}  // namespace

std::array<SparseMatrix, 6> centrifugal_geometric_stiffness(const FeModel& model, const SparseMatrix& K,
                                                            const SparseMatrix& M, bool lower,
                                                            int rigid_body_modes, Ordering ordering) {
  if (model.beam_elements.empty()) {
    throw Error("geometric stiffening is implemented for beam components only (" + model.element_kind +
                " have no prestress stiffness yet)");
  }
  const Eigen::MatrixXd loads = model.transform.transpose() * centrifugal_loads(model);
  const Eigen::MatrixXd phi_r = free_rigid_body_modes(model, M, lower, rigid_body_modes);
  const Eigen::MatrixXd u = model.transform * inertia_relief_solve(K, M, lower, loads, phi_r, ordering);

  // Each element's axial force under each load, and its geometric stiffness in global DOF.
  std::array<std::vector<Eigen::Triplet<double>>, 6> triplets;
  for (const BeamElementRecord& e : model.beam_elements) {
    const Matrix12 T = local_from_global(e.axes);
    std::array<int, 12> dofs;
    for (int i = 0; i < 6; ++i) {
      dofs[i] = 6 * e.node1 + i;
      dofs[6 + i] = 6 * e.node2 + i;
    }
    const Matrix12 unit = T.transpose() * local_geometric_stiffness(e.data, 1.0) * T;
    for (int p = 0; p < 6; ++p) {
      Vector12 ue;
      for (int i = 0; i < 12; ++i) ue(i) = u(dofs[i], p);
      const double N = axial_force(e.data, T * ue);
      for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 12; ++j)
          if (unit(i, j) != 0.0) triplets[p].emplace_back(dofs[i], dofs[j], N * unit(i, j));
    }
  }
  std::array<SparseMatrix, 6> out;
  for (int p = 0; p < 6; ++p) {
    SparseMatrix all(model.all_dofs(), model.all_dofs());
    all.setFromTriplets(triplets[p].begin(), triplets[p].end());
    out[p] = model.transform.transpose() * all * model.transform;
  }
  return out;
}

}  // namespace nvh::condense
