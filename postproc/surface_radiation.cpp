#include "postproc/surface_radiation.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "postproc/surface_motion.hpp"

namespace nvh::postproc {

Eigen::MatrixXd surface_normal_shapes(const SurfaceExport& surface, int modes) {
  const auto nodes = static_cast<Eigen::Index>(surface.labels.size());
  const std::size_t per_node = nodes > 0 ? surface.shape.size() / static_cast<std::size_t>(3 * nodes) : 0;
  if (modes < 0 || static_cast<std::size_t>(modes) > per_node)
    throw Error("surface: " + std::to_string(modes) + " modal coordinates asked, the surface export holds " +
                std::to_string(per_node));
  Eigen::MatrixXd psi(nodes, modes);
  // /surface/shape is (nodes, 3, n) row-major: element (k, d, j) at (k 3 + d) n + j.
  for (Eigen::Index k = 0; k < nodes; ++k)
    for (int j = 0; j < modes; ++j) {
      double v = 0.0;
      for (int d = 0; d < 3; ++d)
        v += surface.normal(k, d) * surface.shape[(static_cast<std::size_t>(k) * 3 + d) * per_node + j];
      psi(k, j) = v;
    }
  return psi;
}

Eigen::MatrixXd observer_normal_shapes(const PointSet& observers, int modes) {
  const auto count = static_cast<Eigen::Index>(observers.shapes.size());
  if (observers.normals.rows() != count || count == 0) return {};
  Eigen::MatrixXd psi(count, modes);
  for (Eigen::Index p = 0; p < count; ++p) {
    const Eigen::MatrixXd& shape = observers.shapes[static_cast<std::size_t>(p)];
    if (shape.cols() < modes)
      throw Error("observation point '" + observers.names[static_cast<std::size_t>(p)] + "': " +
                  std::to_string(shape.cols()) + " coordinates, expected at least " + std::to_string(modes));
    psi.row(p) = observers.normals.row(p) * shape.topLeftCorner(3, modes);
  }
  return psi;
}

Eigen::MatrixXd rigid_normal_shapes(const Eigen::MatrixXd& position, const Eigen::MatrixXd& normal) {
  Eigen::MatrixXd psi(position.rows(), 6);
  for (Eigen::Index k = 0; k < position.rows(); ++k) {
    const Eigen::Vector3d r = position.row(k).transpose(), n = normal.row(k).transpose();
    psi.block<1, 3>(k, 0) = n.transpose();
    psi.block<1, 3>(k, 3) = r.cross(n).transpose();
  }
  return psi;
}

Eigen::Matrix<double, 6, 1> body_frame_velocity(const Eigen::Vector3d& velocity, const Eigen::Vector3d& omega,
                                                const Eigen::Vector4d& euler_parameters) {
  const Eigen::Matrix3d a = euler_rotation(euler_parameters);
  Eigen::Matrix<double, 6, 1> out;
  out << a.transpose() * velocity, a.transpose() * omega;
  return out;
}

Eigen::MatrixXd normal_velocity(const Eigen::MatrixXd& modal_velocities,
                                const Eigen::MatrixXd& normal_shapes) {
  return modal_velocities * normal_shapes.transpose();
}

NormalVelocityWelch::NormalVelocityWelch(double sample_rate_hz, int segment_length, WindowKind window,
                                         double overlap, Eigen::MatrixXd normal_shapes)
    : fs_(sample_rate_hz),
      window_(make_window(window, segment_length)),
      plan_(segment_length),
      hop_(std::max(1, static_cast<int>(std::lround(segment_length * (1.0 - overlap))))),
      psi_t_(normal_shapes.transpose()) {
  if (!(overlap >= 0.0 && overlap < 1.0))
    throw Error("--overlap " + std::to_string(overlap) + ": expected a fraction in [0, 1)");
  const Eigen::Index bins = segment_length / 2 + 1;
  h_re_.resize(bins, psi_t_.rows());
  h_im_.resize(bins, psi_t_.rows());
  power_sum_ = Eigen::MatrixXd::Zero(bins, psi_t_.cols());
}

void NormalVelocityWelch::push(const Eigen::MatrixXd& modal_velocities) {
  const Eigen::Index modes = psi_t_.rows();
  if (modal_velocities.cols() != modes)
    throw Error("surface velocity: " + std::to_string(modal_velocities.cols()) + " modal velocities given, " +
                std::to_string(modes) + " expected");
  for (Eigen::Index r = 0; r < modal_velocities.rows(); ++r)
    for (Eigen::Index j = 0; j < modes; ++j) pending_.push_back(modal_velocities(r, j));
  pending_rows_ += modal_velocities.rows();
  const int n = plan_.size();
  std::int64_t first = 0;
  while (pending_rows_ - first >= n) {
    process_segment(first);
    first += hop_;
  }
  if (first > 0) {
    const std::int64_t drop = std::min(first, pending_rows_);
    pending_.erase(pending_.begin(), pending_.begin() + drop * modes);
    pending_rows_ -= drop;
  }
}

void NormalVelocityWelch::process_segment(std::int64_t first_row) {
  const Eigen::Index modes = psi_t_.rows(), bins = h_re_.rows();
  const int n = plan_.size();
  double* in = plan_.input();
  for (Eigen::Index j = 0; j < modes; ++j) {
    for (int i = 0; i < n; ++i)
      in[i] = window_.w[static_cast<std::size_t>(i)] *
              pending_[static_cast<std::size_t>((first_row + i) * modes + j)];
    plan_.execute();
    const std::complex<double>* out = plan_.output();
    for (Eigen::Index k = 0; k < bins; ++k) {
      h_re_(k, j) = out[k].real();
      h_im_(k, j) = out[k].imag();
    }
  }
  // V = H Psi^T (eq. 2), real and imaginary parts as two real products, a block of points at a time so that
  // the temporaries stay small (bins x 1024) on a surface of many nodes.
  constexpr Eigen::Index kPoints = 1024;
  for (Eigen::Index p0 = 0; p0 < psi_t_.cols(); p0 += kPoints) {
    const Eigen::Index count = std::min(kPoints, psi_t_.cols() - p0);
    v_re_.noalias() = h_re_ * psi_t_.middleCols(p0, count);
    v_im_.noalias() = h_im_ * psi_t_.middleCols(p0, count);
    power_sum_.middleCols(p0, count).array() += v_re_.array().square() + v_im_.array().square();
  }
  ++averages_;
}

Eigen::VectorXd NormalVelocityWelch::frequency_hz() const {
  const int n = plan_.size();
  Eigen::VectorXd f(power_sum_.rows());
  for (Eigen::Index k = 0; k < f.size(); ++k) f[k] = fs_ * static_cast<double>(k) / n;
  return f;
}

Eigen::MatrixXd NormalVelocityWelch::psd() const {
  const int n = plan_.size();
  const Eigen::Index bins = power_sum_.rows();
  const double m = averages_ > 0 ? static_cast<double>(averages_) : 1.0;
  Eigen::MatrixXd p = power_sum_ / (m * fs_ * window_.sum_squares);
  // c_k = 2 inside (0, N/2), 1 at DC and (even N) Nyquist.
  for (Eigen::Index k = 1; k < bins; ++k)
    if (!(n % 2 == 0 && k == bins - 1)) p.row(k) *= 2.0;
  return p;
}

Eigen::VectorXd erp_density(const Eigen::MatrixXd& psd, const Eigen::VectorXd& area, double rho_c,
                            const std::vector<Eigen::Index>& nodes) {
  Eigen::VectorXd erp = Eigen::VectorXd::Zero(psd.rows());
  for (const Eigen::Index k : nodes) erp += area[k] * psd.col(k);
  return rho_c * erp;
}

Eigen::VectorXd area_mean_psd(const Eigen::MatrixXd& psd, const Eigen::VectorXd& area,
                              const std::vector<Eigen::Index>& nodes) {
  double total = 0.0;
  for (const Eigen::Index k : nodes) total += area[k];
  if (!(total > 0.0)) throw Error("surface region: zero area, no mean velocity");
  return erp_density(psd, area, 1.0, nodes) / total;
}

SurfaceRegion parse_region(const std::string& text) {
  const auto eq = text.find('=');
  const std::string expected = "expected NAME=xmin,ymin,zmin,xmax,ymax,zmax (m, the component's axes)";
  if (eq == std::string::npos || eq == 0) throw Error("--region '" + text + "': " + expected);
  SurfaceRegion region;
  region.name = text.substr(0, eq);
  std::vector<double> values;
  std::stringstream list(text.substr(eq + 1));
  std::string item;
  while (std::getline(list, item, ',')) {
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || item.find_first_not_of(" ", used) != std::string::npos || !std::isfinite(v))
      throw Error("--region '" + text + "': '" + item + "' is not a finite number; " + expected);
    values.push_back(v);
  }
  if (values.size() != 6)
    throw Error("--region '" + text + "': " + std::to_string(values.size()) + " numbers; " + expected);
  region.lower = Eigen::Vector3d(values[0], values[1], values[2]);
  region.upper = Eigen::Vector3d(values[3], values[4], values[5]);
  if ((region.lower.array() > region.upper.array()).any())
    throw Error("--region '" + text + "': a lower bound above its upper bound; " + expected);
  return region;
}

std::vector<Eigen::Index> nodes_in_region(const Eigen::MatrixXd& position, const SurfaceRegion& region) {
  std::vector<Eigen::Index> nodes;
  for (Eigen::Index k = 0; k < position.rows(); ++k) {
    const Eigen::Vector3d p = position.row(k).transpose();
    if ((p.array() >= region.lower.array()).all() && (p.array() <= region.upper.array()).all())
      nodes.push_back(k);
  }
  return nodes;
}

}  // namespace nvh::postproc
