#pragma once
// The generalized symmetric eigenproblem K x = lambda M x of structural dynamics (lambda = omega^2),
// for the lowest modes: K symmetric positive semi-definite (singular for a free-free body), M symmetric
// positive definite. Units: K in N/m (N m/rad), M in kg (kg m^2), lambda in rad^2/s^2.
//
// Backends:
// - kBlockLanczos (default): shift-invert block Lanczos (block_lanczos.hpp) on the factorization below,
//   a block of 6-12 vectors per solve (one reading of the factor for all of them).
// - kSpectra: shift-invert Lanczos (Spectra::SymGEigsShiftSolver) on a CHOLMOD supernodal Cholesky
//   factorization of K - sigma M with a negative shift sigma, so a singular (free-free) K factorizes and
//   the rigid-body modes (lambda = 0) are found like any other.
// - kArpack: ARPACK's dsaupd/dseupd in shift-invert mode 3 on the same factorization (for comparison).
// - kDense: Eigen's GeneralizedSelfAdjointEigenSolver on dense copies (small or reduced models, tests).
//
// With fmax_hz set, the request grows the number of modes until the highest one found lies above fmax,
// reusing the factorization. Every returned mode passes a residual check.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <functional>
#include <limits>
#include <memory>
#include <string>

#include "condense/constrained_factor.hpp"
#include "condense/p_multigrid.hpp"
#include "condense/sparse_cholesky.hpp"

namespace nvh::condense {

using SparseMatrix = Eigen::SparseMatrix<double>;  // column-major

enum class EigenBackend { kSpectra, kArpack, kDense, kLobpcg, kBlockLanczos };

/// Progress of an iterative solve: solves with the factorization done in the current Lanczos run, and
/// the number a run without restarts needs (its basis size). Called every few solves; the library
/// never prints, the caller decides (the CLI draws nvh::Progress).
using EigenProgress = std::function<void(int done, int expected)>;

/// Parse "block-lanczos" | "spectra" | "arpack" | "dense" | "lobpcg"; nvh::Error listing the choices
/// otherwise.
EigenBackend parse_eigen_backend(const std::string& name);
std::string to_string(EigenBackend backend);

struct EigenRequest {
  int modes = 0;         ///< the lowest `modes` eigenpairs (used when > 0)
  double fmax_hz = 0.0;  ///< or all eigenpairs with frequency <= fmax_hz (used when modes == 0)
  /// Shift sigma (rad^2/s^2, must be < 0). 0 = automatic: -(2 pi f_s)^2 with f_s = max(1 Hz, fmax/100),
  /// or from the matrices' diagonal when only `modes` is given.
  double shift = 0.0;
  EigenBackend backend = EigenBackend::kBlockLanczos;
  double tolerance = 1e-10;  ///< convergence tolerance of the Lanczos iteration
  /// Accept a mode if ||K x - lambda M x|| / (||K x|| + |lambda| ||M x|| + sqrt(eps) ||K||_1 ||x||) <= limit
  /// (the last term, the round-off floor of K x, keeps rigid modes - K x and lambda both round-off - from
  /// failing the check).
  double residual_limit = 1e-6;
  EigenProgress progress;               ///< optional
  Ordering ordering = Ordering::kAuto;  ///< fill-reducing ordering of the factorization
  /// Optional: a factorization of K itself, K positive definite (a Craig-Bampton interior). Then the
  /// shift is 0 and nothing is factorized; the caller has used it for its own solves with K. If it
  /// carries constraints C x = 0 (constrained_factor.hpp), the eigenpairs are those of K and M on the
  /// null space of C: K x - lambda M x = -C^T mu, C x = 0 (the residual check then measures the part
  /// of K x - lambda M x outside the range of C^T).
  std::shared_ptr<const ConstrainedFactor> stiffness_factor;
  /// K and M hold their lower triangles only (with the diagonal), exactly symmetric by construction.
  bool lower_triangles = false;
  /// kLobpcg: the coarse space of its preconditioner (p_multigrid.hpp; solids of C3D10 elements), required.
  std::shared_ptr<const CoarseSpace> coarse_space;
};

struct EigenResult {
  Eigen::VectorXd
      eigenvalues;          ///< lambda = omega^2, ascending (tiny negatives of rigid modes kept as computed)
  Eigen::MatrixXd vectors;  ///< columns M-orthonormal: X^T M X = I
  Eigen::VectorXd residuals;       ///< relative residual of each mode (see residual_limit)
  double shift = 0.0;              ///< the shift used (0 for kDense)
  int matrix_operations = 0;       ///< number of solves with the factorization (cost measure)
  FactorStats factor;              ///< ordering, fill and time of the factorization(s) (none for kDense)
  double iteration_seconds = 0.0;  ///< wall time of the Lanczos runs (or of the dense solve)
  /// fmax requests: the lowest eigenvalue found above fmax (NaN if none was), for messages such as
  /// "fmax lies below the first mode at ... Hz".
  double next_eigenvalue = std::numeric_limits<double>::quiet_NaN();
  /// Count requests: -1 if the count ends at a gap of the spectrum; otherwise it ends inside a group of
  /// equal eigenvalues (mode `modes` + 1, solved for as a guard, equals mode `modes` to 1e-8), and this
  /// is the group's first mode (0-based) - the modes kept of the group are an arbitrary part of its
  /// eigenspace (the solver's choice). Not checked by lobpcg.
  int split_first = -1;
};

/// Lowest eigenpairs of K x = lambda M x, K and M symmetric: both triangles stored, or the lower one
/// alone if request.lower_triangles. Throws nvh::Error if the factorization fails (K - sigma M not
/// positive definite: M not positive definite), the iteration does not converge, a residual exceeds the
/// limit, or the request asks for more modes than the problem has.
///
/// This overload consumes K and M (pass std::move(K), or temporaries): their storage is given back
/// before the factorization, which sets the peak memory of large models. (Eigen 3.4's SparseMatrix has
/// no move operations, hence rvalue references rather than values: no copy is made.)
EigenResult solve_eigenproblem(SparseMatrix&& K, SparseMatrix&& M, const EigenRequest& request);
/// The same on copies of K and M.
EigenResult solve_eigenproblem(const SparseMatrix& K, const SparseMatrix& M, const EigenRequest& request);

/// Frequency in Hz of an eigenvalue lambda = omega^2 (negative round-off gives 0).
double frequency_hz(double eigenvalue);
/// Eigenvalue omega^2 of a frequency in Hz.
double eigenvalue_of_hz(double hz);
/// Exponent p of the mode count N(lambda) ~ lambda^p, from the eigenvalues found (any order): between the
/// middle one and the highest, p = ln(N_top / N_mid) / ln(lambda_top / lambda_mid), clamped to [1/4, 3/2]
/// (Weyl: 1/4 for beams in bending, a fourth-order operator in one dimension, lambda ~ k^4; 1/2 for axial and
/// torsional waves and for plates; 1 for shells; 3/2 for solids); 1/2 if the modes are too few or still
/// rigid. Sizes the next pass of an fmax request.
double growth_exponent(const Eigen::VectorXd& values);

}  // namespace nvh::condense
