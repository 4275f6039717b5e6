#include "postproc/surface_motion.hpp"

#include <string>

#include "common/error.hpp"

namespace nvh::postproc {

Eigen::Matrix3d euler_rotation(const Eigen::Vector4d& euler_parameters) {
  const double e0 = euler_parameters[0];
  const Eigen::Vector3d e = euler_parameters.tail<3>();
  Eigen::Matrix3d skew;
  skew << 0, -e.z(), e.y(), e.z(), 0, -e.x(), -e.y(), e.x(), 0;
  return (2 * e0 * e0 - 1) * Eigen::Matrix3d::Identity() + 2 * (e * e.transpose() + e0 * skew);
}

Eigen::MatrixXd elastic_displacement(const SurfaceExport& surface, const Eigen::VectorXd& eta) {
  const auto nodes = static_cast<Eigen::Index>(surface.labels.size());
  const auto per_node =
      nodes > 0 ? static_cast<Eigen::Index>(surface.shape.size() / static_cast<std::size_t>(3 * nodes)) : 0;
  if (eta.size() > per_node)
    throw Error("surface: " + std::to_string(eta.size()) +
                " modal coordinates given, the surface export holds " + std::to_string(per_node));
  // /surface/shape is (nodes, 3, n) row-major: the rows (k, d) of a (3 nodes x n) row-major matrix.
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Map<const RowMajor> phi(surface.shape.data(), 3 * nodes, per_node);
  const Eigen::VectorXd u = phi.leftCols(eta.size()) * eta;  // (k, d) at 3 k + d
  return Eigen::Map<const RowMajor>(u.data(), nodes, 3);
}

Eigen::MatrixXd rigid_motion_displacement(const Eigen::MatrixXd& position, const Eigen::MatrixXd& elastic,
                                          const Eigen::Vector3d& origin,
                                          const Eigen::Vector4d& euler_parameters) {
  const Eigen::Matrix3d a = euler_rotation(euler_parameters);
  Eigen::MatrixXd d = (position + elastic) * a.transpose();  // rows: (A (x + u))^T
  d.rowwise() += origin.transpose();
  return d - position;
}

std::vector<std::int64_t> select_frames(std::int64_t first, std::int64_t last, std::int64_t max_frames) {
  if (last < first || max_frames < 1) return {};
  const std::int64_t samples = last - first + 1;
  std::int64_t stride = 1;
  // With stride s the frames number floor((samples - 1) / s) + 1; the smallest s keeping that <= max_frames:
  if (samples > max_frames) stride = (samples - 1) / max_frames + 1;
  std::vector<std::int64_t> frames;
  for (std::int64_t i = first; i <= last && static_cast<std::int64_t>(frames.size()) < max_frames;
       i += stride)
    frames.push_back(i);
  return frames;
}

}  // namespace nvh::postproc
