// The serial N_Vector kernels and the sparse zero of solve/sundials_kernels.hpp against SUNDIALS' own serial
// implementation (the reference: libsundials' N_V*_Serial, which a vector keeps until the kernels are
// installed), operation by operation, on random vectors whose length is not a multiple of the kernels'
// interleaving (four partial sums, up to eight vectors per pass), with the aliasing SUNDIALS allows (z == x,
// z == y, z == X[0]). Element-wise operations must agree exactly; reductions (four partial sums against one
// running sum) to round-off, 1e-14 relative. And an IDA run: the same steps as with SUNDIALS' kernels, the
// same end state to 1e-10.
#include <gtest/gtest.h>
#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "solve/sundials_kernels.hpp"

namespace nvh::solve {
namespace {

constexpr sunindextype kN = 37;  // 9 x 4 + 1: the partial sums' remainder is exercised

/// Two sets of the same random vectors: `ref` with SUNDIALS' serial kernels, `fast` with ours.
struct Pair {
  SUNContext ctx = nullptr;
  std::vector<N_Vector> ref, fast;
  Pair(int count, unsigned seed) {
    SUNContext_Create(nullptr, &ctx);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-2, 2);
    for (int k = 0; k < count; ++k) {
      N_Vector r = N_VNew_Serial(kN, ctx), f = N_VNew_Serial(kN, ctx);
      use_fast_serial_kernels(f);
      for (sunindextype i = 0; i < kN; ++i) NV_Ith_S(r, i) = NV_Ith_S(f, i) = u(rng);
      ref.push_back(r), fast.push_back(f);
    }
  }
  ~Pair() {
    for (N_Vector v : ref) N_VDestroy(v);
    for (N_Vector v : fast) N_VDestroy(v);
    SUNContext_Free(&ctx);
  }
  Pair(const Pair&) = delete;
  Pair& operator=(const Pair&) = delete;
  /// Vector k of both sets are equal entry by entry.
  void expect_equal(int k, const char* what) const {
    for (sunindextype i = 0; i < kN; ++i)
      ASSERT_DOUBLE_EQ(NV_Ith_S(fast[k], i), NV_Ith_S(ref[k], i)) << what << ", entry " << i;
  }
  void set(int k, sunindextype i, double v) { NV_Ith_S(ref[k], i) = NV_Ith_S(fast[k], i) = v; }
};

void expect_close(double fast, double ref, const char* what) {
  EXPECT_NEAR(fast, ref, 1e-14 * std::max(1.0, std::abs(ref))) << what;
}

TEST(SundialsKernels, ElementWiseOperationsEqualSundials) {
  Pair p(4, 1);
  auto both = [&](auto op) { op(p.ref), op(p.fast); };
  using V = std::vector<N_Vector>;
  both([](V& v) { N_VLinearSum(0.7, v[0], -1.3, v[1], v[2]); });
  p.expect_equal(2, "z = a x + b y");
  both([](V& v) { N_VLinearSum(1.0, v[0], 1.0, v[1], v[0]); });  // z == x
  p.expect_equal(0, "z == x, a = b = 1");
  both([](V& v) { N_VLinearSum(-1.0, v[0], 2.5, v[1], v[1]); });  // z == y
  p.expect_equal(1, "z == y");
  both([](V& v) { N_VScale(-3.0, v[0], v[3]); });
  p.expect_equal(3, "scale");
  both([](V& v) { N_VScale(0.5, v[3], v[3]); });
  p.expect_equal(3, "scale in place");
  both([](V& v) { N_VConst(4.25, v[2]); });
  p.expect_equal(2, "const");
  both([](V& v) { N_VProd(v[0], v[1], v[2]); });
  p.expect_equal(2, "product");
  both([](V& v) { N_VDiv(v[0], v[1], v[2]); });
  p.expect_equal(2, "quotient");
  both([](V& v) { N_VAbs(v[0], v[2]); });
  p.expect_equal(2, "abs");
  both([](V& v) { N_VInv(v[1], v[2]); });
  p.expect_equal(2, "inverse");
  both([](V& v) { N_VAddConst(v[0], -0.25, v[2]); });
  p.expect_equal(2, "add constant");
  both([](V& v) { N_VCompare(1.0, v[0], v[2]); });
  p.expect_equal(2, "compare");

  // inverse test and constraint mask: with a zero entry and with constraints of every kind
  p.set(1, 5, 0.0);
  booleantype ok_ref = N_VInvTest(p.ref[1], p.ref[2]), ok_fast = N_VInvTest(p.fast[1], p.fast[2]);
  EXPECT_EQ(ok_fast, ok_ref);
  EXPECT_EQ(ok_fast, SUNFALSE);
  p.expect_equal(2, "inverse test");
  for (sunindextype i = 0; i < kN; ++i) p.set(3, i, static_cast<double>(i % 5) - 2.0);  // -2 .. 2
  p.set(0, 7, 0.0);
  ok_ref = N_VConstrMask(p.ref[3], p.ref[0], p.ref[2]);
  ok_fast = N_VConstrMask(p.fast[3], p.fast[0], p.fast[2]);
  EXPECT_EQ(ok_fast, ok_ref);
  p.expect_equal(2, "constraint mask");
}

TEST(SundialsKernels, ReductionsEqualSundialsToRoundOff) {
  Pair p(3, 2);
  for (sunindextype i = 0; i < kN; ++i)
    p.set(2, i, i % 3 == 0 ? 0.0 : (i % 3 == 1 ? 1.0 : -1.0));  // the mask
  auto& r = p.ref;
  auto& f = p.fast;
  expect_close(N_VDotProd(f[0], f[1]), N_VDotProd(r[0], r[1]), "dot");
  expect_close(N_VMaxNorm(f[0]), N_VMaxNorm(r[0]), "max norm");
  expect_close(N_VWrmsNorm(f[0], f[1]), N_VWrmsNorm(r[0], r[1]), "wrms norm");
  expect_close(N_VWrmsNormMask(f[0], f[1], f[2]), N_VWrmsNormMask(r[0], r[1], r[2]), "wrms norm, mask");
  EXPECT_LT(N_VWrmsNormMask(f[0], f[1], f[2]), N_VWrmsNorm(f[0], f[1]));  // the mask drops entries
  expect_close(N_VMin(f[0]), N_VMin(r[0]), "min");
  expect_close(N_VWL2Norm(f[0], f[1]), N_VWL2Norm(r[0], r[1]), "weighted l2 norm");
  expect_close(N_VL1Norm(f[0]), N_VL1Norm(r[0]), "l1 norm");
  expect_close(N_VMinQuotient(f[0], f[2]), N_VMinQuotient(r[0], r[2]), "min quotient");
  expect_close(N_VWSqrSumLocal(f[0], f[1]), N_VWSqrSumLocal(r[0], r[1]), "weighted square sum");
  expect_close(N_VWSqrSumMaskLocal(f[0], f[1], f[2]), N_VWSqrSumMaskLocal(r[0], r[1], r[2]),
               "masked square sum");
}

TEST(SundialsKernels, FusedAndArrayOperationsEqualSundials) {
  // SUNDIALS' serial vector with its fused and array operations enabled is the reference for those.
  constexpr int kVectors = 12;  // more than one pass of eight
  Pair p(3 * kVectors + 2, 3);
  for (N_Vector v : p.ref) N_VEnableFusedOps_Serial(v, SUNTRUE);
  std::array<double, kVectors> c;
  for (int j = 0; j < kVectors; ++j) c[j] = 0.3 * j - 1.1;
  auto slice = [&](std::vector<N_Vector>& v, int first) { return v.data() + first; };
  for (int nvec : {1, 2, 3, 6, 8, 9, 12}) {
    N_VLinearCombination(nvec, c.data(), slice(p.ref, 0), p.ref[kVectors]);
    N_VLinearCombination(nvec, c.data(), slice(p.fast, 0), p.fast[kVectors]);
    for (sunindextype i = 0; i < kN; ++i)
      EXPECT_NEAR(NV_Ith_S(p.fast[kVectors], i), NV_Ith_S(p.ref[kVectors], i), 1e-14)
          << "combination of " << nvec;
  }
  // z == X[0], with c0 = 1 and c0 != 1
  for (double c0 : {1.0, -0.4}) {
    c[0] = c0;
    N_VLinearCombination(7, c.data(), slice(p.ref, 0), p.ref[0]);
    N_VLinearCombination(7, c.data(), slice(p.fast, 0), p.fast[0]);
    for (sunindextype i = 0; i < kN; ++i)
      EXPECT_NEAR(NV_Ith_S(p.fast[0], i), NV_Ith_S(p.ref[0], i), 1e-14) << "z == X[0], c0 = " << c0;
  }
  // Z_j = a_j x + Y_j
  N_VScaleAddMulti(4, c.data(), p.ref[1], slice(p.ref, 2), slice(p.ref, kVectors + 2));
  N_VScaleAddMulti(4, c.data(), p.fast[1], slice(p.fast, 2), slice(p.fast, kVectors + 2));
  for (int j = 0; j < 4; ++j) p.expect_equal(kVectors + 2 + j, "scale-add multi");
  std::array<double, kVectors> d_ref, d_fast;
  N_VDotProdMulti(5, p.ref[1], slice(p.ref, 2), d_ref.data());
  N_VDotProdMulti(5, p.fast[1], slice(p.fast, 2), d_fast.data());
  for (int j = 0; j < 5; ++j) expect_close(d_fast[j], d_ref[j], "dot multi");
  // arrays: Z_j = a X_j + b Y_j, Z_j = c_j X_j, Z_j = c, norms
  N_VLinearSumVectorArray(3, 0.5, slice(p.ref, 0), -2.0, slice(p.ref, 3), slice(p.ref, 2 * kVectors));
  N_VLinearSumVectorArray(3, 0.5, slice(p.fast, 0), -2.0, slice(p.fast, 3), slice(p.fast, 2 * kVectors));
  for (int j = 0; j < 3; ++j) p.expect_equal(2 * kVectors + j, "linear sum array");
  N_VScaleVectorArray(3, c.data(), slice(p.ref, 0), slice(p.ref, 0));
  N_VScaleVectorArray(3, c.data(), slice(p.fast, 0), slice(p.fast, 0));
  for (int j = 0; j < 3; ++j) p.expect_equal(j, "scale array in place");
  N_VWrmsNormVectorArray(3, slice(p.ref, 0), slice(p.ref, 3), d_ref.data());
  N_VWrmsNormVectorArray(3, slice(p.fast, 0), slice(p.fast, 3), d_fast.data());
  for (int j = 0; j < 3; ++j) expect_close(d_fast[j], d_ref[j], "wrms norm array");
  N_VWrmsNormMaskVectorArray(3, slice(p.ref, 0), slice(p.ref, 3), p.ref[6], d_ref.data());
  N_VWrmsNormMaskVectorArray(3, slice(p.fast, 0), slice(p.fast, 3), p.fast[6], d_fast.data());
  for (int j = 0; j < 3; ++j) expect_close(d_fast[j], d_ref[j], "wrms norm mask array");
  N_VConstVectorArray(2, 7.5, slice(p.ref, 8));
  N_VConstVectorArray(2, 7.5, slice(p.fast, 8));
  for (int j = 0; j < 2; ++j) p.expect_equal(8 + j, "const array");
  // Z[k][j] = a_k X_j + Y[k][j] and Z_j = sum_k c_k X[k][j]: 2 vectors, 3 sums
  N_Vector* yr[3] = {slice(p.ref, 10), slice(p.ref, 12), slice(p.ref, 14)};
  N_Vector* zr[3] = {slice(p.ref, 16), slice(p.ref, 18), slice(p.ref, 20)};
  N_Vector* yf[3] = {slice(p.fast, 10), slice(p.fast, 12), slice(p.fast, 14)};
  N_Vector* zf[3] = {slice(p.fast, 16), slice(p.fast, 18), slice(p.fast, 20)};
  N_VScaleAddMultiVectorArray(2, 3, c.data(), slice(p.ref, 0), yr, zr);
  N_VScaleAddMultiVectorArray(2, 3, c.data(), slice(p.fast, 0), yf, zf);
  for (int k = 16; k < 22; ++k) p.expect_equal(k, "scale-add multi array");
  N_VLinearCombinationVectorArray(2, 3, c.data(), yr, slice(p.ref, 22));
  N_VLinearCombinationVectorArray(2, 3, c.data(), yf, slice(p.fast, 22));
  for (int k = 22; k < 24; ++k)
    for (sunindextype i = 0; i < kN; ++i)
      EXPECT_NEAR(NV_Ith_S(p.fast[k], i), NV_Ith_S(p.ref[k], i), 1e-14) << "linear combination array";
}

TEST(SundialsKernels, SparseZeroEqualsSundials) {
  SUNContext ctx = nullptr;
  SUNContext_Create(nullptr, &ctx);
  SUNMatrix a = SUNSparseMatrix(5, 4, 9, CSC_MAT, ctx), b = SUNSparseMatrix(5, 4, 9, CSC_MAT, ctx);
  use_fast_sparse_kernels(b);
  for (SUNMatrix m : {a, b}) {
    for (int k = 0; k < 9; ++k)
      SUNSparseMatrix_Data(m)[k] = k + 1.0, SUNSparseMatrix_IndexValues(m)[k] = k % 5;
    for (int c = 0; c <= 4; ++c) SUNSparseMatrix_IndexPointers(m)[c] = 2 * c;
    ASSERT_EQ(SUNMatZero(m), 0);
  }
  for (int k = 0; k < 9; ++k) {
    EXPECT_EQ(SUNSparseMatrix_Data(b)[k], SUNSparseMatrix_Data(a)[k]);
    EXPECT_EQ(SUNSparseMatrix_IndexValues(b)[k], SUNSparseMatrix_IndexValues(a)[k]);
  }
  for (int c = 0; c <= 4; ++c)
    EXPECT_EQ(SUNSparseMatrix_IndexPointers(b)[c], SUNSparseMatrix_IndexPointers(a)[c]);
  SUNMatDestroy(a), SUNMatDestroy(b);
  SUNContext_Free(&ctx);
}

// IDA on the damped oscillator x'' + 2 zeta w x' + w^2 x = 0 written as a residual, once with SUNDIALS'
// kernels and once with ours: the same number of steps (the error test sees round-off only), the same end
// state, and both on the closed form.
struct Oscillator {
  static constexpr double w = 20.0, zeta = 0.05;
  static int residual(double, N_Vector y, N_Vector yp, N_Vector r, void*) {
    NV_Ith_S(r, 0) = NV_Ith_S(yp, 0) - NV_Ith_S(y, 1);
    NV_Ith_S(r, 1) = NV_Ith_S(yp, 1) + 2 * zeta * w * NV_Ith_S(y, 1) + w * w * NV_Ith_S(y, 0);
    return 0;
  }
  /// Integrates to t = 1 s; returns the steps, and x(1) in `x`.
  static long run(bool fast, double& x) {
    SUNContext ctx = nullptr;
    SUNContext_Create(nullptr, &ctx);
    N_Vector y = N_VNew_Serial(2, ctx), yp = N_VNew_Serial(2, ctx);
    if (fast) use_fast_serial_kernels(y), use_fast_serial_kernels(yp);
    NV_Ith_S(y, 0) = 1, NV_Ith_S(y, 1) = 0;
    NV_Ith_S(yp, 0) = 0, NV_Ith_S(yp, 1) = -w * w;
    void* mem = IDACreate(ctx);
    IDAInit(mem, residual, 0.0, y, yp);
    IDASStolerances(mem, 1e-10, 1e-12);
    IDASetMaxNumSteps(mem, 100000);
    SUNMatrix j = SUNDenseMatrix(2, 2, ctx);
    SUNLinearSolver ls = SUNLinSol_Dense(y, j, ctx);
    IDASetLinearSolver(mem, ls, j);
    double t = 0;
    IDASolve(mem, 1.0, &t, y, yp, IDA_NORMAL);
    long steps = 0;
    IDAGetNumSteps(mem, &steps);
    x = NV_Ith_S(y, 0);
    IDAFree(&mem);
    SUNLinSolFree(ls), SUNMatDestroy(j);
    N_VDestroy(y), N_VDestroy(yp);
    SUNContext_Free(&ctx);
    return steps;
  }
};

TEST(SundialsKernels, IdaTakesTheSameStepsAndReachesTheClosedForm) {
  double x_ref = 0, x_fast = 0;
  const long steps_ref = Oscillator::run(false, x_ref), steps_fast = Oscillator::run(true, x_fast);
  const double wd = Oscillator::w * std::sqrt(1 - Oscillator::zeta * Oscillator::zeta);
  const double closed = std::exp(-Oscillator::zeta * Oscillator::w) *
                        (std::cos(wd) + Oscillator::zeta * Oscillator::w / wd * std::sin(wd));
  EXPECT_EQ(steps_fast, steps_ref);
  EXPECT_NEAR(x_fast, x_ref, 1e-10);
  EXPECT_NEAR(x_fast, closed, 1e-7);
}

}  // namespace
}  // namespace nvh::solve
