// Dense and sparse LU for IDA's Newton matrix (see newton_matrix_solver.hpp).
#include "solve/newton_matrix_solver.hpp"

#include <klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <vector>

// LAPACK (Fortran calling convention; the library is OpenBLAS's through Debian's liblapack.so.3).
extern "C" {
void dgetrf_(const int* m, const int* n, double* a, const int* lda, int* ipiv, int* info);
void dgetrs_(const char* trans, const int* n, const int* nrhs, const double* a, const int* lda,
             const int* ipiv, double* b, const int* ldb, int* info, std::size_t trans_length);
}

namespace nvh::solve {

const char* to_string(NewtonSolver kind) {
  return kind == NewtonSolver::kDense ? "dense" : "klu";
}

NewtonSolverChoice choose_newton_solver(const std::string& setting, int unknowns,
                                        std::span<const int> column_start, std::span<const int> rows) {
  NewtonSolverChoice choice;
  if (setting == "klu" || setting == "dense") {
    choice.kind = setting == "dense" ? NewtonSolver::kDense : NewtonSolver::kKlu;
    return choice;
  }
  // Below 100 unknowns either factorizes in microseconds, and KLU keeps the arithmetic of the small scenes
  // as it was (tests compare two formulations of one model to 1e-9); above 3000 the dense matrix (72 MB)
  // and its 2/3 n^3 flops outgrow any fill met so far.
  if (unknowns < 100 || unknowns > 3000) return choice;
  // KLU's symbolic analysis of the pattern (AMD ordering, no values): its estimated flops and fill.
  klu_common common;
  klu_defaults(&common);
  klu_symbolic* symbolic =
      klu_analyze(unknowns, const_cast<int*>(column_start.data()), const_cast<int*>(rows.data()), &common);
  if (symbolic == nullptr) return choice;  // KLU will report the problem itself
  const double klu_flops = symbolic->est_flops, klu_entries = symbolic->lnz + symbolic->unz;
  klu_free_symbolic(&symbolic, &common);
  // Rates measured on the Newton matrices of the engine (358 unknowns), the compressor (375) and the
  // valvetrain (144) (bench/README.md "The Newton matrix"). The dense solve includes the refinement step
  // (two solves and a sparse product).
  const double n = unknowns;
  constexpr double kKluFactor = 2.7e9, kKluSolve = 3e9, kDenseFactor = 28e9, kDenseSolve = 12e9;  // flop/s
  choice.klu_cost_s = klu_flops / kKluFactor + kSolvesPerSetup * 2 * klu_entries / kKluSolve;
  choice.dense_cost_s = 2.0 / 3.0 * n * n * n / kDenseFactor +
                        kSolvesPerSetup * (4 * n * n + 2.0 * double(rows.size())) / kDenseSolve;
  // Dense only where clearly cheaper: near the crossover the model errs (the valvetrain's matrix: predicted
  // 0.24 ms dense against 0.25 ms KLU, measured 20 % slower dense over a run - small n runs the dense kernels
  // below the rates above).
  constexpr double kMargin = 0.7;
  choice.kind = choice.dense_cost_s < kMargin * choice.klu_cost_s ? NewtonSolver::kDense : NewtonSolver::kKlu;
  return choice;
}

namespace {

struct DenseLu {
  int n = 0;
  std::vector<double> lu;  // column-major n x n: the scaled matrix, then its LU factors
  std::vector<int> pivots;
  std::vector<double> row_scale;  // 1 / max |a_ij| of each row (as KLU's default scaling)
  std::vector<double> residual;   // of the refinement step
  sunindextype last_flag = 0;
};

DenseLu& content(SUNLinearSolver s) {
  return *static_cast<DenseLu*>(s->content);
}

SUNLinearSolver_Type dense_type(SUNLinearSolver) {
  return SUNLINEARSOLVER_DIRECT;
}
SUNLinearSolver_ID dense_id(SUNLinearSolver) {
  return SUNLINEARSOLVER_CUSTOM;
}
int dense_initialize(SUNLinearSolver s) {
  content(s).last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

int dense_setup(SUNLinearSolver s, SUNMatrix a) {
  DenseLu& d = content(s);
  if (SUNMatGetID(a) != SUNMATRIX_SPARSE || SUNSparseMatrix_SparseType(a) != CSC_MAT ||
      SUNSparseMatrix_Rows(a) != d.n || SUNSparseMatrix_Columns(a) != d.n) {
    d.last_flag = SUNLS_ILL_INPUT;
    return SUNLS_ILL_INPUT;
  }
  const sunindextype* start = SUNSparseMatrix_IndexPointers(a);
  const sunindextype* row = SUNSparseMatrix_IndexValues(a);
  const double* value = SUNSparseMatrix_Data(a);
  // Rows scaled to a largest entry of 1 before partial pivoting: the Newton matrix's rows differ by many
  // orders (the constraints' against the dynamics' scaled by cj), and unscaled pivoting lets the large rows
  // choose, which cost the constraints digits (a speed driver's speed, a test of tests/solve).
  std::fill(d.lu.begin(), d.lu.end(), 0.0);
  std::fill(d.row_scale.begin(), d.row_scale.end(), 0.0);
  for (int c = 0; c < d.n; ++c) {
    double* column = d.lu.data() + static_cast<std::size_t>(c) * d.n;
    for (sunindextype k = start[c]; k < start[c + 1]; ++k) column[row[k]] += value[k];
  }
  for (int c = 0; c < d.n; ++c) {
    const double* column = d.lu.data() + static_cast<std::size_t>(c) * d.n;
    for (sunindextype k = start[c]; k < start[c + 1]; ++k)
      d.row_scale[row[k]] = std::max(d.row_scale[row[k]], std::abs(column[row[k]]));
  }
  for (double& s : d.row_scale) s = s > 0 ? 1 / s : 1.0;  // an empty row: singular, dgetrf says so
  for (int c = 0; c < d.n; ++c) {
    double* column = d.lu.data() + static_cast<std::size_t>(c) * d.n;
    for (sunindextype k = start[c]; k < start[c + 1]; ++k) column[row[k]] *= d.row_scale[row[k]];
  }
  int info = 0;
  dgetrf_(&d.n, &d.n, d.lu.data(), &d.n, d.pivots.data(), &info);
  // info > 0: an exactly zero pivot (singular). Recoverable, as KLU's SUNLS_LUFACT_FAIL: IDA cuts the step.
  d.last_flag = info == 0 ? SUNLS_SUCCESS : info > 0 ? SUNLS_LUFACT_FAIL : SUNLS_PACKAGE_FAIL_UNREC;
  return static_cast<int>(d.last_flag);
}

int dense_solve(SUNLinearSolver s, SUNMatrix a, N_Vector x, N_Vector b, realtype) {
  DenseLu& d = content(s);
  N_VScale(1.0, b, x);
  double* v = N_VGetArrayPointer(x);
  for (int i = 0; i < d.n; ++i) v[i] *= d.row_scale[i];  // (R A) x = R b
  const int one = 1;
  int info = 0;
  dgetrs_("N", &d.n, &one, d.lu.data(), &d.n, d.pivots.data(), v, &d.n, &info, 1);
  if (info == 0) {
    // One step of iterative refinement against the sparse A: r = R (b - A x), x += (R A)^-1 r. It costs a
    // sparse product and a second pair of triangular solves, and recovers the digits the Newton matrix's
    // condition (1/h^2 for index-2 constraints) takes: on Simeon's slider crank at rtol 1e-10 the
    // multipliers' error fell from 3.7e-6 to 1.2e-7 and the steps from 59,733 to 53,903
    // (tests/solve/test_simeon_crank.cpp).
    const sunindextype* start = SUNSparseMatrix_IndexPointers(a);
    const sunindextype* row = SUNSparseMatrix_IndexValues(a);
    const double* value = SUNSparseMatrix_Data(a);
    const double* bb = N_VGetArrayPointer(b);
    d.residual.assign(bb, bb + d.n);
    for (int c = 0; c < d.n; ++c)
      for (sunindextype k = start[c]; k < start[c + 1]; ++k) d.residual[row[k]] -= value[k] * v[c];
    for (int i = 0; i < d.n; ++i) d.residual[i] *= d.row_scale[i];
    dgetrs_("N", &d.n, &one, d.lu.data(), &d.n, d.pivots.data(), d.residual.data(), &d.n, &info, 1);
    for (int i = 0; i < d.n; ++i) v[i] += d.residual[i];
  }
  d.last_flag = info == 0 ? SUNLS_SUCCESS : SUNLS_PACKAGE_FAIL_UNREC;
  return static_cast<int>(d.last_flag);
}

sunindextype dense_last_flag(SUNLinearSolver s) {
  return content(s).last_flag;
}

int dense_space(SUNLinearSolver s, long* real_words, long* integer_words) {
  const DenseLu& d = content(s);
  *real_words = static_cast<long>(d.lu.size() + d.row_scale.size());
  *integer_words = static_cast<long>(d.pivots.size());
  return SUNLS_SUCCESS;
}

int dense_free(SUNLinearSolver s) {
  if (s == nullptr) return SUNLS_SUCCESS;
  delete static_cast<DenseLu*>(s->content);
  s->content = nullptr;
  SUNLinSolFreeEmpty(s);
  return SUNLS_SUCCESS;
}

// ------------------------------------------------------------------ sparse LU: KLU
/// KLU on IDA's CSC matrix (sunindextype = long: KLU's "l" interface), in place of SUNDIALS' SUNLinSol_KLU.
/// The symbolic analysis (BTF, then AMD on each block: KLU's default) is made once for the model's fixed
/// pattern; SUNDIALS' solver analyzed again (COLAMD) after every IDAReInit, i.e. at every contact event. The
/// first setup after IDA's start or a restart factorizes with partial pivoting; the others refactorize with
/// the last pivot order, and factorize afresh when that fails or its reciprocal condition estimate falls
/// below uround^(2/3) (SUNDIALS' rule, less its klu_condest, which takes several solves). Measured on the
/// bridge scene with the flexible rocker (bench/README.md "IDA's vector kernels and KLU"): SUNDIALS' solver
/// let the bridge's tilt between the valves - a lightly damped mode that the pads alone hold, exactly 0 by
/// the scene's symmetry - grow from round-off (1e-30 rad/s) to 0.1 rad/s within 120 cam deg under BDF order
/// 5, unseen by the error test until it changed the cam force by 7 %; with this one it stays at 1e-27 rad/s,
/// as with the dense solver. No iterative refinement (as SUNDIALS' KLU): one more solve and product per
/// iteration cost 7 % on the valvetrain and changed nothing measured.
struct SparseLu {
  long n = 0;
  klu_l_common common{};
  klu_l_symbolic* symbolic = nullptr;
  klu_l_numeric* numeric = nullptr;
  sunindextype last_flag = 0;
  ~SparseLu() {
    if (numeric) klu_l_free_numeric(&numeric, &common);
    if (symbolic) klu_l_free_symbolic(&symbolic, &common);
  }
};

SparseLu& klu_content(SUNLinearSolver s) {
  return *static_cast<SparseLu*>(s->content);
}
/// IDA initializes its linear solver at the start and after every IDAReInit (each contact event): the next
/// setup factorizes with fresh pivots (the symbolic analysis is kept).
int klu_initialize(SUNLinearSolver s) {
  SparseLu& k = klu_content(s);
  if (k.numeric) klu_l_free_numeric(&k.numeric, &k.common);
  k.last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

int klu_setup(SUNLinearSolver s, SUNMatrix a) {
  SparseLu& k = klu_content(s);
  if (SUNMatGetID(a) != SUNMATRIX_SPARSE || SUNSparseMatrix_SparseType(a) != CSC_MAT ||
      SUNSparseMatrix_Rows(a) != k.n || SUNSparseMatrix_Columns(a) != k.n) {
    k.last_flag = SUNLS_ILL_INPUT;
    return SUNLS_ILL_INPUT;
  }
  auto* start = reinterpret_cast<long*>(SUNSparseMatrix_IndexPointers(a));
  auto* row = reinterpret_cast<long*>(SUNSparseMatrix_IndexValues(a));
  double* value = SUNSparseMatrix_Data(a);
  if (k.symbolic == nullptr) {
    k.symbolic = klu_l_analyze(k.n, start, row, &k.common);
    if (k.symbolic == nullptr) {
      k.last_flag = SUNLS_PACKAGE_FAIL_UNREC;
      return SUNLS_PACKAGE_FAIL_UNREC;
    }
  }
  bool fresh = k.numeric == nullptr;
  if (!fresh) {
    const bool refactored = klu_l_refactor(start, row, value, k.symbolic, k.numeric, &k.common) != 0;
    fresh = !refactored || klu_l_rcond(k.symbolic, k.numeric, &k.common) == 0 ||
            k.common.rcond < std::pow(std::numeric_limits<double>::epsilon(), 2.0 / 3.0);
    if (fresh) klu_l_free_numeric(&k.numeric, &k.common);
  }
  if (fresh) {
    k.numeric = klu_l_factor(start, row, value, k.symbolic, &k.common);
    if (k.numeric == nullptr) {  // singular: recoverable, IDA takes a shorter step
      k.last_flag = k.common.status == KLU_SINGULAR ? SUNLS_LUFACT_FAIL : SUNLS_PACKAGE_FAIL_UNREC;
      return static_cast<int>(k.last_flag);
    }
  }
  k.last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

int klu_solve(SUNLinearSolver s, SUNMatrix, N_Vector x, N_Vector b, realtype) {
  SparseLu& k = klu_content(s);
  N_VScale(1.0, b, x);
  double* v = N_VGetArrayPointer(x);
  if (klu_l_solve(k.symbolic, k.numeric, k.n, 1, v, &k.common) == 0) {
    k.last_flag = SUNLS_PACKAGE_FAIL_UNREC;
    return SUNLS_PACKAGE_FAIL_UNREC;
  }
  k.last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

sunindextype klu_last_flag(SUNLinearSolver s) {
  return klu_content(s).last_flag;
}
int klu_free(SUNLinearSolver s) {
  if (s == nullptr) return SUNLS_SUCCESS;
  delete static_cast<SparseLu*>(s->content);
  s->content = nullptr;
  SUNLinSolFreeEmpty(s);
  return SUNLS_SUCCESS;
}

}  // namespace

SUNLinearSolver make_sparse_lu_solver(long unknowns, SUNContext ctx) {
  SUNLinearSolver s = SUNLinSolNewEmpty(ctx);
  if (s == nullptr) throw std::bad_alloc();
  s->ops->gettype = dense_type;  // direct
  s->ops->getid = dense_id;      // custom
  s->ops->initialize = klu_initialize;
  s->ops->setup = klu_setup;
  s->ops->solve = klu_solve;
  s->ops->lastflag = klu_last_flag;
  s->ops->free = klu_free;
  auto* k = new SparseLu;
  k->n = unknowns;
  klu_l_defaults(&k->common);
  s->content = k;
  return s;
}

SUNLinearSolver make_dense_lu_solver(long unknowns, SUNContext ctx) {
  SUNLinearSolver s = SUNLinSolNewEmpty(ctx);
  if (s == nullptr) throw std::bad_alloc();
  s->ops->gettype = dense_type;
  s->ops->getid = dense_id;
  s->ops->initialize = dense_initialize;
  s->ops->setup = dense_setup;
  s->ops->solve = dense_solve;
  s->ops->lastflag = dense_last_flag;
  s->ops->space = dense_space;
  s->ops->free = dense_free;
  auto* d = new DenseLu;
  d->n = static_cast<int>(unknowns);
  d->lu.assign(static_cast<std::size_t>(unknowns) * unknowns, 0.0);
  d->pivots.assign(unknowns, 0);
  d->row_scale.assign(unknowns, 1.0);
  s->content = d;
  return s;
}

SUNLinearSolver make_newton_solver(NewtonSolver kind, SUNMatrix a, SUNContext ctx) {
  if (kind == NewtonSolver::kDense) return make_dense_lu_solver(SUNSparseMatrix_Rows(a), ctx);
  return make_sparse_lu_solver(SUNSparseMatrix_Rows(a), ctx);
}

}  // namespace nvh::solve
