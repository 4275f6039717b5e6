#include "condense/lobpcg.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <tuple>
#include <utility>
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

/// Orthonormalize b in the M inner product (mb = M b), with ab = A b changed alike, by SVQB (Stathopoulos
/// and Wu, SIAM J. Sci. Comput. 23(6), 2002, Algorithm 3): G = b^T M b scaled by `reference` (each
/// column's M-norm before the caller's projection; G's own diagonal if empty) to D G D = Z Theta Z^T, then
/// b <- b D Z Theta^-1/2. Directions with theta below kDrop are dropped (the "ortho-drop" of Duersch, Shao,
/// Yang and Gu, SIAM J. Sci. Comput. 40(5), 2018): a column that the projection has all but cancelled, or
/// one nearly dependent on the others, is rounding noise, and its images A b, M b - formed by the same
/// linear combinations, not by new products - would carry errors amplified by theta^-1/2 into the Ritz
/// problem (seen as a spurious Ritz value, then a breakdown, before this was done). Returns the number of
/// columns kept (0: none), and the largest over the smallest theta kept.
constexpr double kDrop = 1e-10;  // the images' errors stay below 1e5 eps of their norms
std::pair<Eigen::Index, double> svqb(Block& b, Block& mb, Block& ab, Block& scratch,
                                     const Eigen::VectorXd& reference = Eigen::VectorXd()) {
  const Eigen::MatrixXd g = gram(b, mb);
  Eigen::VectorXd d = reference.size() ? reference : Eigen::VectorXd(g.diagonal().cwiseMax(0).cwiseSqrt());
  for (Eigen::Index j = 0; j < d.size(); ++j) d[j] = d[j] > 0 ? 1 / d[j] : 0;
  const Eigen::MatrixXd scaled = d.asDiagonal() * (0.5 * (g + g.transpose())) * d.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scaled);
  const Eigen::VectorXd& theta = eig.eigenvalues();  // ascending
  const double floor = kDrop * std::max(1.0, theta.size() ? theta[theta.size() - 1] : 0.0);
  Eigen::Index first = 0;
  while (first < theta.size() && !(theta[first] > floor)) ++first;
  const Eigen::Index kept = theta.size() - first;
  if (kept == 0 || !eig.eigenvectors().allFinite()) return {0, 0.0};
  const Eigen::MatrixXd c = d.asDiagonal() * eig.eigenvectors().rightCols(kept) *
                            theta.tail(kept).cwiseSqrt().cwiseInverse().asDiagonal();
  right_multiply(b, c, scratch);
  right_multiply(mb, c, scratch);
  right_multiply(ab, c, scratch);
  return {kept, theta[theta.size() - 1] / theta[first]};
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
  // The start: the given block, its dependent columns dropped, filled up to m with random ones.
  std::mt19937 random(20261129);  // a fixed seed: the same run gives the same modes
  std::normal_distribution<double> normal;
  if (start.rows() == n && start.cols() <= m) x.swap(start);
  for (int attempt = 0;; ++attempt) {
    if (const Eigen::Index have = x.cols(); have < m) {
      x.conservativeResize(n, m);
      for (Eigen::Index i = 0; i < n; ++i)
        for (Eigen::Index j = have; j < m; ++j) x(i, j) = normal(random);
    }
    for (int pass = 0; pass < 2; ++pass) project(x);
    symmetric_block_product(m_mass, x, mx);
    symmetric_block_product(a, x, ax);
    if (svqb(x, mx, ax, s1).first == m) break;
    if (attempt == 2) throw Error("lobpcg: no start block of " + std::to_string(m) + " independent vectors");
  }
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
                  " iterations: largest relative residual " + scientific(worst) + " > " +
                  scientific(tolerance) + " (try the spectra eigensolver)");
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
    // W M-orthogonal to the constraints and to X by classical Gram-Schmidt twice ("twice is enough":
    // Giraud, Langou, Rozloznik, Comput. Math. Appl. 50, 2005): a residual of a nearly converged column lies
    // almost in span X, and one pass leaves its remainder far from orthogonal. Before A W and M W are
    // formed, so that these are exact products of what is kept.
    for (int pass = 0; pass < 2; ++pass) {
      project(w);
      times(x, gram(mx, w), w, -1, 1);
    }
    symmetric_block_product(m_mass, w, mw);
    symmetric_block_product(a, w, aw);
    auto [kw, condition] = svqb(w, mw, aw, s1);
    if (kw == 0)
      throw Error(
          "lobpcg: the preconditioned residuals lie in the span of the current vectors at iteration " +
          std::to_string(it) + " (try the spectra eigensolver)");
    if (condition > 1e6) kw = svqb(w, mw, aw, s1).first;  // a second pass restores orthonormality
    bool with_p = p.cols() > 0;
    if (with_p) {  // P against X and W, then orthonormal; its cancelled directions dropped
      const Eigen::VectorXd before = column_dots(p, mp).cwiseMax(0).sqrt().matrix();  // M-norms
      const Eigen::MatrixXd cx = gram(mx, p), cw = gram(mw, p);
      for (auto [pb, xb, wb] :
           {std::tuple{&p, &x, &w}, std::tuple{&ap, &ax, &aw}, std::tuple{&mp, &mx, &mw}}) {
        times(*xb, cx, *pb, -1, 1);
        times(*wb, cw, *pb, -1, 1);
      }
      auto [kept, p_condition] = svqb(p, mp, ap, s1, before);
      if (kept > 0 && p_condition > 1e6) kept = svqb(p, mp, ap, s1).first;
      with_p = kept > 0;
    }
    // The Ritz problem on the M-orthonormal basis [X W P]: B = I, A's blocks (X^T A X = diag(mu)).
    const Eigen::Index kp = with_p ? p.cols() : 0, k = m + kw + kp;
    Eigen::MatrixXd ritz_matrix = Eigen::MatrixXd::Zero(k, k);
    ritz_matrix.topLeftCorner(m, m) = mu.asDiagonal();
    ritz_matrix.block(0, m, m, kw) = gram(x, aw);
    ritz_matrix.block(m, m, kw, kw) = gram(w, aw);
    if (with_p) {
      ritz_matrix.block(0, m + kw, m, kp) = gram(x, ap);
      ritz_matrix.block(m, m + kw, kw, kp) = gram(w, ap);
      ritz_matrix.block(m + kw, m + kw, kp, kp) = gram(p, ap);
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ritz(ritz_matrix.selfadjointView<Eigen::Upper>());
    const Eigen::MatrixXd c = ritz.eigenvectors().leftCols(m);
    mu = ritz.eigenvalues().head(m);
    const Eigen::MatrixXd cx = c.topRows(m), cw = c.middleRows(m, kw), cp = c.bottomRows(kp);
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

LobpcgResult lobpcg_up_to(const SparseMatrix& a, const SparseMatrix& m_mass, const PMultigrid& preconditioner,
                          double mu_max, int first_count, double tolerance, int guard, int max_iterations,
                          const EigenProgress* progress, Block start, const LobpcgConstraints* constraints) {
  const Eigen::Index n = a.rows();
  LobpcgConstraints found;  // the given constraints, then every mode found
  if (constraints) found = *constraints;
  LobpcgResult all;
  all.vectors.resize(n, 0);
  for (int count = std::max(first_count, 1);;) {
    const Eigen::Index have = all.values.size();
    if (have + count + guard > n / 3)
      throw Error("lobpcg: the band up to fmax holds more than " + std::to_string(have) +
                  " modes, too many for the block method on " + std::to_string(n) +
                  " unknowns (use the spectra eigensolver)");
    const LobpcgResult part = lobpcg(a, m_mass, preconditioner, count, tolerance, guard, max_iterations,
                                     progress, std::move(start), found.y.cols() > 0 ? &found : nullptr);
    start = Block();
    all.values.conservativeResize(have + count);
    all.values.tail(count) = part.values;
    all.vectors.conservativeResize(Eigen::NoChange, have + count);
    all.vectors.rightCols(count) = part.vectors;
    all.iterations += part.iterations;
    all.largest_residual = std::max(all.largest_residual, part.largest_residual);
    if (part.values.maxCoeff() > mu_max) break;
    // The next run keeps M-orthogonal to all found so far, and seeks as many more as the mode count's
    // growth says lie below mu_max, with 15 % to spare (as the Lanczos passes of eigensolver.cpp).
    Block y(n, found.y.cols() + count), my;
    if (found.y.cols() > 0) y.leftCols(found.y.cols()) = found.y;
    y.rightCols(count) = part.vectors;
    symmetric_block_product(m_mass, y.rightCols(count).eval(), my);
    Block my_all(n, y.cols());
    if (found.my.cols() > 0) my_all.leftCols(found.my.cols()) = found.my;
    my_all.rightCols(count) = my;
    found.y.swap(y);
    found.my.swap(my_all);
    const Eigen::Index total = all.values.size();
    const double top = all.values.maxCoeff();
    const double wanted = std::ceil(1.15 * total * std::pow(mu_max / top, growth_exponent(all.values))) -
                          static_cast<double>(total);
    count = static_cast<int>(std::max(wanted, std::max(10.0, 0.25 * total)));
  }
  // Ascending over all runs (each run's are; a later run's may interleave where an earlier one stopped).
  std::vector<Eigen::Index> order(static_cast<std::size_t>(all.values.size()));
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<Eigen::Index>(i);
  std::sort(order.begin(), order.end(),
            [&](Eigen::Index i, Eigen::Index j) { return all.values[i] < all.values[j]; });
  LobpcgResult sorted = all;
  for (std::size_t i = 0; i < order.size(); ++i) {
    sorted.values[static_cast<Eigen::Index>(i)] = all.values[order[i]];
    sorted.vectors.col(static_cast<Eigen::Index>(i)) = all.vectors.col(order[i]);
  }
  return sorted;
}

}  // namespace nvh::condense
