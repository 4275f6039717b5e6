// Tests of condense/block_lanczos against closed forms:
// - the 7-point Laplacian of an n x n x n cube with Dirichlet boundaries, T (x) I (x) I + I (x) T (x) I +
//   I (x) I (x) T, T = tridiag(-1, 2, -1): eigenvalues 4 (sin^2(p pi / 2(n+1)) + sin^2(q ...) + sin^2(r
//   ...)), p, q, r = 1..n, with multiplicities 1, 3, 3, 3, 6, ... The operator is its inverse (a dense
//   Cholesky solve), as shift-invert uses it: the largest eigenvalues of C are 1 / the lowest of the
//   Laplacian;
// - a diagonal operator with two distinct values: the Krylov space becomes invariant after two blocks,
//   the iteration must go on from fresh directions (the breakdown path).
#include "condense/block_lanczos.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "common/error.hpp"

namespace nvh::condense {
namespace {

constexpr double kPi = std::numbers::pi;

Eigen::MatrixXd cube_laplacian(int n) {
  const int size = n * n * n;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(size, size);
  const auto index = [n](int i, int j, int k) { return (i * n + j) * n + k; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const int row = index(i, j, k);
        a(row, row) = 6;
        if (i + 1 < n) a(row, index(i + 1, j, k)) = a(index(i + 1, j, k), row) = -1;
        if (j + 1 < n) a(row, index(i, j + 1, k)) = a(index(i, j + 1, k), row) = -1;
        if (k + 1 < n) a(row, index(i, j, k + 1)) = a(index(i, j, k + 1), row) = -1;
      }
  return a;
}

/// The Laplacian's eigenvalues, ascending.
std::vector<double> cube_eigenvalues(int n) {
  std::vector<double> one;
  for (int p = 1; p <= n; ++p) one.push_back(4 * std::pow(std::sin(p * kPi / (2.0 * (n + 1))), 2));
  std::vector<double> all;
  for (double a : one)
    for (double b : one)
      for (double c : one) all.push_back(a + b + c);
  std::sort(all.begin(), all.end());
  return all;
}

struct InverseLaplacian {
  Eigen::LLT<Eigen::MatrixXd> factor;
  int products = 0;
  void operator()(const Eigen::MatrixXd& x, Eigen::MatrixXd& y) {
    y = factor.solve(x);
    products += static_cast<int>(x.cols());
  }
};

double worst_vector_residual(const Eigen::MatrixXd& a, const BlockLanczosResult& r) {
  double worst = 0;
  for (Eigen::Index j = 0; j < r.values.size(); ++j) {
    const Eigen::VectorXd x = r.vectors.col(j);
    worst = std::max(worst, (a * x - x / r.values[j]).norm() * r.values[j]);
  }
  return worst;
}

TEST(BlockLanczos, CubeLaplacianTripleEigenvaluesAgainstTheClosedForm) {
  constexpr int kGrid = 10;  // 1000 unknowns
  const Eigen::MatrixXd a = cube_laplacian(kGrid);
  const std::vector<double> reference = cube_eigenvalues(kGrid);
  InverseLaplacian c{Eigen::LLT<Eigen::MatrixXd>(a)};
  // 20 values: 1 + 3 + 3 + 3 + 6 + ... - cut where the closed form has a gap, not inside a multiple one.
  int nev = 20;
  while (reference[nev] - reference[nev - 1] < 1e-9) --nev;
  for (int block : {3, 4, 8}) {  // a block Krylov space holds up to b copies of a multiple eigenvalue
    BlockLanczosOptions options;
    options.block_size = block;
    options.tolerance = 1e-10;
    c.products = 0;
    const BlockLanczosResult r = block_lanczos(a.rows(), std::ref(c), nev, options);
    ASSERT_EQ(r.values.size(), nev);
    double error = 0;
    for (int j = 0; j < nev; ++j)
      error = std::max(error, std::abs(1 / r.values[j] - reference[j]) / reference[j]);
    const double orthonormality =
        (r.vectors.transpose() * r.vectors - Eigen::MatrixXd::Identity(nev, nev)).cwiseAbs().maxCoeff();
    EXPECT_LT(error, 1e-11) << "block " << block;  // measured: 6e-14 to 1.2e-13
    EXPECT_LT(orthonormality, 1e-12) << "block " << block;
    EXPECT_LT(worst_vector_residual(a, r), 1e-8) << "block " << block;
    EXPECT_EQ(r.products, c.products);
    std::printf(
        "[ block %d ] %d eigenvalues of the 10^3 cube: max rel. error %.1e, |V^T V - I| %.1e, "
        "%d products, %d restarts\n",
        block, nev, error, orthonormality, r.products, r.restarts);
  }
}

TEST(BlockLanczos, DeflatedRunFindsTheNextEigenvalues) {
  constexpr int kGrid = 10;
  const Eigen::MatrixXd a = cube_laplacian(kGrid);
  const std::vector<double> reference = cube_eigenvalues(kGrid);
  InverseLaplacian c{Eigen::LLT<Eigen::MatrixXd>(a)};
  BlockLanczosOptions options;
  options.block_size = 4;
  const BlockLanczosResult first = block_lanczos(a.rows(), std::ref(c), 7, options);  // 1 + 3 + 3
  options.deflate = &first.vectors;
  const BlockLanczosResult next =
      block_lanczos(a.rows(), std::ref(c), 6, options);  // 3 + 3 (4th, 5th levels)
  for (int j = 0; j < 6; ++j)
    EXPECT_NEAR(1 / next.values[j], reference[7 + j], 1e-12 * reference[7 + j]) << "value " << 7 + j;
  EXPECT_LT((first.vectors.transpose() * next.vectors).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(BlockLanczos, AllConvergedReturnsTheFreePairsBeyondTheRequest) {
  // all_converged (the fmax passes): a diagonal operator with five large eigenvalues 10, 9, 8, 7, 6 and
  // the rest in (0, 0.01); 3 asked for in blocks of 4. The five are captured together, so the 4th and 5th
  // have converged with the 3rd and come back too, each exact; without all_converged, 3.
  constexpr int kSize = 200;
  Eigen::VectorXd d(kSize);
  for (int i = 0; i < kSize; ++i) d[i] = i < 5 ? 10.0 - i : 0.01 * (i + 1) / (kSize + 1);
  const BlockOperator c = [&d](const Eigen::MatrixXd& x, Eigen::MatrixXd& y) { y = d.asDiagonal() * x; };
  BlockLanczosOptions options;
  options.block_size = 4;
  EXPECT_EQ(block_lanczos(kSize, c, 3, options).values.size(), 3);
  options.all_converged = true;
  const BlockLanczosResult r = block_lanczos(kSize, c, 3, options);
  EXPECT_GE(r.values.size(), 5);
  for (Eigen::Index j = 0; j < r.values.size(); ++j) {
    EXPECT_NEAR(r.values[j], d[j], 1e-12 * d[j]) << "value " << j;
    EXPECT_LT((d.asDiagonal() * r.vectors.col(j) - r.values[j] * r.vectors.col(j)).norm(), 1e-9) << j;
  }
  std::printf("[ all converged ] 3 asked for, %d returned\n", static_cast<int>(r.values.size()));
}

TEST(BlockLanczos, InvariantSubspaceGoesOnFromFreshDirections) {
  // diag(2, 2, 2, 1, 1, ..., 1): a start block of 3 and its images span an invariant subspace of
  // dimension 6 (the eigenspace of 2 and three directions of 1); the next block is lost and must be
  // replaced by fresh directions orthogonal to everything. The 4 largest eigenvalues: 2, 2, 2, 1.
  constexpr int kSize = 100;
  Eigen::VectorXd d = Eigen::VectorXd::Ones(kSize);
  d.head(3).setConstant(2.0);
  const BlockOperator c = [&d](const Eigen::MatrixXd& x, Eigen::MatrixXd& y) { y = d.asDiagonal() * x; };
  BlockLanczosOptions options;
  options.block_size = 3;
  const BlockLanczosResult r = block_lanczos(kSize, c, 4, options);
  ASSERT_EQ(r.values.size(), 4);
  const Eigen::Vector4d expected(2, 2, 2, 1);
  EXPECT_LT((r.values - expected).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT((r.vectors.transpose() * r.vectors - Eigen::MatrixXd::Identity(4, 4)).cwiseAbs().maxCoeff(),
            1e-14);
  for (int j = 0; j < 4; ++j)
    EXPECT_LT((d.asDiagonal() * r.vectors.col(j) - expected[j] * r.vectors.col(j)).norm(), 1e-12);
}

TEST(BlockLanczos, PartlyLostBlockKeepsTheRecurrenceExact) {
  // diag(3, 2, 1, ..., 1), blocks of 3: the start block and its images span 5 dimensions (one direction
  // of each of 3 and 2, three of 1), so the second block loses one of its three directions and keeps two:
  // the lost one is replaced, and the Ritz pairs must still be exact eigenpairs.
  constexpr int kSize = 60;
  Eigen::VectorXd d = Eigen::VectorXd::Ones(kSize);
  d[0] = 3;
  d[1] = 2;
  const BlockOperator c = [&d](const Eigen::MatrixXd& x, Eigen::MatrixXd& y) { y = d.asDiagonal() * x; };
  BlockLanczosOptions options;
  options.block_size = 3;
  const BlockLanczosResult r = block_lanczos(kSize, c, 3, options);
  const Eigen::Vector3d expected(3, 2, 1);
  EXPECT_LT((r.values - expected).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT((r.vectors.transpose() * r.vectors - Eigen::MatrixXd::Identity(3, 3)).cwiseAbs().maxCoeff(),
            1e-14);
  for (int j = 0; j < 3; ++j)
    EXPECT_LT((d.asDiagonal() * r.vectors.col(j) - expected[j] * r.vectors.col(j)).norm(), 1e-12) << j;
}

TEST(BlockLanczos, GrowingRunFindsABandOfUnknownCountInOneKrylovSpace) {
  // options.grow (condense's fmax requests): all eigenvalues of the 10^3 cube Laplacian up to a bound in
  // a gap of the closed form near the 40th, from a request for 6 that grows by 8 whenever the wanted
  // ones have converged below the bound, and stops once a converged one lies beyond it. Against the
  // closed form, and against the cost of separate runs for the same counts (what restarting at each
  // growth costs).
  constexpr int kGrid = 10;
  const Eigen::MatrixXd a = cube_laplacian(kGrid);
  const std::vector<double> reference = cube_eigenvalues(kGrid);
  int count = 40;
  while (reference[count] - reference[count - 1] < 1e-9) ++count;
  const double bound = 0.5 * (reference[count - 1] + reference[count]);
  InverseLaplacian c{Eigen::LLT<Eigen::MatrixXd>(a)};
  BlockLanczosOptions options;
  options.block_size = 4;
  std::vector<int> requests{6};
  options.grow = [&](const Eigen::VectorXd& theta, Eigen::Index converged) -> BlockLanczosGrowth {
    EXPECT_TRUE(std::is_sorted(theta.data(), theta.data() + theta.size(), std::greater<>()));
    if (converged > 0 && 1 / theta[converged - 1] > bound) return {.stop = true};
    if (converged < requests.back()) return {};
    requests.push_back(requests.back() + 8);
    return {.nev = requests.back()};
  };
  c.products = 0;
  const BlockLanczosResult r = block_lanczos(a.rows(), std::ref(c), requests.front(), options);
  ASSERT_GT(r.values.size(), count);
  EXPECT_GT(1 / r.values[count], bound);
  double error = 0;
  for (int j = 0; j <= count; ++j)
    error = std::max(error, std::abs(1 / r.values[j] - reference[j]) / reference[j]);
  EXPECT_LT(error, 1e-11);  // measured: 1e-13
  EXPECT_LT((r.vectors.transpose() * r.vectors - Eigen::MatrixXd::Identity(r.values.size(), r.values.size()))
                .cwiseAbs()
                .maxCoeff(),
            1e-12);
  EXPECT_LT(worst_vector_residual(a, r), 1e-8);
  EXPECT_EQ(r.growths, static_cast<int>(requests.size()) - 1);
  EXPECT_GE(r.growths, 3);
  // Separate runs for the same requests, each from a random block (options without grow).
  options.grow = nullptr;
  int separate = 0;
  for (int nev : requests) separate += block_lanczos(a.rows(), std::ref(c), nev, options).products;
  EXPECT_LT(r.products, 0.6 * separate);  // measured: 372 against 888
  std::printf(
      "[ grow ] %d eigenvalues up to %.4f: requests %d..%d (%d growths), %d products; separate runs %d\n",
      count, bound, requests.front(), requests.back(), r.growths, r.products, separate);
}

TEST(BlockLanczos, RequestsThatDoNotFitAreRefused) {
  const BlockOperator c = [](const Eigen::MatrixXd& x, Eigen::MatrixXd& y) { y = x; };
  BlockLanczosOptions options;
  options.block_size = 4;
  EXPECT_THROW(block_lanczos(20, c, 10, options), Error);  // 10 + 3 blocks > 20
  EXPECT_THROW(block_lanczos(200, c, 0, options), Error);
}

}  // namespace
}  // namespace nvh::condense
