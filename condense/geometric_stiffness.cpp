#include "condense/geometric_stiffness.hpp"

#include <Eigen/Cholesky>

#include "common/error.hpp"
#include "condense/static_solve.hpp"

namespace nvh::condense {
namespace {

/// The matrix B_ab of the load case b_ab = rho B_ab x: 1 - e_a e_a^T (a = b) or -(e_a e_b^T + e_b e_a^T).
Eigen::Matrix3d load_case_matrix(int p) {
  const int a = kSpinProducts[p][0], b = kSpinProducts[p][1];
  Eigen::Matrix3d B = Eigen::Matrix3d::Zero();
  if (a == b) {
    B.setIdentity();
    B(a, a) = 0.0;
  } else {
    B(a, b) = B(b, a) = -1.0;
  }
  return B;
}

/// The centrifugal loads b_ab on all nodal DOF (6N x 6), int N^T rho B_ab x dV.
/// Beams: from the position moments (int rho N_A^T x_k dV is column 3k+A of position_moment_all, so
/// (b_ab)_A = rho sum_k B_Ak x_k loads sum_k B_Ak column 3k+A). Volumes: the shape functions reproduce the
/// linear field B x exactly, so the load is the consistent scalar mass times its nodal values,
/// f(6i+A) = sum_j m_ij (B x_j)_A.
Eigen::MatrixXd centrifugal_loads(const FeModel& model) {
  Eigen::MatrixXd f = Eigen::MatrixXd::Zero(model.all_dofs(), 6);
  const int nodes = static_cast<int>(model.nodes.size());
  for (int p = 0; p < 6; ++p) {
    const Eigen::Matrix3d B = load_case_matrix(p);
    if (model.scalar_mass_only()) {
      Eigen::MatrixXd field(nodes, 3);  // row j: (B x_j)^T
      for (int j = 0; j < nodes; ++j) field.row(j) = (B * model.nodes[j]).transpose();
      const Eigen::MatrixXd load = model.scalar_mass * field;
      for (int i = 0; i < nodes; ++i)
        for (int A = 0; A < 3; ++A) f(6 * i + A, p) = load(i, A);
      continue;
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

SparseMatrix prestress_stiffness(const FeModel& model, const Eigen::VectorXd& u) {
  if (u.size() != model.all_dofs())
    throw Error("prestress stiffness: the displacement is not on all nodal DOF");
  std::vector<Eigen::Triplet<double>> triplets;
  // Beams: each element's axial force, times its geometric stiffness per unit force.
  for (const BeamElementRecord& e : model.beam_elements) {
    const Matrix12 T = local_from_global(e.axes);
    std::array<int, 12> dofs;
    for (int i = 0; i < 6; ++i) {
      dofs[i] = 6 * e.node1 + i;
      dofs[6 + i] = 6 * e.node2 + i;
    }
    Vector12 ue;
    for (int i = 0; i < 12; ++i) ue(i) = u(dofs[i]);
    const double N = axial_force(e.data, T * ue);
    const Matrix12 k = T.transpose() * local_geometric_stiffness(e.data, N) * T;
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j)
        if (k(i, j) != 0.0) triplets.emplace_back(dofs[i], dofs[j], k(i, j));
  }
  // Solids: each element's stress stiffness, the same scalar block on every translation component.
  for (std::size_t k = 0; k < model.solid_elements.size(); ++k) {
    const MeshElement& e = model.solid_elements[k];
    const int n = static_cast<int>(e.nodes.size());
    Eigen::Matrix<double, 3, Eigen::Dynamic> x(3, n);
    Eigen::VectorXd ue(3 * n);
    for (int i = 0; i < n; ++i) {
      x.col(i) = model.nodes[e.nodes[i]];
      ue.segment<3>(3 * i) = u.segment<3>(6 * e.nodes[i]);
    }
    const Eigen::MatrixXd kg =
        solid_stress_stiffness(parse_solid_type(e.type), x, model.solid_materials[k], ue);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int a = 0; a < 3; ++a) triplets.emplace_back(6 * e.nodes[i] + a, 6 * e.nodes[j] + a, kg(i, j));
  }
  SparseMatrix all(model.all_dofs(), model.all_dofs());
  all.setFromTriplets(triplets.begin(), triplets.end());
  return all;
}

std::array<SparseMatrix, 6> centrifugal_geometric_stiffness(const FeModel& model, const SparseMatrix& K,
                                                            const SparseMatrix& M, bool lower,
                                                            int rigid_body_modes, Ordering ordering) {
  if (model.beam_elements.empty() && model.solid_elements.empty()) {
    throw Error("geometric stiffening: the model (" + model.element_kind +
                ") holds no beam or solid element records (volume models keep them only when the "
                "reduction asks for geometric_stiffening)");
  }
  const Eigen::MatrixXd loads = model.transform.transpose() * centrifugal_loads(model);
  const Eigen::MatrixXd phi_r = free_rigid_body_modes(model, M, lower, rigid_body_modes);
  const Eigen::MatrixXd u = model.transform * inertia_relief_solve(K, M, lower, loads, phi_r, ordering);
  std::array<SparseMatrix, 6> out;
  for (int p = 0; p < 6; ++p) {
    const SparseMatrix all = prestress_stiffness(model, u.col(p));
    out[p] = model.transform.transpose() * all * model.transform;
  }
  return out;
}

SparseMatrix preload_geometric_stiffness(const FeModel& model, const SparseMatrix& K, const SparseMatrix& M,
                                         bool lower, int rigid_body_modes, Ordering ordering,
                                         const Eigen::VectorXd& load) {
  if (model.beam_elements.empty() && model.solid_elements.empty())
    throw Error("preload: the model (" + model.element_kind + ") holds no beam or solid element records");
  const Eigen::MatrixXd f = model.transform.transpose() * load;
  const Eigen::MatrixXd phi_r = free_rigid_body_modes(model, M, lower, rigid_body_modes);
  const Eigen::VectorXd u = model.transform * inertia_relief_solve(K, M, lower, f, phi_r, ordering).col(0);
  return model.transform.transpose() * prestress_stiffness(model, u) * model.transform;
}

}  // namespace nvh::condense
