// The serial N_Vector kernels and the sparse matrix zero (see sundials_kernels.hpp). Every operation reads
// all its operands at an index before it writes the result there, so a result may alias any operand (SUNDIALS
// allows z == x, z == y, z == X[0]). Sums over several vectors add in the order SUNDIALS' serial kernels do
// (X[0], X[1], ...); reductions over the entries (dot products, norms) in four partial sums, which differ
// from SUNDIALS' single running sum by round-off.
#include "solve/sundials_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace nvh::solve {

namespace {

double* data(N_Vector v) {
  return NV_DATA_S(v);
}
sunindextype length(N_Vector v) {
  return NV_LENGTH_S(v);
}

// --- standard operations ------------------------------------------------------------------------------

void linear_sum(double a, N_Vector x, double b, N_Vector y, N_Vector z) {
  const double *xd = data(x), *yd = data(y);
  double* zd = data(z);
  const sunindextype n = length(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = a * xd[i] + b * yd[i];
}

void constant(double c, N_Vector z) {
  std::fill_n(data(z), length(z), c);
}

void product(N_Vector x, N_Vector y, N_Vector z) {
  const double *xd = data(x), *yd = data(y);
  double* zd = data(z);
  for (sunindextype i = 0, n = length(z); i < n; ++i) zd[i] = xd[i] * yd[i];
}

void quotient(N_Vector x, N_Vector y, N_Vector z) {
  const double *xd = data(x), *yd = data(y);
  double* zd = data(z);
  for (sunindextype i = 0, n = length(z); i < n; ++i) zd[i] = xd[i] / yd[i];
}

void scale(double c, N_Vector x, N_Vector z) {
  const double* xd = data(x);
  double* zd = data(z);
  for (sunindextype i = 0, n = length(z); i < n; ++i) zd[i] = c * xd[i];
}

void absolute(N_Vector x, N_Vector z) {
  const double* xd = data(x);
  double* zd = data(z);
  for (sunindextype i = 0, n = length(z); i < n; ++i) zd[i] = std::abs(xd[i]);
}

void inverse(N_Vector x, N_Vector z) {
  const double* xd = data(x);
  double* zd = data(z);
  for (sunindextype i = 0, n = length(z); i < n; ++i) zd[i] = 1.0 / xd[i];
}

void add_constant(N_Vector x, double b, N_Vector z) {
  const double* xd = data(x);
  double* zd = data(z);
  for (sunindextype i = 0, n = length(z); i < n; ++i) zd[i] = xd[i] + b;
}

/// sum_i f(i) in four interleaved partial sums (which the compiler can vectorize, where one running sum
/// in IEEE order cannot), added at the end.
template <class Term>
double sum4(sunindextype n, Term f) {
  double s[4] = {0, 0, 0, 0};
  sunindextype i = 0;
  for (; i + 4 <= n; i += 4)
    for (int k = 0; k < 4; ++k) s[k] += f(i + k);
  for (; i < n; ++i) s[0] += f(i);
  return (s[0] + s[1]) + (s[2] + s[3]);
}

double dot(N_Vector x, N_Vector y) {
  const double *xd = data(x), *yd = data(y);
  return sum4(length(x), [&](sunindextype i) { return xd[i] * yd[i]; });
}

double max_norm(N_Vector x) {
  const double* xd = data(x);
  double m = 0;
  for (sunindextype i = 0, n = length(x); i < n; ++i) m = std::max(m, std::abs(xd[i]));
  return m;
}

/// sum (x_i w_i)^2
double weighted_square_sum(N_Vector x, N_Vector w) {
  const double *xd = data(x), *wd = data(w);
  return sum4(length(x), [&](sunindextype i) {
    const double p = xd[i] * wd[i];
    return p * p;
  });
}

/// sum over id_i > 0 of (x_i w_i)^2
double weighted_square_sum_mask(N_Vector x, N_Vector w, N_Vector id) {
  const double *xd = data(x), *wd = data(w), *idd = data(id);
  return sum4(length(x), [&](sunindextype i) {
    const double p = idd[i] > 0 ? xd[i] * wd[i] : 0.0;
    return p * p;
  });
}

double wrms_norm(N_Vector x, N_Vector w) {
  return std::sqrt(weighted_square_sum(x, w) / static_cast<double>(length(x)));
}

double wrms_norm_mask(N_Vector x, N_Vector w, N_Vector id) {
  return std::sqrt(weighted_square_sum_mask(x, w, id) / static_cast<double>(length(x)));
}

double minimum(N_Vector x) {
  const double* xd = data(x);
  const sunindextype n = length(x);
  if (n == 0) return std::numeric_limits<double>::max();  // SUNDIALS' BIG_REAL, as its serial kernel starts
  double m = xd[0];
  for (sunindextype i = 1; i < n; ++i) m = std::min(m, xd[i]);
  return m;
}

double weighted_l2_norm(N_Vector x, N_Vector w) {
  return std::sqrt(weighted_square_sum(x, w));
}

double l1_norm(N_Vector x) {
  const double* xd = data(x);
  return sum4(length(x), [&](sunindextype i) { return std::abs(xd[i]); });
}

void compare(double c, N_Vector x, N_Vector z) {
  const double* xd = data(x);
  double* zd = data(z);
  for (sunindextype i = 0, n = length(z); i < n; ++i) zd[i] = std::abs(xd[i]) >= c ? 1.0 : 0.0;
}

/// z = 1/x where x != 0; false if some x_i is 0 (z_i is then left as it was).
booleantype inverse_test(N_Vector x, N_Vector z) {
  const double* xd = data(x);
  double* zd = data(z);
  booleantype no_zero = SUNTRUE;
  for (sunindextype i = 0, n = length(x); i < n; ++i) {
    if (xd[i] == 0.0)
      no_zero = SUNFALSE;
    else
      zd[i] = 1.0 / xd[i];
  }
  return no_zero;
}

/// m_i = 1 where x_i violates the constraint c_i (2: x > 0, 1: x >= 0, -1: x <= 0, -2: x < 0), else 0;
/// true if none is violated.
booleantype constraint_mask(N_Vector c, N_Vector x, N_Vector m) {
  const double *cd = data(c), *xd = data(x);
  double* md = data(m);
  bool violated = false;
  for (sunindextype i = 0, n = length(x); i < n; ++i) {
    md[i] = 0.0;
    if (cd[i] == 0.0) continue;
    const bool test =
        (std::abs(cd[i]) > 1.5 && xd[i] * cd[i] <= 0.0) || (std::abs(cd[i]) > 0.5 && xd[i] * cd[i] < 0.0);
    if (test) md[i] = 1.0, violated = true;
  }
  return violated ? SUNFALSE : SUNTRUE;
}

/// min over denom_i != 0 of num_i / denom_i (SUNDIALS' BIG_REAL if there is none).
double min_quotient(N_Vector num, N_Vector denom) {
  const double *nd = data(num), *dd = data(denom);
  double m = std::numeric_limits<double>::max();
  for (sunindextype i = 0, n = length(num); i < n; ++i)
    if (dd[i] != 0.0) m = std::min(m, nd[i] / dd[i]);
  return m;
}

// --- fused operations -----------------------------------------------------------------------------------

/// zd[i] (+)= sum_{j < K} c_j x_j[i], added in the order j = 0, 1, ...: K fixed, so the compiler keeps the
/// coefficients in registers and vectorizes over i.
template <int K, bool kAccumulate>
void combine(sunindextype n, const double* c, const double* const* x, double* zd) {
  for (sunindextype i = 0; i < n; ++i) {
    double s = kAccumulate ? zd[i] : c[0] * x[0][i];
    for (int j = kAccumulate ? 0 : 1; j < K; ++j) s += c[j] * x[j][i];
    zd[i] = s;
  }
}

template <bool kAccumulate>
void combine(int count, sunindextype n, const double* c, const double* const* x, double* zd) {
  switch (count) {
    case 1:
      return combine<1, kAccumulate>(n, c, x, zd);
    case 2:
      return combine<2, kAccumulate>(n, c, x, zd);
    case 3:
      return combine<3, kAccumulate>(n, c, x, zd);
    case 4:
      return combine<4, kAccumulate>(n, c, x, zd);
    case 5:
      return combine<5, kAccumulate>(n, c, x, zd);
    case 6:
      return combine<6, kAccumulate>(n, c, x, zd);
    case 7:
      return combine<7, kAccumulate>(n, c, x, zd);
    default:
      return combine<8, kAccumulate>(n, c, x, zd);
  }
}

/// z = sum_j c_j X_j, added in the order j = 0, 1, ... (z may be X[0]). Up to eight vectors (IDA's history
/// at order 5 and its corrections) in one pass over z; more in further passes of up to eight, each added
/// to the partial sum.
int linear_combination(int nvec, double* c, N_Vector* X, N_Vector z) {
  if (nvec < 1) return -1;
  constexpr int kWidth = 8;
  const double* x[kWidth];
  const sunindextype n = length(z);
  for (int first = 0; first < nvec; first += kWidth) {
    const int count = std::min(nvec - first, kWidth);
    for (int j = 0; j < count; ++j) x[j] = data(X[first + j]);
    if (first == 0)
      combine<false>(count, n, c, x, data(z));
    else
      combine<true>(count, n, c + first, x, data(z));
  }
  return 0;
}

/// Z_j = a_j x + Y_j
int scale_add_multi(int nvec, double* a, N_Vector x, N_Vector* Y, N_Vector* Z) {
  if (nvec < 1) return -1;
  const double* xd = data(x);
  const sunindextype n = length(x);
  for (int j = 0; j < nvec; ++j) {
    const double* yd = data(Y[j]);
    double* zd = data(Z[j]);
    const double aj = a[j];
    for (sunindextype i = 0; i < n; ++i) zd[i] = aj * xd[i] + yd[i];
  }
  return 0;
}

/// d_j = x . Y_j
int dot_multi(int nvec, N_Vector x, N_Vector* Y, double* d) {
  if (nvec < 1) return -1;
  for (int j = 0; j < nvec; ++j) d[j] = dot(x, Y[j]);
  return 0;
}

// --- vector array operations ----------------------------------------------------------------------------

/// Z_j = a X_j + b Y_j
int linear_sum_array(int nvec, double a, N_Vector* X, double b, N_Vector* Y, N_Vector* Z) {
  if (nvec < 1) return -1;
  for (int j = 0; j < nvec; ++j) linear_sum(a, X[j], b, Y[j], Z[j]);
  return 0;
}

/// Z_j = c_j X_j
int scale_array(int nvec, double* c, N_Vector* X, N_Vector* Z) {
  if (nvec < 1) return -1;
  for (int j = 0; j < nvec; ++j) scale(c[j], X[j], Z[j]);
  return 0;
}

int constant_array(int nvec, double c, N_Vector* Z) {
  if (nvec < 1) return -1;
  for (int j = 0; j < nvec; ++j) constant(c, Z[j]);
  return 0;
}

int wrms_norm_array(int nvec, N_Vector* X, N_Vector* W, double* norms) {
  if (nvec < 1) return -1;
  for (int j = 0; j < nvec; ++j) norms[j] = wrms_norm(X[j], W[j]);
  return 0;
}

int wrms_norm_mask_array(int nvec, N_Vector* X, N_Vector* W, N_Vector id, double* norms) {
  if (nvec < 1) return -1;
  for (int j = 0; j < nvec; ++j) norms[j] = wrms_norm_mask(X[j], W[j], id);
  return 0;
}

/// Z[k][j] = a_k X_j + Y[k][j], j < nvec, k < nsum
int scale_add_multi_array(int nvec, int nsum, double* a, N_Vector* X, N_Vector** Y, N_Vector** Z) {
  if (nvec < 1 || nsum < 1) return -1;
  for (int j = 0; j < nvec; ++j)
    for (int k = 0; k < nsum; ++k) {
      const double *xd = data(X[j]), *yd = data(Y[k][j]);
      double* zd = data(Z[k][j]);
      for (sunindextype i = 0, n = length(X[j]); i < n; ++i) zd[i] = a[k] * xd[i] + yd[i];
    }
  return 0;
}

/// Z_j = sum_k c_k X[k][j], j < nvec, k < nsum
int linear_combination_array(int nvec, int nsum, double* c, N_Vector** X, N_Vector* Z) {
  if (nvec < 1 || nsum < 1) return -1;
  constexpr int kMax = 16;
  N_Vector column[kMax];
  for (int j = 0; j < nvec; ++j) {
    if (nsum > kMax) {  // not met in SUNDIALS' integrators: the slow form, by partial sums
      scale(c[0], X[0][j], Z[j]);
      for (int k = 1; k < nsum; ++k) linear_sum(c[k], X[k][j], 1.0, Z[j], Z[j]);
      continue;
    }
    for (int k = 0; k < nsum; ++k) column[k] = X[k][j];
    linear_combination(nsum, c, column, Z[j]);
  }
  return 0;
}

// --- the sparse matrix ----------------------------------------------------------------------------------

/// SUNMatZero: every stored value, row index and column pointer 0 (as SUNDIALS' SUNMatZero_Sparse).
int zero_sparse(SUNMatrix a) {
  const sunindextype nnz = SUNSparseMatrix_NNZ(a);
  std::fill_n(SUNSparseMatrix_Data(a), nnz, 0.0);
  std::fill_n(SUNSparseMatrix_IndexValues(a), nnz, sunindextype{0});
  std::fill_n(SUNSparseMatrix_IndexPointers(a), SUNSparseMatrix_NP(a) + 1, sunindextype{0});
  return 0;
}

}  // namespace

void use_fast_sparse_kernels(SUNMatrix a) {
  a->ops->zero = zero_sparse;
}

void use_fast_serial_kernels(N_Vector v) {
  N_Vector_Ops ops = v->ops;
  ops->nvlinearsum = linear_sum;
  ops->nvconst = constant;
  ops->nvprod = product;
  ops->nvdiv = quotient;
  ops->nvscale = scale;
  ops->nvabs = absolute;
  ops->nvinv = inverse;
  ops->nvaddconst = add_constant;
  ops->nvdotprod = dot;
  ops->nvmaxnorm = max_norm;
  ops->nvwrmsnorm = wrms_norm;
  ops->nvwrmsnormmask = wrms_norm_mask;
  ops->nvmin = minimum;
  ops->nvwl2norm = weighted_l2_norm;
  ops->nvl1norm = l1_norm;
  ops->nvcompare = compare;
  ops->nvinvtest = inverse_test;
  ops->nvconstrmask = constraint_mask;
  ops->nvminquotient = min_quotient;

  ops->nvlinearcombination = linear_combination;
  ops->nvscaleaddmulti = scale_add_multi;
  ops->nvdotprodmulti = dot_multi;

  ops->nvlinearsumvectorarray = linear_sum_array;
  ops->nvscalevectorarray = scale_array;
  ops->nvconstvectorarray = constant_array;
  ops->nvwrmsnormvectorarray = wrms_norm_array;
  ops->nvwrmsnormmaskvectorarray = wrms_norm_mask_array;
  ops->nvscaleaddmultivectorarray = scale_add_multi_array;
  ops->nvlinearcombinationvectorarray = linear_combination_array;

  ops->nvdotprodlocal = dot;
  ops->nvmaxnormlocal = max_norm;
  ops->nvminlocal = minimum;
  ops->nvl1normlocal = l1_norm;
  ops->nvinvtestlocal = inverse_test;
  ops->nvconstrmasklocal = constraint_mask;
  ops->nvminquotientlocal = min_quotient;
  ops->nvwsqrsumlocal = weighted_square_sum;
  ops->nvwsqrsummasklocal = weighted_square_sum_mask;
}

}  // namespace nvh::solve
