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

RigidBodyInertia rigid_body_inertia(const FeModel& model) {
  const Eigen::MatrixXd R = model.rigid_body_field();
  const Eigen::Matrix<double, 6, 6> rigid_mass = R.transpose() * (model.mass_all * R);
  return rigid_body_inertia(rigid_mass);
}

ModalInvariants modal_invariants(const FeModel& model, const Eigen::MatrixXd& shapes) {
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
