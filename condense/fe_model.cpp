#include "condense/fe_model.hpp"

#include <Eigen/SVD>

#include <Eigen/Geometry>
#include <algorithm>
#include <limits>
#include <sstream>

#include "common/error.hpp"

namespace nvh::condense {

int FeModel::find_node(const Vec3& at, double tolerance) const {
  const Eigen::Vector3d p(at[0], at[1], at[2]);
  int best = -1;
  double best_distance = tolerance;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const double d = (nodes[i] - p).norm();
    if (d <= best_distance) {
      best = static_cast<int>(i);
      best_distance = d;
    }
  }
  return best;
}

int FeModel::nearest_node(const Vec3& at) const {
  return find_node(at, std::numeric_limits<double>::infinity());
}

namespace {

/// The congruence T^T A T of a symmetric 6N x 6N matrix A, given by `column(r, add)`, which calls
/// add(s, A(s, r)) for every stored entry of column r. Column q of the result is
/// sum_r T(r, q) sum_s A(s, r) T(s, :)^T (Gustavson's algorithm with a dense accumulator), of which only
/// the rows p >= q are summed; the upper triangle is their mirror image, so the result is exactly
/// symmetric (rounding would otherwise differ between (p, q) and (q, p) with couplings, and the
/// eigen-solve would have to symmetrize a copy). One pass for the pattern, which sizes the result
/// exactly, one for the values: no 6N x n intermediate and no transposed copies, as Eigen's T^T * A * T
/// would build. With `lower_only` the upper triangle is left out.
template <class Column>
SparseMatrix congruence(const SparseMatrix& T, bool lower_only, const Column& column) {
  const Eigen::Index n = T.cols();
  const Eigen::SparseMatrix<double, Eigen::RowMajor> rows = T;  // T(s, :) for the row DOF s
  // Visit every (p, T(r, q) A(s, r) T(s, p)) of result column q with p >= q.
  const auto visit = [&](Eigen::Index q, auto&& add) {
    for (SparseMatrix::InnerIterator t(T, q); t; ++t) {
      column(t.row(), [&](Eigen::Index s, double a) {
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator u(rows, s); u; ++u)
          if (u.col() >= q) add(u.col(), t.value() * a * u.value());
      });
    }
  };
  // Column q holds, above the diagonal, the rows q' < q whose lower part has row q (upper[q] of them),
  // then its own lower part (lower[q] rows p >= q).
  std::vector<int> lower(static_cast<std::size_t>(n), 0), upper(static_cast<std::size_t>(n), 0);
  std::vector<Eigen::Index> seen(static_cast<std::size_t>(n), -1);  // last column that had row p
  for (Eigen::Index q = 0; q < n; ++q) {
    visit(q, [&](Eigen::Index p, double) {
      if (seen[p] == q) return;
      seen[p] = q;
      ++lower[q];
      if (p > q && !lower_only) ++upper[p];
    });
  }
  SparseMatrix result(n, n);
  int* outer = result.outerIndexPtr();
  outer[0] = 0;
  for (Eigen::Index q = 0; q < n; ++q) outer[q + 1] = outer[q] + upper[q] + lower[q];
  result.resizeNonZeros(outer[n]);
  int* inner = result.innerIndexPtr();
  double* values = result.valuePtr();
  std::vector<int> next_upper(outer, outer + n);  // where column p's next mirrored entry goes
  std::vector<double> sum(static_cast<std::size_t>(n), 0.0);
  std::fill(seen.begin(), seen.end(), -1);
  for (Eigen::Index q = 0; q < n; ++q) {
    int* const first = inner + outer[q] + upper[q];
    int k = 0;
    visit(q, [&](Eigen::Index p, double value) {
      if (seen[p] != q) seen[p] = q, first[k++] = static_cast<int>(p);
      sum[p] += value;
    });
    // Rows come in order when T maps DOF to free DOF monotonically (no couplings); sort otherwise.
    if (!std::is_sorted(first, first + k)) std::sort(first, first + k);
    double* const first_value = values + outer[q] + upper[q];
    for (int j = 0; j < k; ++j) first_value[j] = sum[first[j]], sum[first[j]] = 0.0;
  }
  // The upper triangle: the mirror image (q, p) of every (p, q), p > q; the columns q go in order, so
  // the rows of each column's upper part come out sorted.
  for (Eigen::Index q = 0; q < n && !lower_only; ++q) {
    for (int j = outer[q] + upper[q]; j < outer[q + 1]; ++j) {
      const int p = inner[j];
      if (p == q) continue;
      const int slot = next_upper[p]++;
      inner[slot] = static_cast<int>(q);
      values[slot] = values[j];
    }
  }
  return result;
}

}  // namespace

SparseMatrix FeModel::stiffness(Triangles stored) const {
  return congruence(transform, stored == Triangles::kLower, [&](Eigen::Index r, auto&& add) {
    for (SparseMatrix::InnerIterator it(stiffness_all, r); it; ++it) add(it.row(), it.value());
  });
}

SparseMatrix FeModel::mass(Triangles stored) const {
  const bool lower_only = stored == Triangles::kLower;
  if (!scalar_mass_only()) {
    return congruence(transform, lower_only, [&](Eigen::Index r, auto&& add) {
      for (SparseMatrix::InnerIterator it(mass_all, r); it; ++it) add(it.row(), it.value());
    });
  }
  // M_all(6 i + a, 6 j + a) = m_ij on the translations a < 3; the rotation columns are empty.
  return congruence(transform, lower_only, [&](Eigen::Index r, auto&& add) {
    const Eigen::Index a = r % 6;
    if (a >= 3) return;
    for (SparseMatrix::InnerIterator it(scalar_mass, r / 6); it; ++it) add(6 * it.row() + a, it.value());
  });
}

Eigen::MatrixXd FeModel::rigid_body_field() const {
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(all_dofs(), 6);
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const Eigen::Vector3d& x = nodes[n];
    for (int k = 0; k < 3; ++k) {
      r(6 * n + k, k) = 1.0;
      // Unit rotation about axis k: u = e_k x x, theta = e_k.
      const Eigen::Vector3d u = Eigen::Vector3d::Unit(k).cross(x);
      r.block<3, 1>(6 * n, 3 + k) = u;
      r(6 * n + 3 + k, 3 + k) = 1.0;
    }
  }
  return r;
}

Eigen::MatrixXd FeModel::unsupported_rigid_motions() const {
  const Eigen::MatrixXd field = rigid_body_field();
  std::vector<int> held;
  for (int d = 0; d < all_dofs(); ++d)
    if (supported_dof[d]) held.push_back(d);
  if (held.empty()) return Eigen::MatrixXd::Identity(6, 6);
  Eigen::MatrixXd rows(static_cast<Eigen::Index>(held.size()), 6);
  for (std::size_t i = 0; i < held.size(); ++i) rows.row(static_cast<Eigen::Index>(i)) = field.row(held[i]);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(rows, Eigen::ComputeFullV);
  svd.setThreshold(1e-9);
  return svd.matrixV().rightCols(6 - svd.rank());
}

std::vector<int> FeModel::free_index() const {
  // A dependent DOF of a distributing coupling (elimination form) is a row of T that may hold a coefficient
  // of exactly 1 too (on its point's translation): it is not a free DOF.
  std::vector<char> dependent(static_cast<std::size_t>(all_dofs()), 0);
  for (const LinearConstraint& c : constraints) dependent[static_cast<std::size_t>(c.dof)] = 1;
  std::vector<int> index(all_dofs(), -1);
  for (int col = 0; col < transform.outerSize(); ++col) {
    for (SparseMatrix::InnerIterator it(transform, col); it; ++it) {
      const int node = static_cast<int>(it.row()) / 6;
      if (master_of[node] == node && it.value() == 1.0 && !dependent[static_cast<std::size_t>(it.row())])
        index[it.row()] = col;
    }
  }
  return index;
}

namespace {
std::string format_point(const Vec3& p) {
  std::ostringstream s;
  s << "[" << p[0] << ", " << p[1] << ", " << p[2] << "]";
  return s.str();
}
}  // namespace

void apply_supports(FeModel& model, const std::vector<Support>& supports, double tolerance) {
  model.supported_dof.assign(model.all_dofs(), false);
  for (const Support& sup : supports) {
    std::vector<int> held;
    if (sup.box) {
      const auto& b = *sup.box;
      for (int n = 0; n < static_cast<int>(model.nodes.size()); ++n) {
        const Eigen::Vector3d& x = model.nodes[n];
        bool inside = true;
        for (int k = 0; k < 3; ++k)
          inside = inside && x(k) >= b[k] - tolerance && x(k) <= b[3 + k] + tolerance;
        if (inside && model.master_of[n] == n && !model.inactive_dof[6 * n]) held.push_back(n);
      }
      if (held.empty())
        throw Error("the support box holds no node of the model", sup.where, sup.path + ".box");
    } else {
      const int n = model.find_node(sup.at, tolerance);
      if (n < 0) {
        throw Error("the support at " + format_point(sup.at) + " is not on the model", sup.where,
                    sup.path + ".at");
      }
      if (model.master_of[n] != n) {
        throw Error("the support at " + format_point(sup.at) +
                        " is on the end of a rigid link; support its master station instead",
                    sup.where, sup.path + ".at");
      }
      held.push_back(n);
    }
    for (int n : held)
      for (int d = 0; d < 6; ++d)
        if (sup.dofs[d]) model.supported_dof[6 * n + d] = true;
  }
}

void build_transform(FeModel& model) {
  const int n_all = model.all_dofs();
  const int n_nodes = static_cast<int>(model.nodes.size());
  std::vector<bool> dependent(n_all, false);
  for (const LinearConstraint& c : model.constraints) dependent[c.dof] = true;
  std::vector<int> free_index(n_all, -1);
  int n_free = 0;
  for (int n = 0; n < n_nodes; ++n) {
    if (model.master_of[n] != n) continue;
    for (int d = 0; d < 6; ++d) {
      const int dof = 6 * n + d;
      if (!model.supported_dof[dof] && !model.inactive_dof[dof] && !dependent[dof])
        free_index[dof] = n_free++;
    }
  }
  std::vector<Eigen::Triplet<double>> tt;
  for (int n = 0; n < n_nodes; ++n) {
    const int m = model.master_of[n];
    auto add = [&](int row, int master_dof, double value) {
      const int col = free_index[master_dof];
      if (col >= 0 && value != 0.0) tt.emplace_back(row, col, value);
    };
    for (int d = 0; d < 6; ++d) add(6 * n + d, 6 * m + d, 1.0);
    if (m != n) {
      // theta x r = -r x theta: u_s,i += sum_j (-[r]_x)_{ij} theta_j.
      const Eigen::Vector3d r = model.nodes[n] - model.nodes[m];
      Eigen::Matrix3d rx;
      rx << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) add(6 * n + i, 6 * m + 3 + j, -rx(i, j));
    }
  }
  // Dependent DOF: their rows are the constraint's combination of independent DOF (a held DOF is 0).
  for (const LinearConstraint& c : model.constraints) {
    for (const auto& [dof, coefficient] : c.terms) {
      const int col = free_index[dof];
      if (col >= 0 && coefficient != 0.0) tt.emplace_back(c.dof, col, coefficient);
    }
  }
  model.transform.resize(n_all, n_free);
  model.transform.setFromTriplets(tt.begin(), tt.end());
  // Constraint rows on the free DOF (their DOF are masters; a held DOF is 0 and drops out).
  std::vector<Eigen::Triplet<double>> ct;
  for (std::size_t r = 0; r < model.constraint_rows.size(); ++r) {
    for (const auto& [dof, coefficient] : model.constraint_rows[r].terms) {
      const int col = free_index[dof];
      if (col >= 0 && coefficient != 0.0) ct.emplace_back(static_cast<int>(r), col, coefficient);
    }
  }
  model.constraint_matrix.resize(static_cast<Eigen::Index>(model.constraint_rows.size()), n_free);
  model.constraint_matrix.setFromTriplets(ct.begin(), ct.end());
}

}  // namespace nvh::condense
