#include "condense/invariants.hpp"

namespace nvh::condense {

RigidBodyInertia rigid_body_inertia(const Eigen::Matrix<double, 6, 6>& rigid_mass) {
  // R^T M R = [ m I      -m [c]x ]     ([c]x: the cross-product matrix of c)
  //           [ m [c]x    J_o    ]     (J_o: inertia tensor about the origin)
  RigidBodyInertia r;
  r.mass = rigid_mass.block<3, 3>(0, 0).trace() / 3.0;
  const Eigen::Matrix3d mc_cross = rigid_mass.block<3, 3>(3, 0);
  const Eigen::Vector3d mc(mc_cross(2, 1), mc_cross(0, 2), mc_cross(1, 0));
  r.center_of_mass = r.mass > 0.0 ? Eigen::Vector3d(mc / r.mass) : Eigen::Vector3d::Zero();
  r.inertia_origin = rigid_mass.block<3, 3>(3, 3);
  r.inertia_origin = 0.5 * (r.inertia_origin + r.inertia_origin.transpose()).eval();
  // Parallel axis theorem: J_o = J_c + m (|c|^2 I - c c^T).
  const Eigen::Vector3d& c = r.center_of_mass;
  r.inertia = r.inertia_origin - r.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  // J_o = tr(I) 1 - I for I = int rho x x^T, so I = tr(J_o)/2 1 - J_o.
  r.second_moment = 0.5 * r.inertia_origin.trace() * Eigen::Matrix3d::Identity() - r.inertia_origin;
  return r;
}

namespace {

/// The node coordinates as columns x, y, z (N x 3).
Eigen::MatrixXd coordinates(const FeModel& model) {
  Eigen::MatrixXd X(static_cast<Eigen::Index>(model.nodes.size()), 3);
  for (std::size_t n = 0; n < model.nodes.size(); ++n) X.row(static_cast<Eigen::Index>(n)) = model.nodes[n];
  return X;
}

/// Volume models: R^T M_all R from the scalar mass m. With the moments of the interpolated position
/// (exact for isoparametric elements) m_tot = 1^T m 1, m c_k = 1^T m x_k and I_kl = x_k^T m x_l:
///   R^T M R = [ m_tot I    -m [c]x ],   J_o = tr(I) 1 - I.
///             [ m [c]x      J_o    ]
Eigen::Matrix<double, 6, 6> rigid_mass_from_scalar(const FeModel& model) {
  Eigen::MatrixXd Q(static_cast<Eigen::Index>(model.nodes.size()), 4);
  Q.col(0).setOnes();
  Q.rightCols(3) = coordinates(model);
  const Eigen::MatrixXd mQ = model.scalar_mass * Q;
  const Eigen::Matrix4d G = Q.transpose() * mQ;
  const Eigen::Vector3d first = G.block<3, 1>(1, 0);
  const Eigen::Matrix3d second = G.block<3, 3>(1, 1);
  Eigen::Matrix3d first_cross;
  first_cross << 0, -first.z(), first.y(), first.z(), 0, -first.x(), -first.y(), first.x(), 0;
  Eigen::Matrix<double, 6, 6> r;
  r.block<3, 3>(0, 0) = G(0, 0) * Eigen::Matrix3d::Identity();
  r.block<3, 3>(3, 0) = first_cross;
  r.block<3, 3>(0, 3) = -first_cross;
  r.block<3, 3>(3, 3) = second.trace() * Eigen::Matrix3d::Identity() - second;
  return r;
}

/// Volume models: the invariants of ModalInvariants from the scalar mass m and the translations U_a
/// (N x n: rows 6 i + a of the nodal shapes). With the interpolated position x_k (exact for
/// isoparametric elements) and p_k = m x_k:
///   S_bar_a = 1^T m U_a,   I_tilde_kl = p_k^T U_l,   S_rot = int rho x x S dV = eps_kbl I_tilde_bl,
///   S_kl = U_k^T m U_l.
ModalInvariants modal_invariants_from_scalar(const FeModel& model, const Eigen::MatrixXd& shapes) {
  const Eigen::Index N = static_cast<Eigen::Index>(model.nodes.size()), n = shapes.cols();
  // [U_x U_y U_z x y z] (N x (3 n + 3)) and its product with m, in one pass over m (row-major: each
  // entry m_ij adds a contiguous row of W).
  using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  RowMajorMatrix W(N, 3 * n + 3);
  for (int a = 0; a < 3; ++a) {
    W.middleCols(a * n, n) = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::Stride<Eigen::Dynamic, 6>>(
        shapes.data() + a, N, n, Eigen::Stride<Eigen::Dynamic, 6>(shapes.outerStride(), 6));
  }
  W.rightCols(3) = coordinates(model);
  const RowMajorMatrix mW = model.scalar_mass * W;
  const auto U = [&](int a) { return W.middleCols(a * n, n); };
  const auto mU = [&](int a) { return mW.middleCols(a * n, n); };
  const auto p = [&](int k) { return mW.col(3 * n + k); };

  ModalInvariants inv;
  inv.translational.resize(3, n);
  for (int a = 0; a < 3; ++a) inv.translational.row(a) = mU(a).colwise().sum();
  inv.position.resize(9);
  inv.quadratic.resize(9);
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < 3; ++l) inv.position[3 * k + l] = U(l).transpose() * p(k);
    // S_kl = S_lk^T (m is symmetric): 6 products instead of 9.
    for (int l = k; l < 3; ++l) {
      inv.quadratic[3 * k + l] = U(k).transpose() * mU(l);
      if (l != k) inv.quadratic[3 * l + k] = inv.quadratic[3 * k + l].transpose();
    }
  }
  // (x x S)_k = x_{k+1} S_{k+2} - x_{k+2} S_{k+1}.
  inv.rotational.resize(3, n);
  for (int k = 0; k < 3; ++k) {
    const int b = (k + 1) % 3, l = (k + 2) % 3;
    inv.rotational.row(k) = (inv.position[3 * b + l] - inv.position[3 * l + b]).transpose();
  }
  return inv;
}

}  // namespace

RigidBodyInertia rigid_body_inertia(const FeModel& model) {
  if (model.scalar_mass_only()) return rigid_body_inertia(rigid_mass_from_scalar(model));
  const Eigen::MatrixXd R = model.rigid_body_field();
  const Eigen::Matrix<double, 6, 6> rigid_mass = R.transpose() * (model.mass_all * R);
  return rigid_body_inertia(rigid_mass);
}

ModalInvariants modal_invariants(const FeModel& model, const Eigen::MatrixXd& shapes) {
  if (model.scalar_mass_only()) return modal_invariants_from_scalar(model, shapes);
  const Eigen::MatrixXd R = model.rigid_body_field();
  const Eigen::MatrixXd MS = model.mass_all * shapes;  // 6N x n
  ModalInvariants inv;
  // Rigid translations and rotations are represented exactly by the beam's interpolation, so
  // int rho e_k . S dV = R_k^T M S and int rho (x x S)_k dV = R_{3+k}^T M S.
  inv.translational = R.leftCols(3).transpose() * MS;
  inv.rotational = R.rightCols(3).transpose() * MS;
  inv.position.resize(9);
  inv.quadratic.resize(9);
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < 3; ++l) {
      inv.position[3 * k + l] = shapes.transpose() * model.position_moment_all.col(3 * k + l);
    }
    // S_kl = S_lk^T (the component mass matrices are pairwise transposes): 6 products instead of 9.
    for (int l = k; l < 3; ++l) {
      inv.quadratic[3 * k + l] = shapes.transpose() * (model.component_mass_all[k][l] * shapes);
      if (l != k) inv.quadratic[3 * l + k] = inv.quadratic[3 * k + l].transpose();
    }
  }
  return inv;
}

}  // namespace nvh::condense
