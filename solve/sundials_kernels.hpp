#pragma once
// Optimized arithmetic for SUNDIALS' serial N_Vector and sparse SUNMatrix, installed into their operation
// tables.
//
// Why. Debian 12's libsundials (6.4.1) is compiled without optimization: its serial vector kernels keep
// every loop index and pointer on the stack (objdump of N_VLinearSum_Serial in libsundials_ida.so.6: a load
// and a store through %rbp per operand, no SIMD) and take about 27 instructions per vector entry. On the
// valvetrain scene (114 unknowns, 22k IDA steps) they were a quarter of solve's instructions (callgrind,
// bench/README.md "IDA's vector kernels"), and IDA's N_VLinearCombination, without a fused kernel in the
// serial vector, fell back to one N_VLinearSum pass per history vector. SUNMatZero_Sparse, which IDA calls
// before every Jacobian, was another 1.6 %.
//
// What. `use_fast_serial_kernels(v)` replaces the arithmetic entries of v's operation table (SUNDIALS 6,
// sundials_nvector.h: the standard operations, the fused and vector-array operations and the local
// reductions) by the loops of sundials_kernels.cpp, compiled with this project's flags. Each computes what
// the SUNDIALS documentation of the operation defines (user guide, "Description of the NVECTOR
// operations"), so IDA's results change only by round-off. The constructors, the data access and
// everything else stay SUNDIALS' own. Vectors cloned from v (N_VClone copies the table: every vector IDA
// makes from y0) inherit the kernels. `use_fast_sparse_kernels(a)` does the same for a sparse matrix's
// SUNMatZero.
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_sparse.h>

namespace nvh::solve {

/// Installs the kernels into a serial vector's operation table (v from N_VNew_Serial or a clone of one).
void use_fast_serial_kernels(N_Vector v);

/// Installs a SUNMatZero kernel into a sparse matrix's operation table (a from SUNSparseMatrix).
void use_fast_sparse_kernels(SUNMatrix a);

}  // namespace nvh::solve
