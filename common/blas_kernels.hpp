#pragma once
// Which kernels the BLAS under CHOLMOD runs, and a fix for one case where they are far too slow.
//
// OpenBLAS (Debian 12: 0.3.21) picks its kernels from the CPU model when it is loaded and falls back to
// its Prescott (SSE3) kernels for models it does not know - seen on this project's machines: a Xeon of
// family 6, model 207 (Emerald Rapids) in a virtual machine. CHOLMOD's supernodal factorization then
// runs 2.2 times slower (240k-DOF engine block: 8.8 s instead of 3.9 s). The choice can only be
// changed before the library loads, through the environment variable OPENBLAS_CORETYPE.
#include <string>

namespace nvh {

/// The BLAS kernels in use, for reports: "OpenBLAS SkylakeX", ..., or "not OpenBLAS" (the reference BLAS
/// or another library).
std::string blas_kernels();

/// If the loaded BLAS is OpenBLAS running its Prescott fall-back, OPENBLAS_CORETYPE is not set and the
/// CPU has AVX-512 (or AVX2 and FMA), re-execute this program (/proc/self/exe, the same argv) with
/// OPENBLAS_CORETYPE=SkylakeX (Haswell). Returns normally when there is nothing to do or the re-execution
/// fails (the run then goes on with the slow kernels). Call it first in main(), before any output.
void select_blas_kernels(char** argv);

}  // namespace nvh
