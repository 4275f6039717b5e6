#pragma once
// Reduction of a structural model (K, M on its free DOF) to a small basis u = B q:
//
// - free-free (or supported) modal: B = the elastic normal modes up to fmax (or N of them); the
//   rigid-body modes are separated and left to the floating frame of reference.
// - Craig-Bampton (Craig and Bampton, AIAA J. 6(7), 1968): boundary (interface) DOF kept physical,
//   constraint modes Psi = -K_ii^-1 K_ib from one sparse Cholesky factorization with many right-hand sides,
//   plus the fixed-interface normal modes of (K_ii, M_ii) up to fmax:
//       B = [ I    0     ]   (rows: boundary DOF)
//           [ Psi  Phi_i ]   (rows: interior DOF)
// - Guyan (Guyan, AIAA J. 3(2), 1965): the constraint modes only.
//
// With `orthonormalize` the reduced eigenproblem K_r x = lambda M_r x is solved and the basis rotated
// onto its eigenvectors (B <- B X, rigid-body ones dropped), so every coordinate is a mode of the
// reduced, unconstrained system with M_r = I and K_r = diag(omega^2), as Adams and RecurDyn do.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <string>
#include <vector>

#include "common/log.hpp"
#include "condense/component.hpp"
#include "condense/eigensolver.hpp"
#include "condense/frf_error.hpp"

namespace nvh::condense {

struct ReductionInput {
  /// K and M on the free DOF. The modal reduction hands them over to the eigen-solve, which gives their
  /// storage back before its factorization (large solids: the peak memory): after reduce() they are
  /// empty then.
  SparseMatrix stiffness;
  SparseMatrix mass;
  /// K and M hold their lower triangles only (modal reduction only: Craig-Bampton needs both).
  bool lower_triangles = false;
  /// Linear constraints C u = 0 on the free DOF (m x n; distributing couplings in multiplier form,
  /// fe_model.hpp), or empty. Craig-Bampton and Guyan only, without the error estimate (band).
  SparseMatrix constraints;
  std::vector<int> boundary_dofs;           ///< free-DOF indices kept physical (Craig-Bampton, Guyan)
  std::vector<std::string> boundary_names;  ///< one per boundary DOF, e.g. "main1.rx"
  int rigid_body_modes = 0;                 ///< how many zero-frequency modes the unsupported model has
  ReductionSettings settings;
  EigenBackend backend = EigenBackend::kBlockLanczos;
  /// kLobpcg: its preconditioner's coarse space (volume components of C3D10 elements); see eigensolver.hpp.
  std::shared_ptr<const CoarseSpace> coarse_space;
  EigenProgress progress;               ///< optional, handed to the eigen-solves
  Ordering ordering = Ordering::kAuto;  ///< fill-reducing ordering of every factorization
  /// Craig-Bampton: unit loads (free DOF x k, one per column) whose static response the basis must hold:
  /// load_residual_vectors (reduction.cpp) adds it; empty: none. Named for the log.
  Eigen::MatrixXd residual_loads;
  std::vector<std::string> residual_load_names;
  /// Length l that scales rotations in the error estimate (frf_error.hpp), m: the model's size.
  double length_scale = 1.0;
};

struct ReducedModel {
  Eigen::MatrixXd basis;      ///< n_free x m: u = basis * q
  Eigen::MatrixXd mass;       ///< m x m: basis^T M basis
  Eigen::MatrixXd stiffness;  ///< m x m: basis^T K basis
  Eigen::MatrixXd damping;    ///< m x m: modal damping, 2 zeta omega on each elastic mode
  /// Elastic eigenfrequencies of the reduced system (K_r, M_r), ascending, Hz. For orthonormalized and
  /// modal bases these are the frequencies of the coordinates themselves.
  Eigen::VectorXd frequency_hz;
  /// What each coordinate is: "mode 3", "main1.x", "fixed-interface mode 2".
  std::vector<std::string> coordinates;
  /// Static-correction vectors in the basis: residual modes (modal) or residual vectors (Craig-Bampton).
  int static_correction = 0;
  /// Rigid-body modes removed from the basis (modal, orthonormalized) or still contained in it (raw
  /// Craig-Bampton and Guyan of an unsupported component).
  int rigid_body_modes_removed = 0;
  int rigid_body_modes_contained = 0;
  /// Fixed-interface frequencies (Craig-Bampton), Hz, for information.
  Eigen::VectorXd fixed_interface_hz;
  /// Largest relative residual of the full-model eigen-solve.
  double max_residual = 0.0;
  /// The sparse factorizations (eigen-solve, constraint modes): ordering, fill, time.
  FactorStats factor;
  /// Wall time of the eigen-solves' iterations (without their factorizations), s.
  double eigen_seconds = 0.0;
  /// Solves with the factorization in the eigen-solves (each streams the whole factor).
  int eigen_solves = 0;
  /// The eigensolver that found the modes: the one asked for, except that a lobpcg Craig-Bampton with an
  /// error estimate or residual vectors factors K_ii and finds them by spectra on that factor.
  EigenBackend backend = EigenBackend::kBlockLanczos;
  /// With settings.band_hz: the estimated receptance error at the interfaces in the band.
  FrfErrorEstimate frf_error;
  /// The cut-off of the kept modes, Hz: fmax as given or chosen from the band (0: a count was given).
  double cutoff_hz = 0.0;
  /// With the band and no count: the cut-offs tried (Hz) and their estimated errors, in order.
  std::vector<std::pair<double, double>> cutoff_passes;
};

/// nvh::Error when fmax lies below the first (elastic or fixed-interface) mode, the interior is not
/// restrained by the boundary DOF (a mechanism), or a method needs interfaces that the model lacks.
ReducedModel reduce(ReductionInput& input, const Logger& log);

}  // namespace nvh::condense
