#pragma once
// The preconditioner of the iterative eigen-solve (lobpcg.hpp) for solids of second-order tetrahedra: one
// symmetric two-grid p-multigrid cycle. The coarse level is the linear tetrahedra (TET4) on the TET10 mesh's
// vertices - a midside node's displacement interpolated linearly from its edge's two vertices (the
// prolongation P) - with the Galerkin matrix P^T A P factored by CHOLMOD: about a seventh of the unknowns
// and a small fraction of the fill of A's own factor. The smoother is a Chebyshev polynomial in the
// Jacobi-scaled A on [lambda_max / 8, 1.1 lambda_max] of D^-1 A (Adams, Brezina, Hu and Tuminaro,
// J. Comput. Phys. 188, 2003), lambda_max by power iteration.
//
// The free DOF are renumbered along a Z-order (Morton) curve through the nodes first: a product with A then
// gathers the rows of a block of vectors from nearby memory (measured on a 233k-DOF block: 11.5 against 2.8
// Gflop/s for 40 vectors, before the product kept its 16-column chunks in registers).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "condense/abaqus_mesh.hpp"
#include "condense/constrained_factor.hpp"
#include "condense/fe_model.hpp"

namespace nvh::condense {

/// A block of n vectors of length m stored row by row (a row is the m values of one DOF, contiguous).
using Block = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// y = A x for a symmetric A stored whole (both triangles, sorted): A is streamed once for the whole block.
/// Compiled for AVX-512, AVX2 and the baseline, chosen when the program loads. (From the lower triangle
/// alone, half the memory, a LOBPCG iteration on 233k DOF took 3.4 instead of 2.5 s: the writes scatter.)
void symmetric_block_product(const SparseMatrix& a, const Block& x, Block& y);

/// Per column j, the sum over the rows of x(i, j) y(i, j), in one pass over the rows.
Eigen::ArrayXd column_dots(const Block& x, const Block& y);

/// The symmetric `a` (its lower triangle is read) renumbered by `new_index` (old -> new) and stored whole,
/// each column's rows sorted: the form symmetric_block_product reads. `a`'s storage is given back first.
SparseMatrix renumbered_whole(SparseMatrix&& a, const std::vector<int>& new_index);

/// The coarse space of a mesh of C3D10 elements on the model's free DOF.
struct CoarseSpace {
  /// Per free DOF (the model's numbering), its index along the Z-order curve.
  std::vector<int> new_index;
  /// Free DOF (new numbering) x coarse DOF (the free translations of the vertices, in the same order).
  SparseMatrix prolongation;
  /// A free part's rigid-body motions on the free DOF (new numbering), one column each; none if supported.
  Eigen::MatrixXd rigid_modes;
  /// Rows (new numbering) that are coarse DOF themselves and that the smoother leaves to the coarse level:
  /// those of distributing couplings in elimination form (see tet10_vertex_space).
  std::vector<int> coarse_only;
};

/// nvh::Error if an element is not C3D10 (the coarse space is their vertices).
CoarseSpace tet10_vertex_space(const Mesh& mesh, const FeModel& model);

/// The coarse space of the DOF `kept` (indices into the model's free DOF, ascending; the others held, as the
/// interface of Craig-Bampton holds its boundary): their rows, renumbered along the same Z-order; a vertex
/// DOF that is not kept contributes nothing, like a support. No rigid-body modes (the held DOF restrain).
CoarseSpace restricted_space(const CoarseSpace& space, const std::vector<int>& kept);

class PMultigrid {
 public:
  /// The Chebyshev degree of each smoothing: measured best on the plain block at 109k DOF (degree 3: 15
  /// LOBPCG iterations instead of 16 and 10 % more time).
  static constexpr int kDegree = 2;

  /// Three blocks of the residual's size that the caller does not need during apply().
  struct Workspace {
    Block &scratch, &residual, &direction;
  };

  /// `a`: the symmetric positive definite A stored whole, in the prolongation's numbering; `degree`: of
  /// each Chebyshev smoothing (before and after the coarse correction); `coarse_only`: rows the smoother
  /// leaves alone (CoarseSpace::coarse_only). nvh::Error if P^T A P is not positive definite.
  PMultigrid(const SparseMatrix& a, const SparseMatrix& prolongation, int degree, Ordering ordering,
             const std::vector<int>& coarse_only = {});

  /// x = T r, T ~ A^-1 symmetric positive definite.
  void apply(const Block& r, Block& x, const Workspace& ws) const;

  Eigen::Index coarse_rows() const { return prolongation_.cols(); }
  const FactorStats& coarse_factor_stats() const { return coarse_factor_->stats(); }
  /// The factor of P^T A P (shared: the start block's coarse eigen-solve works on it at shift 0).
  std::shared_ptr<const ConstrainedFactor> coarse_factor() const { return coarse_factor_; }
  /// P^T A P, its lower triangle (a start for the eigen-solve: the coarse level's own modes).
  const SparseMatrix& coarse_matrix() const { return coarse_; }
  const SparseMatrix& prolongation() const { return prolongation_; }

 private:
  /// Chebyshev iteration for A x = r from x (zero if from_zero), Saad, Iterative Methods for Sparse Linear
  /// Systems, 2nd ed., 2003, Algorithm 12.1, preconditioned by the diagonal.
  void smooth(const Block& r, Block& x, const Workspace& ws, bool from_zero) const;

  const SparseMatrix& a_;
  const SparseMatrix& prolongation_;
  int degree_;
  Eigen::VectorXd inverse_diagonal_;
  double lower_ = 0, upper_ = 0;  // the smoothing interval of D^-1 A
  SparseMatrix coarse_;           // lower triangle of P^T A P
  std::shared_ptr<ConstrainedFactor> coarse_factor_;
  mutable Eigen::MatrixXd coarse_rhs_, coarse_solution_;
};

}  // namespace nvh::condense
