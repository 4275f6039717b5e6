#pragma once
// How far a reduced model's frequency response at its connection points lies from the full model's, in
// the band the user asks for: an a-posteriori estimate from full-model solves at sampled frequencies.
//
// Compared is the undamped receptance (dynamic flexibility) at the interface DOF b,
//     G(w) = E^T (K - w^2 M)^-1 E           (full model, E: unit columns at the interface DOF)
//     G_r(w) = E^T B (K_r - w^2 M_r)^-1 B^T E  (reduced model, basis B)
// at frequencies between the reduced model's resonances in (0, band] (frf_sample_frequencies). Rotations
// are scaled by a length l (rotation x l, moment / l), so every entry is in m/N and a matrix norm means
// the same for a beam end and a bore. The error of a connection point is the relative Frobenius norm of its
// driving-point block, ||G_r,pp - G_pp|| / ||G_pp - G_rigid,pp||, and that of the whole interface the same
// on all of G. The rigid-body part G_rigid = Phi_r,b Phi_r,b^T / (0 - w^2) is exact in both models (the
// floating frame carries it), so the denominator is the elastic response: the estimate is not flattered by
// the rigid-body motion of a free part at low frequency.
//
// The full-model solves need no indefinite factorization (K - w^2 M is indefinite above the first mode).
// With the exact eigenpairs (Phi, Lambda) of (A, B) below a bound w_c > w - the modes the reduction has
// computed anyway - the solution splits into
//     X = Phi (Lambda - w^2)^-1 Phi^T R  +  Y,    Y in the B-orthogonal complement of Phi,
// and on that complement A - w^2 B is positive definite (its eigenvalues there exceed w_c^2 - w^2 > 0), so
// Y follows from conjugate gradients preconditioned with a Cholesky factor of A - sigma B (sigma <= 0)
// and projected onto the complement: deflated PCG (Saad, Yeung, Erhel and Guyomarc'h, SIAM J. Sci.
// Comput. 21 (2000) 1909). The preconditioned operator's eigenvalues lie in
// [(w_c^2 - w^2) / (w_c^2 - sigma), 1), so it converges in a few iterations when w_c is 1.25 w or more.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "condense/constrained_factor.hpp"

namespace nvh::condense {

/// The estimate, as written to /reduction_error of the superelement file (docs/hdf5-format.md).
struct FrfErrorEstimate {
  double band_hz = 0.0;             ///< upper edge of the band, Hz
  double length_scale = 1.0;        ///< l of the rotation scaling, m
  Eigen::VectorXd frequency_hz;     ///< the sampled frequencies, Hz
  std::vector<std::string> points;  ///< connection points (interfaces)
  Eigen::MatrixXd point_error;      ///< points x samples: relative error of the driving-point block
  Eigen::VectorXd interface_error;  ///< samples: relative error of the whole interface receptance
  int solver_iterations = 0;        ///< deflated-PCG iterations, summed over the samples
  double cost_seconds = 0.0;        ///< wall time of the estimate

  bool empty() const { return frequency_hz.size() == 0; }
  /// The largest error over the samples, of the points and the whole interface.
  double max_error() const;
  /// The largest error of point p and the frequency (Hz) where it occurs.
  std::pair<double, double> point_max(int p) const;
};

/// About `count` frequencies in (0, band), none near a resonance: the band is cut at the resonances below
/// it into intervals, each interval gets samples in proportion to its width (at least one), at equal steps
/// below the first resonance and at equal ratios between two, so every sample lies half a step (or half a
/// ratio) from its nearest resonance. Intervals narrower than 5 % (close pairs of modes, the band's edge
/// just above a resonance) get none: there the receptance is the resonant modes' alone and its error
/// that of their frequencies. Hz in, Hz out, ascending.
std::vector<double> frf_sample_frequencies(double band_hz, const Eigen::VectorXd& resonances_hz, int count);

/// Solves (A - w^2 B) X = R by spectral deflation (see the file comment). A and B symmetric, whole or as
/// lower triangles; phi (n x m) B-orthonormal eigenvectors with eigenvalues lambda holding every
/// eigenvalue below `bound` (rad^2/s^2; pass lambda_next or a value known to lie below it); the
/// preconditioner a factorization of A - sigma B. Borrows all of them.
class DeflatedShiftedSolver {
 public:
  DeflatedShiftedSolver(const SparseMatrix& a, const SparseMatrix& b, bool lower, const Eigen::MatrixXd& phi,
                        const Eigen::VectorXd& lambda, double bound, const ConstrainedFactor& preconditioner);

  /// X for w^2 = omega2 < bound. nvh::Error if the complement is not positive definite (a mode below w
  /// missing from phi) or the iteration does not converge to `tolerance` (relative residual).
  Eigen::MatrixXd solve(double omega2, const Eigen::MatrixXd& rhs, double tolerance = 1e-10);
  /// The same with its own w^2 per column (several frequencies in one block: each iteration's
  /// preconditioner solve takes all their right-hand sides at once, which the supernodal factor does
  /// several times faster per column than one at a time).
  Eigen::MatrixXd solve(const Eigen::VectorXd& omega2, const Eigen::MatrixXd& rhs, double tolerance = 1e-10);
  /// Iterations of the last solve (of its slowest column).
  int iterations() const { return iterations_; }
  double bound() const { return bound_; }
  Eigen::Index rows() const { return a_rows_.rows(); }

 private:
  using RowMajorSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  using RowMajorDense = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  /// A x and B x for many columns: row-major copies (both triangles), so each row's product runs over
  /// contiguous rows of x, vectorized across the right-hand sides (the column-major product scatters
  /// one column at a time and was most of the estimate's time on a 47k-DOF solid).
  RowMajorSparse a_rows_;
  RowMajorSparse b_rows_;
  const Eigen::MatrixXd& phi_;
  Eigen::VectorXd lambda_;
  Eigen::MatrixXd b_phi_;  ///< B Phi
  double bound_;
  const ConstrainedFactor& preconditioner_;
  int iterations_ = 0;
};

/// Compare full and reduced receptances sampled at `frequency_hz`: full[s], reduced[s], rigid[s] are the
/// nb x nb receptances at the interface DOF (rigid: the rigid-body part of both, zero for a supported
/// part). dof_names ("main1.rx") group the DOF into points by the name before the last '.'; DOF ending in
/// .rx/.ry/.rz are rotations. Fills everything of the estimate but the cost.
FrfErrorEstimate compare_receptances(double band_hz, const std::vector<double>& frequency_hz,
                                     const std::vector<Eigen::MatrixXd>& full,
                                     const std::vector<Eigen::MatrixXd>& reduced,
                                     const std::vector<Eigen::MatrixXd>& rigid,
                                     const std::vector<std::string>& dof_names, double length_scale);

}  // namespace nvh::condense
