#pragma once
// The linear solver of IDA's Newton iteration: sparse LU (KLU) or dense LU (LAPACK dgetrf / dgetrs, as
// OpenBLAS provides them: blocked, vectorized kernels chosen for the CPU at run time).
//
// Why two. The Newton matrix J = dF/dy + cj dF/dy' of a multibody model is sparse where bodies are rigid and
// joints few, and nearly dense where flexible bodies are: a Craig-Bampton body of m coordinates brings dense
// m x m blocks of its mass and stiffness and couples them to every body its markers touch. On the 4-cylinder
// engine (358 unknowns, 45 + 20 modes) 44 % of J is stored, and KLU (left-looking, column by column, no dense
// kernels) refactorizes it in 4.1 ms and factorizes it in 7.7 ms, where LAPACK's dgetrf on the same matrix
// takes 0.9 ms and its solves 0.02 ms instead of 0.05 (bench/README.md, "The Newton matrix"). KLU is driven
// by this file's own SUNDIALS linear solver (make_sparse_lu_solver): SUNDIALS' SUNLinSol_KLU analyzed the
// pattern again at every IDAReInit (every contact event) and let a lightly damped mode grow from round-off on
// the valvetrain bridge (newton_matrix_solver.cpp says how).
//
// `choose_newton_solver` decides from the sparsity pattern alone (deterministic: a scene always gets the same
// arithmetic, and a restarted run the same solver as an uninterrupted one). KLU's symbolic analysis (AMD)
// estimates its fill and factorization flops; with the rates measured on this code's matrices
// (bench/README.md "The Newton matrix": KLU ~2.7 Gflop/s in its refactorization and ~3 in its solves,
// OpenBLAS's dgetrf ~28 Gflop/s and its solves ~12), dense LU is chosen where its estimated cost of one
// factorization and kSolvesPerSetup solves is below 0.7 of KLU's.
// `[integrator] linear_solver` overrides it.
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nvector.h>

#include <span>
#include <string>

namespace nvh::solve {

enum class NewtonSolver { kKlu, kDense };

/// The choice and what it rests on (estimated seconds of one setup and kSolvesPerSetup solves).
struct NewtonSolverChoice {
  NewtonSolver kind = NewtonSolver::kKlu;
  double klu_cost_s = 0, dense_cost_s = 0;  // 0 when not estimated (an explicit setting)
};

/// Newton iterations (solves) per Jacobian (factorization) assumed by the choice: measured 10 on the engine
/// with finite bearings, 15 on the lubricated engine, 48 on the compressor, 52 on the valvetrain.
inline constexpr double kSolvesPerSetup = 20;

/// `setting`: "auto" (the cheaper for this pattern, as above), "klu" or "dense" (the scene reader validates
/// the key). The pattern is CSC: column_start (n + 1), rows.
NewtonSolverChoice choose_newton_solver(const std::string& setting, int unknowns,
                                        std::span<const int> column_start, std::span<const int> rows);

/// "klu" or "dense".
const char* to_string(NewtonSolver kind);

/// The SUNDIALS linear solver for IDA's sparse (CSC) Newton matrix A: KLU or the dense LU, both below.
/// The caller owns it (SUNLinSolFree).
SUNLinearSolver make_newton_solver(NewtonSolver kind, SUNMatrix a, SUNContext ctx);

/// A direct SUNDIALS linear solver that scatters the SUNSparseMatrix (CSC) it is given into a dense
/// column-major array and factorizes it by LAPACK's dgetrf (partial pivoting); solves by dgetrs. A singular
/// matrix is a recoverable setup failure (IDA then takes a shorter step), as with KLU.
SUNLinearSolver make_dense_lu_solver(long unknowns, SUNContext ctx);

/// KLU (sparse LU) as a SUNDIALS direct linear solver for the same CSC matrix: the symbolic analysis once, a
/// refactorization per setup (a fresh factorization when its condition estimate collapses), one step of
/// iterative refinement per solve (newton_matrix_solver.cpp).
SUNLinearSolver make_sparse_lu_solver(long unknowns, SUNContext ctx);

}  // namespace nvh::solve
