#pragma once
// Block Lanczos with thick restarts for the largest eigenvalues of a symmetric operator C (n x n), applied
// a block of columns at a time. The shift-invert eigen-solve (eigensolver.cpp) runs it on
// C = L^-1 P M P^T L^-T: one application to b columns is one supernodal solve with b right-hand sides,
// which reads the factor once for all b (BLAS-3) where a single-vector Lanczos reads it once per vector -
// on large solids the factor is hundreds of MB and the solves are bound by its reading.
//
// The iteration (Golub & Underwood 1977; Grimes, Lewis & Simon 1994 for the shift-invert use; the restart
// is the block form of Stewart's Krylov-Schur, Zhou & Saad 2008):
//   C V_j = V_{0..j} H_{0..j, j} + V_{j+1} R_{j+1},  V^T V = I,
// each new block orthogonalized against the whole basis twice (classical Gram-Schmidt twice, "twice is
// enough") and made orthonormal by a QR factorization. When the basis holds m columns, the Ritz pairs of
// H (m x m) give the eigenvalues; the residual of Ritz vector V s is || R_last s_last || exactly (with full
// re-orthogonalization). If the wanted ones have not converged, the basis is cut to its best p Ritz
// vectors Y plus the last block, which keeps the relation C Y = Y Theta + V_last B, and grown again.
#include <Eigen/Core>
#include <functional>

namespace nvh::condense {

/// y = C x for a block of columns (y is resized by the callee).
using BlockOperator = std::function<void(const Eigen::MatrixXd& x, Eigen::MatrixXd& y)>;

/// What a run that may grow does next (BlockLanczosOptions::grow).
struct BlockLanczosGrowth {
  bool stop = false;   ///< the leading converged pairs suffice: return them now
  int nev = 0;         ///< otherwise, if more than the present nev: the new number of wanted pairs
  int basis_size = 0;  ///< and the basis for it, as BlockLanczosOptions::basis_size
};

struct BlockLanczosOptions {
  int block_size = 8;  ///< columns applied at once
  int basis_size = 0;  ///< the basis before a restart (rounded up to whole blocks); 0: max(2 nev, nev + 4 b)
  double tolerance = 1e-10;  ///< converged if ||C y - theta y|| <= tolerance * max(eps^(2/3), |theta|)
  int max_restarts = 1000;   ///< nvh::Error beyond
  /// Optional: orthonormal columns (eigenvectors of C found before) the basis stays orthogonal to, so that
  /// a run finds the next eigenvalues (projection deflation).
  const Eigen::MatrixXd* deflate = nullptr;
  /// Return every leading converged Ritz pair of the basis when the nev have converged (at least nev),
  /// not only the nev: those beyond come free.
  bool all_converged = false;
  /// Optional (requests up to a frequency, whose count is not known beforehand): called whenever the
  /// basis is full, with all its Ritz values (descending; each is a lower bound of its eigenvalue of C,
  /// Cauchy's interlacing) and the number of leading ones that have converged. It may stop the run, or
  /// ask for more pairs: then the basis grows by the new columns and the recurrence continues from the
  /// next block - nothing is restarted or computed again, where a new run would start from a random block
  /// and build again what the basis holds. The result holds every leading converged pair, as with
  /// all_converged. A growth that does not fit in the problem is not taken.
  std::function<BlockLanczosGrowth(const Eigen::VectorXd& ritz_values, Eigen::Index converged)> grow;
  /// Optional: called after each block with the columns applied so far.
  std::function<void(int products)> progress;
};

struct BlockLanczosResult {
  Eigen::VectorXd values;   ///< the largest eigenvalues of C, descending (nev, or more: all_converged)
  Eigen::MatrixXd vectors;  ///< their eigenvectors, orthonormal
  int products = 0;         ///< columns C was applied to
  int restarts = 0;
  int growths = 0;  ///< larger requests taken on (options.grow)
};

/// The `nev` largest eigenpairs of the symmetric operator C of size n. Throws nvh::Error if they do not
/// converge within options.max_restarts, or nev does not fit (nev + 2 block_size columns must fit in n
/// less the deflated ones).
BlockLanczosResult block_lanczos(Eigen::Index n, const BlockOperator& c, int nev,
                                 const BlockLanczosOptions& options);

}  // namespace nvh::condense
