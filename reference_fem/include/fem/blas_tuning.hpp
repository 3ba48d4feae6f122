// OpenBLAS chooses its kernels when the library is loaded, from the CPU model.
// Virtual machines that hide the model get the generic SSE3 kernels, which make
// the FEM reference's sparse direct solves about twice as slow. When the CPU has
// AVX2 and FMA and OPENBLAS_CORETYPE is not set, this sets it to Haswell and
// re-executes the program so the loader sees it (before MPI starts; the process
// keeps its id, so mpirun is unaffected). Set TISSUEBENCH_NO_BLAS_TUNING=1 to
// skip it.
#pragma once

#include <cstdlib>

#include <unistd.h>

namespace fem {

inline void tune_blas_and_reexec(char** argv) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (std::getenv("OPENBLAS_CORETYPE") || std::getenv("TISSUEBENCH_NO_BLAS_TUNING")) return;
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) return;
  setenv("OPENBLAS_CORETYPE", "Haswell", 1);
  execv("/proc/self/exe", argv);  // returns only if exec failed: carry on untuned
#else
  (void)argv;
#endif
}

}  // namespace fem
