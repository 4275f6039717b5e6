#pragma once
// Displacement of a flexible body's surface nodes (docs/postproc.md section 3.6, `postproc animate`).
//
// In the floating frame of the body (docs/scene-flexible.md) the elastic displacement of surface node k is
// the modal superposition
//   u_k(t) = Phi_k eta(t) = sum_j Phi_k,j eta_j(t)                                                   (1)
// with Phi_k,j the translation of node k per unit of coordinate j (/surface/shape of docs/hdf5-format.md)
// and eta the modal coordinates of solve's results. With the frame's rigid-body motion (origin r_O, rotation
// A(p) body -> global from the Euler parameters p) the node's global position is r_O + A (x_k + u_k), so its
// displacement from the undeformed surface x_k (component axes) is
//   d_k(t) = r_O + A (x_k + u_k) - x_k                                                               (2)
// and x_k + d_k places the deformed surface where it is in the scene.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "common/superelement.hpp"

namespace nvh::postproc {

/// A(p) = (2 e0^2 - 1) I + 2 (e e^T + e0 e~), body -> global, for Euler parameters p = [e0, e1, e2, e3]
/// (Nikravesh 1988, eq. 6.19; solve/rotation.hpp).
Eigen::Matrix3d euler_rotation(const Eigen::Vector4d& euler_parameters);

/// Eq. (1): u (nodes x 3, m) for the first eta.size() coordinates of /surface/shape. Error if the export
/// holds fewer.
Eigen::MatrixXd elastic_displacement(const SurfaceExport& surface, const Eigen::VectorXd& eta);

/// Eq. (2): d (nodes x 3, m, global axes) from the undeformed positions x (nodes x 3), the elastic
/// displacement u (nodes x 3, body axes), the frame origin r_O and its Euler parameters.
Eigen::MatrixXd rigid_motion_displacement(const Eigen::MatrixXd& position, const Eigen::MatrixXd& elastic,
                                          const Eigen::Vector3d& origin,
                                          const Eigen::Vector4d& euler_parameters);

/// Frames of an animation: the samples first, first + stride, ... <= last, at most `max_frames` of them, with
/// the smallest stride that keeps them within `max_frames` (so they are evenly spaced; the last sample is
/// a frame only if the stride reaches it).
std::vector<std::int64_t> select_frames(std::int64_t first, std::int64_t last, std::int64_t max_frames);

}  // namespace nvh::postproc
