#pragma once
// Assembly straight into compressed sparse storage. The pattern of a 6N x 6N nodal matrix of solids
// follows from the node graph (which nodes share an element) and from which displacement components
// a row and a column couple; it is built once, then element contributions are added in place. No
// triplet lists: those held 16 bytes per element entry (900 per C3D10 stiffness) and set the peak
// memory of the whole run.
#include <Eigen/SparseCore>
#include <array>
#include <vector>

#include "condense/abaqus_mesh.hpp"

namespace nvh::condense {

/// For each node, the sorted nodes that share an element with it (itself included), in CSR form.
struct NodeGraph {
  std::vector<int> start;       ///< node n's neighbours are neighbours[start[n] .. start[n + 1])
  std::vector<int> neighbours;  ///< sorted within each node

  /// Index of node m within n's neighbours (binary search); m must be a neighbour.
  int position(int n, int m) const;
};

/// The graph of `node_count` nodes over the elements' connectivity.
NodeGraph node_graph(int node_count, const std::vector<MeshElement>& elements);

/// A 6 N x 6 N matrix (N = total nodes, graph nodes first) whose column 6 n + b holds the rows
/// 6 m + a for every neighbour m of n and every translation component a with couple[a][b], with
/// zero values; add() then sums element entries into it.
class BlockAssembler {
 public:
  BlockAssembler(const NodeGraph& graph, int total_nodes, const std::array<std::array<bool, 3>, 3>& couple);
  /// A(6 m + a, 6 col_node + b) += value for the row node m at p = graph.position(col_node, m).
  void add(int p, int a, int col_node, int b, double value) {
    matrix_.valuePtr()[matrix_.outerIndexPtr()[6 * col_node + b] + p * per_neighbour_[b] + offset_[a][b]] +=
        value;
  }
  /// Hand the assembled matrix over to `target` (its old contents are freed) and keep nothing. A swap:
  /// Eigen 3.4's SparseMatrix has no move operations, and a copy would hold the matrix twice.
  void take(Eigen::SparseMatrix<double>& target) {
    Eigen::SparseMatrix<double>().swap(target);
    target.swap(matrix_);
  }

 private:
  Eigen::SparseMatrix<double> matrix_;
  std::array<int, 3> per_neighbour_{};          ///< rows per neighbour in a column of component b
  std::array<std::array<int, 3>, 3> offset_{};  ///< row a's place among them
};

/// An N x N matrix over the nodes (N = total nodes, graph nodes first) whose column n holds the rows
/// of n's neighbours, with zero values, such as the scalar mass int rho N_i N_j dV; add() sums into it.
class NodeAssembler {
 public:
  NodeAssembler(const NodeGraph& graph, int total_nodes);
  /// A(m, col_node) += value for the row node m at p = graph.position(col_node, m).
  void add(int p, int col_node, double value) {
    matrix_.valuePtr()[matrix_.outerIndexPtr()[col_node] + p] += value;
  }
  /// Hand the assembled matrix over to `target`, as BlockAssembler::take.
  void take(Eigen::SparseMatrix<double>& target) {
    Eigen::SparseMatrix<double>().swap(target);
    target.swap(matrix_);
  }

 private:
  Eigen::SparseMatrix<double> matrix_;
};

}  // namespace nvh::condense
