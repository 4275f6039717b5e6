#include "condense/block_lanczos.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "common/error.hpp"

extern "C" void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
                       const double* alpha, const double* a, const int* lda, const double* b, const int* ldb,
                       const double* beta, double* c, const int* ldc);

namespace nvh::condense {
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
/// A new direction whose norm the projection has cut below this fraction is taken as lost (round-off).
constexpr double kLost = 1e-11;

// The tall products go to the BLAS (OpenBLAS: kernels for the CPU it runs on; Eigen's own products,
// compiled without -march, run at SSE2 speed). Column-major blocks of n rows with leading dimension n.
/// Q^T X for the first `q_cols` columns of q (n rows) and x (n x b).
Eigen::MatrixXd transpose_times(const Eigen::MatrixXd& q, Eigen::Index q_cols, const Eigen::MatrixXd& x) {
  Eigen::MatrixXd c(q_cols, x.cols());
  if (q_cols == 0 || x.cols() == 0) return c;
  const int m = static_cast<int>(q_cols), nc = static_cast<int>(x.cols()), k = static_cast<int>(q.rows());
  const double one = 1, zero = 0;
  dgemm_("T", "N", &m, &nc, &k, &one, q.data(), &k, x.data(), &k, &zero, c.data(), &m);
  return c;
}

/// X -= Q C for the first C.rows() columns of q.
void subtract_times(const Eigen::MatrixXd& q, const Eigen::MatrixXd& c, Eigen::MatrixXd& x) {
  if (c.rows() == 0 || x.cols() == 0) return;
  const int n = static_cast<int>(q.rows()), nc = static_cast<int>(c.cols()), k = static_cast<int>(c.rows());
  const double minus_one = -1, one = 1;
  dgemm_("N", "N", &n, &nc, &k, &minus_one, q.data(), &n, c.data(), &k, &one, x.data(), &n);
}

/// x loses its components along the first `basis_cols` columns of `basis` and along `deflate`, by
/// classical Gram-Schmidt twice; returns the basis coefficients of both passes summed (basis_cols x b).
Eigen::MatrixXd orthogonalize(const Eigen::MatrixXd& basis, Eigen::Index basis_cols,
                              const Eigen::MatrixXd* deflate, Eigen::MatrixXd& x) {
  Eigen::MatrixXd coefficients = Eigen::MatrixXd::Zero(basis_cols, x.cols());
  for (int pass = 0; pass < 2; ++pass) {
    if (deflate && deflate->cols() > 0)
      subtract_times(*deflate, transpose_times(*deflate, deflate->cols(), x), x);
    const Eigen::MatrixXd c = transpose_times(basis, basis_cols, x);
    subtract_times(basis, c, x);
    coefficients += c;
  }
  return coefficients;
}

/// The first p columns of v (n x m used) become v's first m columns times s (m x p), in place, a chunk
/// of rows at a time (no second basis in memory).
void rotate_basis(Eigen::MatrixXd& v, const Eigen::MatrixXd& s) {
  constexpr Eigen::Index kRows = 4096;
  const int m = static_cast<int>(s.rows()), p = static_cast<int>(s.cols()), ld = static_cast<int>(v.rows());
  const double one = 1, zero = 0;
  Eigen::MatrixXd chunk(kRows, p);
  for (Eigen::Index r = 0; r < v.rows(); r += kRows) {
    const int rows = static_cast<int>(std::min(kRows, v.rows() - r));
    const int ldc = static_cast<int>(chunk.rows());
    dgemm_("N", "N", &rows, &p, &m, &one, v.data() + r, &ld, s.data(), &m, &zero, chunk.data(), &ldc);
    v.block(r, 0, rows, p) = chunk.topRows(rows);
  }
}

}  // namespace

BlockLanczosResult block_lanczos(Eigen::Index n, const BlockOperator& c, int nev,
                                 const BlockLanczosOptions& options) {
  const Eigen::Index deflated = options.deflate ? options.deflate->cols() : 0;
  const Eigen::Index b = std::max(1, options.block_size);
  // The basis: at least nev + 2 blocks (room for the wanted Ritz vectors and new directions), by default
  // max(2 nev, nev + 4 b); whole blocks, and at most what the problem holds (n less the deflated columns,
  // less the next block).
  const Eigen::Index room = n - deflated;
  const auto basis_columns = [&](int wanted, int basis_size) {
    const Eigen::Index size = std::max<Eigen::Index>(
        basis_size > 0 ? basis_size : std::max<Eigen::Index>(2 * wanted, wanted + 4 * b), wanted + 2 * b);
    return std::min((size + b - 1) / b * b, (room - b) / b * b);
  };
  Eigen::Index m = basis_columns(nev, options.basis_size);
  if (nev < 1 || m < nev + 2 * b) {
    throw Error("block Lanczos: " + std::to_string(nev) + " eigenvalues with blocks of " + std::to_string(b) +
                " (a basis of at least nev + 3 blocks) do not fit in a problem of " + std::to_string(room) +
                " unknowns");
  }
  Eigen::MatrixXd v(n, m + b);                          // the basis and, past column m, the next block
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(m + b, m);  // V^T C V, and R of the next block below it
  std::mt19937 random(20261129);                        // a fixed seed: the same run gives the same modes
  std::normal_distribution<double> normal;

  // Orthonormalize block x against the first k columns of v and the deflated ones, store it as Q at column
  // k, and return R = Q^T x (x = V_k R + ...). A direction x has lost (an invariant subspace, or columns
  // dependent within the block: a diagonal entry of R below kLost of the block's norm before the
  // projection) is replaced by a random one orthogonal to everything and the block factored again; the
  // lost part, below kLost, drops out of the recurrence.
  const auto append = [&](Eigen::MatrixXd& x, Eigen::Index k,
                          Eigen::MatrixXd* coefficients) -> Eigen::MatrixXd {
    const double scale = x.colwise().norm().maxCoeff();  // before the projection
    Eigen::MatrixXd g = orthogonalize(v, k, options.deflate, x);
    if (coefficients) *coefficients = std::move(g);
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(x);
    const Eigen::ArrayXd diagonal = qr.matrixQR().diagonal().cwiseAbs();
    if ((diagonal > kLost * scale).all()) {
      v.middleCols(k, b) = qr.householderQ() * Eigen::MatrixXd::Identity(n, b);
      return qr.matrixQR().topRows(b).triangularView<Eigen::Upper>();
    }
    Eigen::MatrixXd replaced = x;
    for (Eigen::Index j = 0; j < b; ++j) {
      if (diagonal[j] > kLost * scale) continue;
      for (Eigen::Index i = 0; i < n; ++i) replaced(i, j) = normal(random);
    }
    orthogonalize(v, k, options.deflate, replaced);  // CGS twice
    qr.compute(replaced);
    if (!(qr.matrixQR().diagonal().cwiseAbs().array() > 0).all())
      throw Error(
          "block Lanczos: no new direction independent of the basis (a basis as large as the problem)");
    v.middleCols(k, b) = qr.householderQ() * Eigen::MatrixXd::Identity(n, b);
    return v.middleCols(k, b).transpose() * x;
  };

  BlockLanczosResult result;
  {
    Eigen::MatrixXd start(n, b);
    for (Eigen::Index j = 0; j < b; ++j)
      for (Eigen::Index i = 0; i < n; ++i) start(i, j) = normal(random);
    append(start, 0, nullptr);
  }
  Eigen::Index k = 0;  // the block at column k is the newest, its image not yet formed
  Eigen::MatrixXd w, g;
  for (;;) {
    for (; k < m; k += b) {
      c(v.middleCols(k, b), w);
      result.products += static_cast<int>(b);
      if (options.progress) options.progress(result.products);
      const Eigen::MatrixXd r = append(w, k + b, &g);  // g: V_{0..k+b}^T C V_k
      h.block(0, k, k + b, b) = g;
      h.block(k + b, k, b, b) = r;
    }
    // Ritz pairs of the basis, largest first.
    const Eigen::MatrixXd hm = 0.5 * (h.topRows(m) + h.topRows(m).transpose());
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ritz(hm);
    const Eigen::MatrixXd s = ritz.eigenvectors().rowwise().reverse();
    const Eigen::VectorXd theta = ritz.eigenvalues().reverse();
    const Eigen::VectorXd residual = (h.bottomRows(b) * s).colwise().norm().transpose();
    // The leading pairs whose residual meets the tolerance (Spectra's criterion), up to `limit`.
    const auto converged_up_to = [&](Eigen::Index from, Eigen::Index limit) {
      while (from < limit && residual[from] <= options.tolerance * std::max(std::pow(kEpsilon, 2.0 / 3.0),
                                                                            std::abs(theta[from])))
        ++from;
      return from;
    };
    Eigen::Index converged = converged_up_to(0, nev);
    bool stop = converged == nev;
    if (options.grow) {
      if (stop) converged = converged_up_to(converged, m - b);  // never the last block's, the least accurate
      const BlockLanczosGrowth more = options.grow(theta, converged);
      const Eigen::Index grown = std::max(m, more.nev > nev ? basis_columns(more.nev, more.basis_size) : 0);
      if (more.stop) {
        stop = true;
      } else if (more.nev > nev && grown >= more.nev + 2 * b) {
        nev = more.nev;
        stop = converged >= nev;
        ++result.growths;
        if (grown > m) {
          // The basis V (m columns, the next block after them) and H take the new columns; the relation
          // C V = V H + V_next R holds as it is, so the recurrence goes on from the next block at m.
          v.conservativeResize(Eigen::NoChange, grown + b);  // keeps the first m + b columns
          Eigen::MatrixXd larger = Eigen::MatrixXd::Zero(grown + b, grown);
          larger.topLeftCorner(m + b, m) = h;
          h.swap(larger);
          k = m;
          m = grown;
          continue;
        }
      }
    } else if (stop && options.all_converged) {
      converged = converged_up_to(converged, m - b);
    }
    if (stop) {
      rotate_basis(v, s.leftCols(converged));
      result.values = theta.head(converged);
      v.conservativeResize(Eigen::NoChange, converged);  // the basis's storage becomes the vectors' (no copy)
      result.vectors.swap(v);
      return result;
    }
    if (result.restarts == options.max_restarts) {
      throw Error("block Lanczos did not converge: " + std::to_string(converged) + " of " +
                  std::to_string(nev) + " eigenvalues after " + std::to_string(result.restarts) +
                  " restarts (" + std::to_string(result.products) + " products, a basis of " +
                  std::to_string(m) + ")");
    }
    // Thick restart: keep the best p Ritz vectors (about half of the room beyond nev, whole blocks to
    // grow) and the next block; C Y = Y Theta + V_next (R s_last).
    ++result.restarts;
    const Eigen::Index p = m - std::max<Eigen::Index>(1, (m - nev) / (2 * b)) * b;
    const Eigen::MatrixXd coupling = h.bottomRows(b) * s.leftCols(p);  // b x p
    rotate_basis(v, s.leftCols(p));
    v.middleCols(p, b) = v.middleCols(m, b);
    h.setZero();
    h.topLeftCorner(p, p).diagonal() = theta.head(p);
    h.block(p, 0, b, p) = coupling;
    h.block(0, p, p, b) = coupling.transpose();
    k = p;
  }
}

}  // namespace nvh::condense
