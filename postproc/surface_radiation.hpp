#pragma once
// Normal surface velocity of a flexible body and its equivalent radiated power (docs/postproc.md
// section 4.5).
//
// A flexible body's elastic motion is u(x, t) = Phi(x) eta(t) in its floating frame (docs/scene-flexible.md),
// so the normal velocity of surface node k, relative to that frame, is the modal superposition
//   v_n,k(t) = n_k . (Phi_k eta'(t)) = sum_j Psi_kj eta'_j(t),   Psi_kj = n_k . Phi_k,j             (1)
// with n_k the outward unit normal and Phi_k,j the translation of node k per unit of coordinate j
// (/surface/shape of docs/hdf5-format.md). The motion of the frame itself (the block rocking on its mounts)
// adds, with v_O the frame origin's velocity and omega the angular velocity, both in body axes,
//   v_n,k^rigid = n_k . (v_O + omega x r_k) = n_k . v_O + (r_k x n_k) . omega                       (1a)
// (r_k the undeformed position in the component frame; the deflection's share of the lever arm is neglected),
// linear in six "rigid coordinates" (v_O, omega): the same superposition with six more columns of Psi.
//
// Its one-sided power spectral density per node by Welch's method (the same segments, windows and
// scaling as postproc spectrum, Heinzel, Ruediger, Schilling 2002, eq. 24):
//   PSD_k(f_i) = c_i <|V_k[i]|^2> / (f_s S2),   V_k[i] = sum_j Psi_kj H_j[i]                       (2)
// where H_j is the DFT of the windowed segment of eta'_j: by linearity of the DFT, (2) is the DFT of the
// windowed v_n,k, formed in modal space (one FFT per mode, not per node).
//
// The equivalent radiated power (ERP: the power the surface would radiate with radiation efficiency 1;
// the radiation efficiency sigma = W / (rho c S <v_n^2>) of Fahy & Gardonio 2007, "Sound and Structural
// Vibration", 2nd ed., chapter 3, set to 1 node by node):
//   ERP = rho c sum_k A_k <v_n,k^2>,   so per unit frequency  ERP'(f) = rho c sum_k A_k PSD_k(f)      (3)
// which for a harmonic velocity of peak amplitude v_hat is the familiar 1/2 rho c sum_k A_k |v_hat_k|^2.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/superelement.hpp"
#include "postproc/spectrum.hpp"
#include "postproc/window.hpp"

namespace nvh::postproc {

/// Dry air at 20 C and 101.325 kPa: density (kg/m^3) and speed of sound (m/s), as ideal gas:
/// rho = p / (R_s T) = 101325 / (287.05 x 293.15) = 1.204; c = 331.3 sqrt(1 + 20 / 273.15) = 343.2.
inline constexpr double kAirDensity = 1.204;
inline constexpr double kAirSoundSpeed = 343.2;

/// Psi of eq. (1) for the surface nodes (nodes x modes): the first `modes` coordinates of /surface/shape.
/// Error if the export has fewer coordinates.
Eigen::MatrixXd surface_normal_shapes(const SurfaceExport& surface, int modes);

/// Psi of eq. (1) for observation points with normals (volume components' /observe/normal): n_p . the
/// translation rows of /observe/shape. Empty if the points carry no normals.
Eigen::MatrixXd observer_normal_shapes(const PointSet& observers, int modes);

/// The six columns of eq. (1a) per point (points x 6): [n_k, r_k x n_k] for (v_O, omega) in body axes.
Eigen::MatrixXd rigid_normal_shapes(const Eigen::MatrixXd& position, const Eigen::MatrixXd& normal);

/// (v_O, omega) in body axes (6) from solve's frame origin velocity and angular velocity (global axes) and
/// Euler parameters p = [e0, e1, e2, e3] (body -> global): A^T v, A^T omega with
/// A(p) = (2 e0^2 - 1) I + 2 (e e^T + e0 e~) (Nikravesh 1988, eq. 6.19; solve/rotation.hpp).
Eigen::Matrix<double, 6, 1> body_frame_velocity(const Eigen::Vector3d& velocity, const Eigen::Vector3d& omega,
                                                const Eigen::Vector4d& euler_parameters);

/// v_n of eq. (1) at every sample: (samples x points) = eta' (samples x modes) Psi^T.
Eigen::MatrixXd normal_velocity(const Eigen::MatrixXd& modal_velocities,
                                const Eigen::MatrixXd& normal_shapes);

/// Welch PSD of the normal velocity of every point (eq. 2), fed block by block with modal velocities.
class NormalVelocityWelch {
 public:
  /// `normal_shapes`: Psi (points x modes); `segment_length` N samples, `overlap` r in [0, 1).
  NormalVelocityWelch(double sample_rate_hz, int segment_length, WindowKind window, double overlap,
                      Eigen::MatrixXd normal_shapes);
  /// Consecutive samples of the modal velocities: rows are samples, columns modes.
  void push(const Eigen::MatrixXd& modal_velocities);
  std::int64_t averages() const { return averages_; }
  Eigen::VectorXd frequency_hz() const;
  /// One-sided PSD per (bin, point), (m/s)^2/Hz when eta' is in coordinates/s and Psi in m/coordinate.
  Eigen::MatrixXd psd() const;
  double resolution_hz() const { return fs_ / plan_.size(); }
  /// Equivalent noise bandwidth of a bin, Hz: PSD x enbw is the amplitude-correct mean square of a tone.
  double enbw_hz() const { return window_.nenbw_bins() * fs_ / plan_.size(); }
  double overlap() const { return 1.0 - static_cast<double>(hop_) / plan_.size(); }
  int segment_length() const { return plan_.size(); }

 private:
  void process_segment(std::int64_t first_row);
  double fs_;
  Window window_;
  FftPlan plan_;
  int hop_;
  Eigen::MatrixXd psi_t_;        // Psi^T (modes x points)
  std::vector<double> pending_;  // samples not yet consumed, row-major (samples x modes)
  std::int64_t pending_rows_ = 0;
  Eigen::MatrixXd h_re_, h_im_;  // DFT of the windowed segment per mode (bins x modes)
  Eigen::MatrixXd v_re_, v_im_;  // DFT of the normal velocity of a block of points (bins x block)
  Eigen::MatrixXd power_sum_;    // sum over segments of |V|^2 (bins x points)
  std::int64_t averages_ = 0;
};

/// ERP per unit frequency, eq. (3): rho c sum_k A_k PSD_k over the points `nodes` (columns of `psd`), W/Hz.
Eigen::VectorXd erp_density(const Eigen::MatrixXd& psd, const Eigen::VectorXd& area, double rho_c,
                            const std::vector<Eigen::Index>& nodes);

/// The area-weighted mean of the velocity PSD over `nodes`: sum A_k PSD_k / sum A_k, (m/s)^2/Hz.
Eigen::VectorXd area_mean_psd(const Eigen::MatrixXd& psd, const Eigen::VectorXd& area,
                              const std::vector<Eigen::Index>& nodes);

/// A surface region: the nodes inside an axis-parallel box of the component's axes (bounds included).
struct SurfaceRegion {
  std::string name;
  Eigen::Vector3d lower, upper;  ///< m
};

/// "NAME=xmin,ymin,zmin,xmax,ymax,zmax" (m); error naming the text and what was expected.
SurfaceRegion parse_region(const std::string& text);

/// Indices of the rows of `position` (points x 3) inside the region's box.
std::vector<Eigen::Index> nodes_in_region(const Eigen::MatrixXd& position, const SurfaceRegion& region);

}  // namespace nvh::postproc
