// DIPC_HD marks point functions that run both on the CPU and inside CUDA kernels.
// Files that use it must not call the CUDA runtime, MPI or PETSc.
#pragma once
#if defined(__CUDACC__)
#define DIPC_HD __host__ __device__ inline
#else
#define DIPC_HD inline
#endif
