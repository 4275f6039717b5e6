#include "condense/lobpcg.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "common/error.hpp"

extern "C" void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
                       const double* alpha, const double* a, const int* lda, const double* b, const int* ldb,
                       const double* beta, double* c, const int* ldc);

namespace nvh::condense {
namespace {

// The dense block products go to the BLAS (OpenBLAS: kernels for the CPU it runs on); Eigen's own
// products, compiled without -march, run at SSE2 speed. A row-major n x m block is, to the column-major
// BLAS, its m x n transpose.

/// A^T B for blocks A, B of n rows (m_a, m_b columns).
Eigen::MatrixXd gram(const Block& a, const Block& b) {
  const int ma = static_cast<int>(a.cols()), mb = static_cast<int>(b.cols()), n = static_cast<int>(a.rows());
  Eigen::MatrixXd c(ma, mb);
  const double one = 1, zero = 0;
  dgemm_("N", "T", &ma, &mb, &n, &one, a.data(), &ma, b.data(), &mb, &zero, c.data(), &ma);
  return c;
}

/// y <- alpha x c + beta y, x: n x k block, c: k x m, y: n x m block (sized here when beta = 0).
void times(const Block& x, const Eigen::MatrixXd& c, Block& y, double alpha, double beta) {
  if (beta == 0) y.resize(x.rows(), c.cols());
  const int m = static_cast<int>(c.cols()), n = static_cast<int>(x.rows()), k = static_cast<int>(x.cols());
  dgemm_("T", "N", &m, &n, &k, &alpha, c.data(), &k, x.data(), &k, &beta, y.data(), &m);
}

/// b <- b c through `scratch`, which is swapped with b (once both exist, no allocation).
void right_multiply(Block& b, const Eigen::MatrixXd& c, Block& scratch) {
  times(b, c, scratch, 1, 0);
  b.swap(scratch);
}

/// Orthonormalize b in the M inner product (mb = M b), with ab = A b changed alike. false if b^T M b is not
/// positive definite (the block has become dependent).
bool orthonormalize(Block& b, Block& mb, Block& ab, Block& scratch) {
  const Eigen::MatrixXd g = gram(b, mb);
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (g + g.transpose()));
  if (llt.info() != Eigen::Success) return false;
  const Eigen::MatrixXd u_inverse = llt.matrixU().solve(Eigen::MatrixXd::Identity(g.rows(), g.cols()));
  if (!u_inverse.allFinite()) return false;
  right_multiply(b, u_inverse, scratch);
  right_multiply(mb, u_inverse, scratch);
  right_multiply(ab, u_inverse, scratch);
  return true;
}

}  // namespace

LobpcgResult lobpcg(const SparseMatrix& a, const SparseMatrix& m_mass, const PMultigrid& preconditioner,
                    int nev, double tolerance, int guard, int max_iterations, const EigenProgress* progress,
                    Block start, const LobpcgConstraints* constraints) {
  // b <- b - Y (M Y)^T b: M-orthogonal to the constraints.
  const auto project = [constraints](Block& b) {
    if (constraints && constraints->y.cols() > 0) times(constraints->y, gram(constraints->my, b), b, -1, 1);
  };
  const Eigen::Index n = a.rows();
  const Eigen::Index m = std::min<Eigen::Index>(nev + guard, n / 3);
  if (nev < 1 || m < nev)
    throw Error("lobpcg: " + std::to_string(nev) + " modes of a model with " + std::to_string(n) +
                " unknowns: too many for the block method");
  // Eleven blocks of n x m; the residuals R live in s2, and the preconditioner works in s1, A W and M W
  // before these are formed.
  Block x, ax, mx, w, aw, mw, p, ap, mp, s1, s2;
  Block& r = s2;
  if (start.rows() == n && start.cols() == m) {
    x.swap(start);
  } else {
    x.resize(n, m);
    std::mt19937 random(20261129);  // a fixed seed: the same run gives the same modes
    std::normal_distribution<double> normal;
    for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = normal(random);
  }
  project(x);
  symmetric_block_product(m_mass, x, mx);
  symmetric_block_product(a, x, ax);
  if (!orthonormalize(x, mx, ax, s1)) throw Error("lobpcg: the start block is dependent");
  Eigen::VectorXd mu;
  {  // Rayleigh-Ritz on X alone
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ritz(gram(x, ax));
    right_multiply(x, ritz.eigenvectors(), s1);
    right_multiply(ax, ritz.eigenvectors(), s1);
    right_multiply(mx, ritz.eigenvectors(), s1);
    mu = ritz.eigenvalues();
  }
  LobpcgResult result;
  std::vector<Eigen::Index> active;  // the columns still iterated: the unconverged wanted ones and the guard
  Eigen::VectorXd residual(m);
  for (int it = 0;; ++it) {
    // Relative residuals of all columns in one pass over the rows (the blocks are row-major).
    {
      Eigen::ArrayXd rr = Eigen::ArrayXd::Zero(m), aa = rr, mm = rr;
      for (Eigen::Index i = 0; i < n; ++i) {
        const auto axi = ax.row(i).array(), mxi = mx.row(i).array();
        rr += (axi - mu.array().transpose() * mxi).square().transpose();
        aa += axi.square().transpose();
        mm += mxi.square().transpose();
      }
      residual = (rr.sqrt() / (aa.sqrt() + mu.array().abs() * mm.sqrt())).matrix();
    }
    const double worst = residual.head(nev).maxCoeff();
    result.iterations = it;
    result.largest_residual = worst;
    if (progress && *progress) (*progress)(it, std::max(it + 1, 20));
    if (worst <= tolerance) break;
    if (it == max_iterations)
      throw Error("lobpcg did not converge in " + std::to_string(max_iterations) +
                  " iterations: largest relative residual " + std::to_string(worst) + " > " +
                  std::to_string(tolerance) + " (try the spectra eigensolver)");
    // Soft locking (Knyazev 2001, sec. 5): a converged wanted vector stays in X and in the Ritz problem,
    // but gets no new search direction; the guard columns always do.
    active.clear();
    for (Eigen::Index j = 0; j < m; ++j)
      if (j >= nev || residual[j] > tolerance) active.push_back(j);
    const Eigen::Index ka = static_cast<Eigen::Index>(active.size());
    r.resize(n, ka);
    for (Eigen::Index i = 0; i < n; ++i)
      for (Eigen::Index c = 0; c < ka; ++c) r(i, c) = ax(i, active[c]) - mu[active[c]] * mx(i, active[c]);
    preconditioner.apply(r, w, {s1, aw, mw});
    project(w);
    times(x, gram(mx, w), w, -1, 1);  // M-orthogonal to X
    symmetric_block_product(m_mass, w, mw);
    symmetric_block_product(a, w, aw);
    if (!orthonormalize(w, mw, aw, s1)) throw Error("lobpcg: the preconditioned residuals became dependent");
    bool with_p = p.cols() > 0;
    if (with_p) {  // P against X and W, then orthonormal; dropped for this step if it has become dependent
      const Eigen::MatrixXd cx = gram(mx, p), cw = gram(mw, p);
      for (auto [pb, xb, wb] :
           {std::tuple{&p, &x, &w}, std::tuple{&ap, &ax, &aw}, std::tuple{&mp, &mx, &mw}}) {
        times(*xb, cx, *pb, -1, 1);
        times(*wb, cw, *pb, -1, 1);
      }
      with_p = orthonormalize(p, mp, ap, s1);
    }
    // The Ritz problem on the M-orthonormal basis [X W P]: B = I, A's blocks (X^T A X = diag(mu)).
    const Eigen::Index kp = with_p ? p.cols() : 0, k = m + ka + kp;
    Eigen::MatrixXd ritz_matrix = Eigen::MatrixXd::Zero(k, k);
    ritz_matrix.topLeftCorner(m, m) = mu.asDiagonal();
    ritz_matrix.block(0, m, m, ka) = gram(x, aw);
    ritz_matrix.block(m, m, ka, ka) = gram(w, aw);
    if (with_p) {
      ritz_matrix.block(0, m + ka, m, kp) = gram(x, ap);
      ritz_matrix.block(m, m + ka, ka, kp) = gram(w, ap);
      ritz_matrix.block(m + ka, m + ka, kp, kp) = gram(p, ap);
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ritz(ritz_matrix.selfadjointView<Eigen::Upper>());
    const Eigen::MatrixXd c = ritz.eigenvectors().leftCols(m);
    mu = ritz.eigenvalues().head(m);
    const Eigen::MatrixXd cx = c.topRows(m), cw = c.middleRows(m, ka), cp = c.bottomRows(kp);
    // D = W cw + P cp, X <- X cx + D, P <- D's active columns; alike for A X, A P, M X, M P.
    const auto update = [&](Block& xb, const Block& wb, Block& pb) {
      times(wb, cw, s1, 1, 0);
      if (with_p) times(pb, cp, s1, 1, 1);
      s2 = s1;
      times(xb, cx, s2, 1, 1);
      xb.swap(s2);
      pb.resize(n, ka);
      for (Eigen::Index i = 0; i < n; ++i)
        for (Eigen::Index col = 0; col < ka; ++col) pb(i, col) = s1(i, active[col]);
    };
    update(x, w, p);
    update(ax, aw, ap);
    update(mx, mw, mp);
  }
  result.values = mu.head(nev);
  result.vectors = x.leftCols(nev);
  return result;
}

}  // namespace nvh::condense
