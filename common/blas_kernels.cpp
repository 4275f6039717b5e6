#include "common/blas_kernels.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace nvh {
namespace {

/// OpenBLAS's own report of its kernels (nullptr if the BLAS loaded is not OpenBLAS).
const char* openblas_corename() {
  using Corename = char* (*)();
  const auto corename = reinterpret_cast<Corename>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  return corename != nullptr ? corename() : nullptr;
}

/// The best OpenBLAS kernel family this CPU runs ("" if none beyond SSE3 is known here).
const char* best_coretype() {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
      __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
      __builtin_cpu_supports("avx512vl")) {
    return "SkylakeX";
  }
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return "Haswell";
  return "";
}

}  // namespace

std::string blas_kernels() {
  const char* name = openblas_corename();
  return name != nullptr ? std::string("OpenBLAS ") + name : std::string("not OpenBLAS");
}

void select_blas_kernels(char** argv) {
  if (std::getenv("OPENBLAS_CORETYPE") != nullptr) return;  // the user's choice, or our re-execution
  const char* name = openblas_corename();
  if (name == nullptr) return;
  std::string current(name);
  std::transform(current.begin(), current.end(), current.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const char* best = best_coretype();
  if (current != "prescott" || *best == '\0') return;
  if (setenv("OPENBLAS_CORETYPE", best, 1) != 0) return;
  execv("/proc/self/exe", argv);
  unsetenv("OPENBLAS_CORETYPE");  // execv failed: go on as we are
}

}  // namespace nvh
