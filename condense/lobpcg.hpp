#pragma once
// LOBPCG: the lowest eigenpairs of A x = mu M x (A, M symmetric positive definite) by the locally optimal
// block preconditioned conjugate gradient method (Knyazev, SIAM J. Sci. Comput. 23(2), 2001, Algorithm 4.1),
// each step a Rayleigh-Ritz on [X W P]: the current vectors X, the preconditioned residuals W = T (A X -
// M X diag(mu)) and the previous search directions P, each block M-orthonormalized and W, P kept
// M-orthogonal to the blocks before them (the stable form of Hetmaniuk and Lehoucq, J. Comput. Phys. 218,
// 2006), so that the Ritz problem is a standard one. Robust against nearly dependent bases: W projected
// twice, and the directions of W and P that the projections cancel dropped (SVQB with "ortho-drop",
// Duersch, Shao, Yang and Gu, SIAM J. Sci. Comput. 40(5), 2018).
//
// The alternative to shift-invert Lanczos for large solids where memory decides: no factor of A, only the
// preconditioner's (p_multigrid.hpp) and eleven blocks of n x (nev + guard) vectors. Measured on the plain
// block of bench/run_volume_bench.sh (233k free DOF, 30 modes): 1,377 MiB and 34.9 s against the factor-based
// solve's 2,632 MiB and 57.2 s (docs/cli.md `--eigensolver`; docs/theory/beams-and-reduction.md section 4.1;
// bench/README.md).
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "condense/eigensolver.hpp"
#include "condense/p_multigrid.hpp"

namespace nvh::condense {

struct LobpcgResult {
  Eigen::VectorXd values;   ///< mu, ascending
  Eigen::MatrixXd vectors;  ///< n x nev, M-orthonormal
  int iterations = 0;
  double largest_residual = 0;  ///< of the nev wanted: ||A x - mu M x|| / (||A x|| + mu ||M x||)
};

/// The nev lowest eigenpairs, with `guard` more vectors in the block (they speed the convergence of the
/// highest wanted ones), until every wanted relative residual is below `tolerance`. A, M stored whole
/// (symmetric_block_product). nvh::Error if the iteration does not converge in `max_iterations` or a block
/// degenerates.
/// `start`: up to n x (nev + guard) start vectors (any scaling; dependent columns are dropped), filled up
/// with random ones; empty: random ones.
/// `constraints`: Y, M-orthonormal, and M Y: the eigenvectors are sought M-orthogonal to Y (a free part's
/// rigid-body modes, known exactly; Knyazev 2001, sec. 5), or empty.
struct LobpcgConstraints {
  Block y, my;
};
LobpcgResult lobpcg(const SparseMatrix& a, const SparseMatrix& m_mass, const PMultigrid& preconditioner,
                    int nev, double tolerance, int guard = 10, int max_iterations = 500,
                    const EigenProgress* progress = nullptr, Block start = Block(),
                    const LobpcgConstraints* constraints = nullptr);

/// Every eigenpair with mu <= mu_max and at least one above it, all converged, by runs of lobpcg(): the
/// first seeks `first_count` modes, each later one the next modes, M-orthogonal to those found (and to
/// `constraints`), their count extrapolated from the growth of the mode count with mu (growth_exponent),
/// until a run finds a value above mu_max. The result holds all runs' modes, ascending. nvh::Error as
/// lobpcg(), or if mu_max lies above a third of the model's modes (too many for the block method).
LobpcgResult lobpcg_up_to(const SparseMatrix& a, const SparseMatrix& m_mass, const PMultigrid& preconditioner,
                          double mu_max, int first_count, double tolerance, int guard = 10,
                          int max_iterations = 500, const EigenProgress* progress = nullptr,
                          Block start = Block(), const LobpcgConstraints* constraints = nullptr);

}  // namespace nvh::condense
