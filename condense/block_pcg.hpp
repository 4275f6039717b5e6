#pragma once
// Preconditioned conjugate gradients for A X = B with many right-hand sides at once: one independent CG per
// column (Hestenes and Stiefel, J. Res. Nat. Bur. Standards 49(6), 1952; preconditioned form: Saad, Iterative
// Methods for Sparse Linear Systems, 2nd ed., 2003, Algorithm 9.1), run side by side so that each product
// with A and each preconditioner cycle serves all columns (symmetric_block_product streams A once).
//
// condense uses it for the constraint modes of Craig-Bampton and Guyan, K_ii Psi = -K_ib, with the two-grid
// p-multigrid cycle of the iterative eigen-solve as the preconditioner (--eigensolver lobpcg): no factor of
// K_ii is formed.
#include "condense/p_multigrid.hpp"

namespace nvh::condense {

struct BlockPcgResult {
  Block x;                      ///< the solutions, one column per right-hand side
  int iterations = 0;           ///< of the slowest column
  double largest_residual = 0;  ///< max over the columns of ||b - A x|| / ||b||
};

/// X with A X = B, A symmetric positive definite stored whole (symmetric_block_product), T ~ A^-1 symmetric
/// positive definite. Stops when every column's relative residual ||b - A x|| / ||b|| is below `tolerance`
/// (a zero column gives x = 0). nvh::Error naming the column and its residual if that takes more than
/// `max_iterations`, or if a column's curvature p^T A p is not positive (A or T not positive definite).
BlockPcgResult block_pcg(const SparseMatrix& a, const PMultigrid& preconditioner, const Block& b,
                         double tolerance, int max_iterations = 1000);

}  // namespace nvh::condense
