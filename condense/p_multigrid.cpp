#include "condense/p_multigrid.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>

#include "common/error.hpp"

namespace nvh::condense {

namespace {

/// Columns [c, c + W) of row j of y = A x, accumulated in W registers over the row's nonzeros.
template <int W>
inline void row_chunk(const int* index, const double* value, int k0, int k1, const double* x, Eigen::Index m,
                      Eigen::Index c, double* out) {
  double acc[W] = {};
  for (int k = k0; k < k1; ++k) {
    const double v = value[k];
    const double* in = x + static_cast<Eigen::Index>(index[k]) * m + c;
    for (int t = 0; t < W; ++t) acc[t] += v * in[t];
  }
  for (int t = 0; t < W; ++t) out[c + t] = acc[t];
}

}  // namespace

__attribute__((target_clones("avx512f", "avx2", "default"))) void symmetric_block_product(
    const SparseMatrix& a, const Block& x, Block& y) {
  // Column j of the symmetric A is its row j: y_j = sum_k a_jk x_k, one pass over A, rows of x gathered;
  // 16 columns of y at a time held in registers (the row's indices and values stay in L1 between chunks).
  const Eigen::Index m = x.cols();
  y.resize(a.rows(), m);
  const int* start = a.outerIndexPtr();
  const int* index = a.innerIndexPtr();
  const double* value = a.valuePtr();
  for (Eigen::Index j = 0; j < a.cols(); ++j) {
    double* out = y.data() + j * m;
    const int k0 = start[j], k1 = start[j + 1];
    Eigen::Index c = 0;
    for (; c + 16 <= m; c += 16) row_chunk<16>(index, value, k0, k1, x.data(), m, c, out);
    for (; c + 4 <= m; c += 4) row_chunk<4>(index, value, k0, k1, x.data(), m, c, out);
    for (; c < m; ++c) row_chunk<1>(index, value, k0, k1, x.data(), m, c, out);
  }
}

namespace {

/// The bits of v (21 of them) with two zeros between each: one coordinate of a 3D Morton code.
std::uint64_t spread_bits(std::uint64_t v) {
  std::uint64_t r = 0;
  for (int b = 0; b < 21; ++b) r |= ((v >> b) & 1u) << (3 * b);
  return r;
}

/// Per free DOF, its index when the DOF are sorted by the Z-order code of their node (then by direction).
std::vector<int> z_order(const FeModel& model, const std::vector<int>& free) {
  Eigen::Vector3d lo = model.nodes[0], hi = lo;
  for (const Eigen::Vector3d& x : model.nodes) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const Eigen::Vector3d scale = (hi - lo).cwiseMax(1e-300).cwiseInverse() * double((1 << 21) - 1);
  std::vector<std::pair<std::uint64_t, int>> keys;
  keys.reserve(static_cast<std::size_t>(model.free_dofs()));
  for (std::size_t g = 0; g < free.size(); ++g) {
    if (free[g] < 0) continue;
    const Eigen::Vector3d u = (model.nodes[g / 6] - lo).cwiseProduct(scale);
    const std::uint64_t code = spread_bits(static_cast<std::uint64_t>(u.x())) |
                               spread_bits(static_cast<std::uint64_t>(u.y())) << 1 |
                               spread_bits(static_cast<std::uint64_t>(u.z())) << 2;
    keys.emplace_back(code * 8 + g % 6, free[g]);
  }
  std::sort(keys.begin(), keys.end());
  std::vector<int> new_index(keys.size());
  for (std::size_t j = 0; j < keys.size(); ++j)
    new_index[static_cast<std::size_t>(keys[j].second)] = static_cast<int>(j);
  return new_index;
}

}  // namespace

CoarseSpace tet10_vertex_space(const Mesh& mesh, const FeModel& model) {
  const std::vector<int> free = model.free_index();
  CoarseSpace space;
  space.new_index = z_order(model, free);
  std::vector<char> vertex(free.size(), 0);
  for (const MeshElement& e : mesh.elements) {
    if (e.type != "C3D10")
      throw Error("the lobpcg eigensolver needs a mesh of second-order tetrahedra (C3D10): element " +
                  std::to_string(e.id) + " (line " + std::to_string(e.line) + " of the mesh) is " + e.type);
    for (int v = 0; v < 4; ++v)
      for (int d = 0; d < 3; ++d) vertex[6 * static_cast<std::size_t>(e.nodes[v]) + d] = 1;
  }
  // Distributing couplings in elimination form: a dependent DOF is a combination of its whole surface and its
  // point, so K couples every DOF of that surface, and of the dependent node's elements, with every other - a
  // dense block of low rank that neither the smoother nor linear interpolation sees (measured on the plain
  // block at 47k DOF with one such coupling: 244 LOBPCG iterations instead of 15). Those nodes' DOF are
  // coarse DOF themselves (their rows of P the identity), so that the coarse matrix holds the block exactly.
  std::vector<char> exact(model.nodes.size(), 0);
  if (!model.constraints.empty()) {
    std::vector<char> dependent_node(model.nodes.size(), 0);
    for (const LinearConstraint& c : model.constraints) {
      dependent_node[static_cast<std::size_t>(c.dof / 6)] = 1;
      for (const auto& [dof, coefficient] : c.terms) exact[static_cast<std::size_t>(dof / 6)] = 1;
    }
    for (const MeshElement& e : mesh.elements) {
      bool touches = false;
      for (int node : e.nodes) touches = touches || dependent_node[static_cast<std::size_t>(node)];
      if (touches)
        for (int node : e.nodes) exact[static_cast<std::size_t>(node)] = 1;
    }
    for (std::size_t node = 0; node < exact.size(); ++node)
      if (exact[node])
        for (int d = 0; d < 6; ++d) vertex[6 * node + d] = 1;
  }
  // Coarse DOF: the free vertex DOF, numbered in the order of the fine ones.
  const std::size_t n = space.new_index.size();
  std::vector<std::size_t> nodal_of_new(n);
  for (std::size_t g = 0; g < free.size(); ++g)
    if (free[g] >= 0) nodal_of_new[static_cast<std::size_t>(space.new_index[free[g]])] = g;
  std::vector<int> coarse(free.size(), -1);
  int nc = 0;
  for (std::size_t g : nodal_of_new)
    if (vertex[g]) coarse[g] = nc++;
  // C3D10 node order: corners 0-3, then the midside nodes of the edges 0-1, 1-2, 2-0, 0-3, 1-3, 2-3.
  static constexpr int kEdge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(2 * n);
  std::vector<char> done(model.nodes.size(), 0);
  const auto row = [&](std::size_t g) { return space.new_index[static_cast<std::size_t>(free[g])]; };
  for (const MeshElement& e : mesh.elements) {
    for (int v = 0; v < 4; ++v) {
      if (std::exchange(done[e.nodes[v]], 1)) continue;
      for (int d = 0; d < 3; ++d) {
        const std::size_t g = 6 * static_cast<std::size_t>(e.nodes[v]) + d;
        if (free[g] >= 0) t.emplace_back(row(g), coarse[g], 1.0);
      }
    }
    for (int s = 0; s < 6; ++s) {
      const int node = e.nodes[4 + s];
      if (std::exchange(done[node], 1)) continue;
      if (exact[static_cast<std::size_t>(node)]) {  // a coarse DOF itself
        for (int d = 0; d < 3; ++d) {
          const std::size_t g = 6 * static_cast<std::size_t>(node) + d;
          if (free[g] >= 0) t.emplace_back(row(g), coarse[g], 1.0);
        }
        continue;
      }
      for (int d = 0; d < 3; ++d) {
        const std::size_t g = 6 * static_cast<std::size_t>(node) + d;
        if (free[g] < 0) continue;
        for (int end : kEdge[s]) {
          const int c = coarse[6 * static_cast<std::size_t>(e.nodes[end]) + d];
          if (c >= 0) t.emplace_back(row(g), c, 0.5);  // a held vertex contributes nothing
        }
      }
    }
  }
  for (std::size_t node = 0; node < exact.size(); ++node)  // a coupling's point: in no element
    if (exact[node] && !done[node])
      for (int d = 0; d < 6; ++d) {
        const std::size_t g = 6 * node + d;
        if (free[g] >= 0) t.emplace_back(row(g), coarse[g], 1.0);
      }
  space.prolongation.resize(static_cast<Eigen::Index>(n), nc);
  space.prolongation.setFromTriplets(t.begin(), t.end());
  for (std::size_t g = 0; g < free.size(); ++g)
    if (free[g] >= 0 && exact[g / 6]) space.coarse_only.push_back(row(g));
  const Eigen::MatrixXd motions = model.unsupported_rigid_motions();  // 6 x r
  if (motions.cols() > 0) {
    const Eigen::MatrixXd field = model.rigid_body_field() * motions;  // 6N x r
    space.rigid_modes.resize(static_cast<Eigen::Index>(n), motions.cols());
    for (std::size_t g = 0; g < free.size(); ++g)
      if (free[g] >= 0)
        space.rigid_modes.row(space.new_index[static_cast<std::size_t>(free[g])]) =
            field.row(static_cast<Eigen::Index>(g));
  }
  return space;
}

Eigen::ArrayXd column_dots(const Block& x, const Block& y) {
  Eigen::ArrayXd sum = Eigen::ArrayXd::Zero(x.cols());
  for (Eigen::Index i = 0; i < x.rows(); ++i) sum += (x.row(i).array() * y.row(i).array()).transpose();
  return sum;
}

SparseMatrix renumbered_whole(SparseMatrix&& a, const std::vector<int>& new_index) {
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> renumbering(a.rows());
  std::copy(new_index.begin(), new_index.end(), renumbering.indices().data());
  SparseMatrix twisted;
  twisted = a.selfadjointView<Eigen::Lower>().twistedBy(renumbering);
  SparseMatrix().swap(a);      // give the storage back now (release() in fe_model.hpp)
  return twisted.transpose();  // = twisted (symmetric), each column's rows sorted
}

CoarseSpace restricted_space(const CoarseSpace& space, const std::vector<int>& kept) {
  const std::size_t n = space.new_index.size();
  std::vector<char> is_kept(n, 0);
  for (int d : kept) is_kept[static_cast<std::size_t>(d)] = 1;
  // The kept DOF's Z-order positions, ranked: their new numbering.
  std::vector<int> row_of_position(n, -1);  // Z-order position -> new row (-1: held)
  {
    std::vector<int> position_kept;
    for (std::size_t d = 0; d < n; ++d)
      if (is_kept[d]) position_kept.push_back(space.new_index[d]);
    std::sort(position_kept.begin(), position_kept.end());
    for (std::size_t k = 0; k < position_kept.size(); ++k)
      row_of_position[static_cast<std::size_t>(position_kept[k])] = static_cast<int>(k);
  }
  CoarseSpace out;
  out.new_index.resize(kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k)
    out.new_index[k] =
        row_of_position[static_cast<std::size_t>(space.new_index[static_cast<std::size_t>(kept[k])])];
  // A coarse column is a vertex DOF, its own fine row holding 1: held if that row is.
  const SparseMatrix& p = space.prolongation;
  std::vector<int> column(static_cast<std::size_t>(p.cols()), -1);
  int nc = 0;
  for (Eigen::Index c = 0; c < p.cols(); ++c) {
    bool held = false;
    for (SparseMatrix::InnerIterator it(p, c); it; ++it)
      held = held || (it.value() == 1.0 && row_of_position[static_cast<std::size_t>(it.row())] < 0);
    if (!held) column[static_cast<std::size_t>(c)] = nc++;
  }
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(p.nonZeros()));
  for (Eigen::Index c = 0; c < p.cols(); ++c) {
    if (column[static_cast<std::size_t>(c)] < 0) continue;
    for (SparseMatrix::InnerIterator it(p, c); it; ++it) {
      const int row = row_of_position[static_cast<std::size_t>(it.row())];
      if (row >= 0) t.emplace_back(row, column[static_cast<std::size_t>(c)], it.value());
    }
  }
  out.prolongation.resize(static_cast<Eigen::Index>(kept.size()), nc);
  out.prolongation.setFromTriplets(t.begin(), t.end());
  for (int position : space.coarse_only)
    if (row_of_position[static_cast<std::size_t>(position)] >= 0)
      out.coarse_only.push_back(row_of_position[static_cast<std::size_t>(position)]);
  return out;
}

PMultigrid::PMultigrid(const SparseMatrix& a, const SparseMatrix& prolongation, int degree, Ordering ordering,
                       const std::vector<int>& coarse_only)
    : a_(a),
      prolongation_(prolongation),
      degree_(degree),
      coarse_factor_(std::make_shared<ConstrainedFactor>(ordering)) {
  inverse_diagonal_ = a_.diagonal().cwiseInverse();
  // Rows left to the coarse level: the smoother's D^-1 is zero there, so a dense block among them (whose
  // D^-1 A has an eigenvalue as large as its size) neither sets lambda_max nor gets smoothed.
  for (int row : coarse_only) inverse_diagonal_[row] = 0;
  // The largest eigenvalue of D^-1 A by 20 steps of power iteration from a fixed start (deterministic).
  Block v = Block::Ones(a_.rows(), 1), w;
  for (Eigen::Index i = 0; i < v.rows(); i += 2) v(i, 0) = -1.0;
  double lambda_max = 0;
  for (int it = 0; it < 20; ++it) {
    v /= v.norm();
    symmetric_block_product(a_, v, w);
    w.array().colwise() *= inverse_diagonal_.array();
    lambda_max = v.col(0).dot(w.col(0));
    v.swap(w);
  }
  upper_ = 1.1 * lambda_max;
  lower_ = upper_ / 8;  // measured on the plain block, 109k DOF: 15 iterations; / 4 and / 16: 16, / 2.5: 17
  SparseMatrix coarse;
  {
    const SparseMatrix ap = a_ * prolongation_;
    coarse = SparseMatrix(prolongation_.transpose()) * ap;
  }
  if (!coarse_factor_->factorize(coarse))
    throw Error("the lobpcg eigensolver: the coarse (vertex) stiffness is not positive definite");
  coarse_ = coarse.triangularView<Eigen::Lower>();
}

void PMultigrid::apply(const Block& r, Block& x, const Workspace& ws) const {
  x.setZero(r.rows(), r.cols());
  smooth(r, x, ws, true);
  symmetric_block_product(a_, x, ws.scratch);
  ws.scratch = r - ws.scratch;  // the residual after the pre-smoothing
  coarse_rhs_.noalias() = prolongation_.transpose() * ws.scratch;
  coarse_solution_ = coarse_factor_->solve(coarse_rhs_);
  x.noalias() += prolongation_ * coarse_solution_;
  smooth(r, x, ws, false);
}

void PMultigrid::smooth(const Block& r, Block& x, const Workspace& ws, bool from_zero) const {
  const double theta = 0.5 * (upper_ + lower_), delta = 0.5 * (upper_ - lower_), sigma = theta / delta;
  double rho = 1 / sigma;
  Block& residual = ws.residual;
  Block& d = ws.direction;
  residual = r;
  if (!from_zero) {
    symmetric_block_product(a_, x, ws.scratch);
    residual -= ws.scratch;
  }
  d = (residual.array().colwise() * inverse_diagonal_.array()).matrix() / theta;
  for (int k = 1; k <= degree_; ++k) {
    x += d;
    if (k == degree_) break;
    symmetric_block_product(a_, d, ws.scratch);
    residual -= ws.scratch;
    const double rho_next = 1 / (2 * sigma - rho);
    d = rho_next * rho * d +
        (2 * rho_next / delta) * (residual.array().colwise() * inverse_diagonal_.array()).matrix();
    rho = rho_next;
  }
}

}  // namespace nvh::condense
