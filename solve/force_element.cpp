// Helpers shared by force elements (force_element.hpp).
#include "solve/force_element.hpp"

namespace nvh::solve {

void jacobian_at_i(const ElementInput& in, ElementJacobian& jac, const Eigen::Ref<const Eigen::MatrixXd>& d_force,
                   const Eigen::Ref<const Eigen::MatrixXd>& d_torque, const Vec3& force) {
  auto& m = jac.matrix;
  const int cols = static_cast<int>(d_force.cols());
  m.block(0, 0, 3, cols) += d_force;
  m.block(3, 0, 3, cols) += d_torque;
  if (in.markers.size() < 2) return;
  // Marker j: -F and -T - d x F with d = p_i - p_j; d(d x F) = d~ dF - F~ (dp_i - dp_j).
  const Vec3 d = in.markers[0].position - in.markers[1].position;
  m.block(6, 0, 3, cols) -= d_force;
  m.block(9, 0, 3, cols) -= d_torque;
  m.block(9, 0, 3, cols).noalias() -= skew(d) * d_force;  // into place: no temporary on the heap
  const Mat3 f = skew(force);
  m.block<3, 3>(9, 0) += f;    // dp_i
  m.block<3, 3>(9, 12) -= f;   // dp_j
}

}  // namespace nvh::solve
