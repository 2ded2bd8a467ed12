/* cuda_call_census: counts and times the CUDA runtime and MPI calls of a process, to find what
 * grows when a run goes from one GPU to several (issue 30: "find and remove what grows", where
 * no system profiler runs on the lent GPU machines).
 *
 *   mpirun -n 2 -x LD_PRELOAD=build-cuda/bench/libcuda_call_census.so dipc ...
 *
 * (built with -DDIPC_WITH_CUDA=ON; docs/performance.md, "Two and four GPUs", has what it found).
 *
 * Each wrapped call is timed around the real one (found with dlsym(RTLD_NEXT)), so a
 * synchronising call counts the wait it causes. At exit every process prints one line per
 * call that happened: calls, seconds and bytes moved (memory copies, MPI messages of the
 * point-to-point calls), prefixed by its MPI rank (Open MPI's or PMI's environment).
 * CENSUS_FILE=PREFIX writes PREFIX.<rank> instead of stderr. CENSUS_TRACE=NAME:N prints the call
 * stack (to stderr) of every N-th call of NAME (a name of the table below), 8 times at most:
 * where a call comes from that is made far more often than expected.
 *
 * Only shared libraries' calls are seen (libcudart.so, libmpi.so): dipc, PETSc and hypre link
 * both dynamically in the CUDA builds. MPI calls are caught through the MPI standard's
 * profiling interface (each MPI_X calls PMPI_X). */
#define _GNU_SOURCE
#include <cuda_runtime_api.h>
#include <dlfcn.h>
#include <execinfo.h>
#include <mpi.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum {
  MEMCPY_D2H, MEMCPY_H2D, MEMCPY_D2D, MEMCPY_OTHER, MEMCPY_ASYNC, MEMSET, MEMSET_ASYNC,
  MALLOC, FREE, MALLOC_HOST, FREE_HOST, HOST_ALLOC, MALLOC_ASYNC, FREE_ASYNC,
  STREAM_SYNC, DEVICE_SYNC, EVENT_SYNC, LAUNCH,
  MPI_ALLREDUCE, MPI_IALLREDUCE, MPI_REDUCE, MPI_BCAST, MPI_BARRIER, MPI_ALLGATHER, MPI_ALLGATHERV,
  MPI_ALLTOALL, MPI_ALLTOALLV, MPI_ISEND, MPI_IRECV, MPI_SEND, MPI_RECV, MPI_WAIT, MPI_WAITALL,
  MPI_WAITANY, MPI_STARTALL, NUM_KINDS
};
static const char* const kNames[NUM_KINDS] = {
  "cudaMemcpy D2H", "cudaMemcpy H2D", "cudaMemcpy D2D", "cudaMemcpy other", "cudaMemcpyAsync", "cudaMemset",
  "cudaMemsetAsync", "cudaMalloc", "cudaFree", "cudaMallocHost", "cudaFreeHost", "cudaHostAlloc",
  "cudaMallocAsync", "cudaFreeAsync", "cudaStreamSynchronize", "cudaDeviceSynchronize",
  "cudaEventSynchronize", "cudaLaunchKernel",
  "MPI_Allreduce", "MPI_Iallreduce", "MPI_Reduce", "MPI_Bcast", "MPI_Barrier", "MPI_Allgather",
  "MPI_Allgatherv", "MPI_Alltoall", "MPI_Alltoallv", "MPI_Isend", "MPI_Irecv", "MPI_Send", "MPI_Recv",
  "MPI_Wait", "MPI_Waitall", "MPI_Waitany", "MPI_Startall"};

static _Atomic long calls_[NUM_KINDS], nanoseconds_[NUM_KINDS], bytes_[NUM_KINDS];

static long now_ns(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec * 1000000000L + t.tv_nsec;
}

/* CENSUS_TRACE: the kind traced (-1: none, -2: not read yet) and every how many calls. */
static int trace_kind_ = -2;
static long trace_every_ = 0;
static _Atomic int traces_ = 0;

static void trace(int kind, long call) {
  if (trace_kind_ == -2) {
    trace_kind_ = -1;
    const char* spec = getenv("CENSUS_TRACE");
    const char* colon = spec ? strchr(spec, ':') : NULL;
    for (int k = 0; colon && k < NUM_KINDS; ++k)
      if (strlen(kNames[k]) == (size_t)(colon - spec) && !strncmp(kNames[k], spec, colon - spec)) {
        trace_kind_ = k;
        trace_every_ = atol(colon + 1);
      }
  }
  if (kind != trace_kind_ || trace_every_ <= 0 || call % trace_every_ || atomic_fetch_add(&traces_, 1) >= 8) return;
  void* frames[24];
  const int n = backtrace(frames, 24);
  fprintf(stderr, "census trace: call %ld of %s\n", call, kNames[kind]);
  backtrace_symbols_fd(frames, n, 2);
}

static void count(int kind, long start, long bytes) {
  trace(kind, atomic_fetch_add(&calls_[kind], 1) + 1);
  atomic_fetch_add(&nanoseconds_[kind], now_ns() - start);
  atomic_fetch_add(&bytes_[kind], bytes);
}

/* The next definition of `name` after this library's (the CUDA runtime's). */
static void* real(const char* name) {
  void* f = dlsym(RTLD_NEXT, name);
  if (!f) {
    fprintf(stderr, "cuda_call_census: no %s after the census library\n", name);
    abort();
  }
  return f;
}
#define REAL(name)                             \
  static __typeof__(&name) real_##name = NULL; \
  if (!real_##name) real_##name = (__typeof__(&name))real(#name)

cudaError_t cudaMemcpy(void* dst, const void* src, size_t bytes, enum cudaMemcpyKind kind) {
  REAL(cudaMemcpy);
  const long t = now_ns();
  const cudaError_t e = real_cudaMemcpy(dst, src, bytes, kind);
  count(kind == cudaMemcpyDeviceToHost   ? MEMCPY_D2H
        : kind == cudaMemcpyHostToDevice ? MEMCPY_H2D
        : kind == cudaMemcpyDeviceToDevice ? MEMCPY_D2D
                                           : MEMCPY_OTHER,
        t, (long)bytes);
  return e;
}

/* The other runtime calls: one timed wrapper each, (params) and (args) as the runtime declares
 * them, and the bytes the call moves or allocates (0 where none). */
#define CENSUS_CUDA(kind, name, params, args, bytes) \
  cudaError_t name params {                          \
    REAL(name);                                      \
    const long t = now_ns();                         \
    const cudaError_t e = real_##name args;          \
    count(kind, t, (long)(bytes));                   \
    return e;                                        \
  }
CENSUS_CUDA(MEMCPY_ASYNC, cudaMemcpyAsync,
            (void* dst, const void* src, size_t bytes, enum cudaMemcpyKind kind, cudaStream_t s),
            (dst, src, bytes, kind, s), bytes)
CENSUS_CUDA(MEMSET, cudaMemset, (void* p, int value, size_t bytes), (p, value, bytes), bytes)
CENSUS_CUDA(MEMSET_ASYNC, cudaMemsetAsync, (void* p, int value, size_t bytes, cudaStream_t s), (p, value, bytes, s),
            bytes)
CENSUS_CUDA(MALLOC, cudaMalloc, (void** p, size_t bytes), (p, bytes), bytes)
CENSUS_CUDA(FREE, cudaFree, (void* p), (p), 0)
CENSUS_CUDA(MALLOC_HOST, cudaMallocHost, (void** p, size_t bytes), (p, bytes), bytes)
CENSUS_CUDA(FREE_HOST, cudaFreeHost, (void* p), (p), 0)
CENSUS_CUDA(HOST_ALLOC, cudaHostAlloc, (void** p, size_t bytes, unsigned int flags), (p, bytes, flags), bytes)
CENSUS_CUDA(MALLOC_ASYNC, cudaMallocAsync, (void** p, size_t bytes, cudaStream_t s), (p, bytes, s), bytes)
CENSUS_CUDA(FREE_ASYNC, cudaFreeAsync, (void* p, cudaStream_t s), (p, s), 0)
CENSUS_CUDA(STREAM_SYNC, cudaStreamSynchronize, (cudaStream_t s), (s), 0)
CENSUS_CUDA(DEVICE_SYNC, cudaDeviceSynchronize, (void), (), 0)
CENSUS_CUDA(EVENT_SYNC, cudaEventSynchronize, (cudaEvent_t ev), (ev), 0)
CENSUS_CUDA(LAUNCH, cudaLaunchKernel, (const void* f, dim3 grid, dim3 block, void** args, size_t shared, cudaStream_t s),
            (f, grid, block, args, shared, s), 0)

/* MPI through its profiling interface: MPI_X calls PMPI_X; bytes are those this rank passes
 * (count times the datatype's size) where the call has one count. */
static long type_bytes(MPI_Datatype type, int n) {
  int size = 0;
  PMPI_Type_size(type, &size);
  return (long)size * n;
}
#define CENSUS_MPI(kind, name, params, args, bytes) \
  int name params {                                 \
    const long t = now_ns();                        \
    const int e = P##name args;                     \
    count(kind, t, bytes);                          \
    return e;                                       \
  }
CENSUS_MPI(MPI_ALLREDUCE, MPI_Allreduce,
           (const void* s, void* r, int n, MPI_Datatype type, MPI_Op op, MPI_Comm comm),
           (s, r, n, type, op, comm), type_bytes(type, n))
CENSUS_MPI(MPI_IALLREDUCE, MPI_Iallreduce,
           (const void* s, void* r, int n, MPI_Datatype type, MPI_Op op, MPI_Comm comm, MPI_Request* q),
           (s, r, n, type, op, comm, q), type_bytes(type, n))
CENSUS_MPI(MPI_REDUCE, MPI_Reduce,
           (const void* s, void* r, int n, MPI_Datatype type, MPI_Op op, int root, MPI_Comm comm),
           (s, r, n, type, op, root, comm), type_bytes(type, n))
CENSUS_MPI(MPI_BCAST, MPI_Bcast, (void* b, int n, MPI_Datatype type, int root, MPI_Comm comm), (b, n, type, root, comm),
           type_bytes(type, n))
CENSUS_MPI(MPI_BARRIER, MPI_Barrier, (MPI_Comm comm), (comm), 0)
CENSUS_MPI(MPI_ALLGATHER, MPI_Allgather,
           (const void* s, int sn, MPI_Datatype st, void* r, int rn, MPI_Datatype rt, MPI_Comm comm),
           (s, sn, st, r, rn, rt, comm), type_bytes(st, sn))
CENSUS_MPI(MPI_ALLGATHERV, MPI_Allgatherv,
           (const void* s, int sn, MPI_Datatype st, void* r, const int* rn, const int* displs, MPI_Datatype rt,
            MPI_Comm comm),
           (s, sn, st, r, rn, displs, rt, comm), type_bytes(st, sn))
CENSUS_MPI(MPI_ALLTOALL, MPI_Alltoall,
           (const void* s, int sn, MPI_Datatype st, void* r, int rn, MPI_Datatype rt, MPI_Comm comm),
           (s, sn, st, r, rn, rt, comm), type_bytes(st, sn))
CENSUS_MPI(MPI_ALLTOALLV, MPI_Alltoallv,
           (const void* s, const int* sn, const int* sd, MPI_Datatype st, void* r, const int* rn, const int* rd,
            MPI_Datatype rt, MPI_Comm comm),
           (s, sn, sd, st, r, rn, rd, rt, comm), 0)
CENSUS_MPI(MPI_ISEND, MPI_Isend,
           (const void* b, int n, MPI_Datatype type, int to, int tag, MPI_Comm comm, MPI_Request* q),
           (b, n, type, to, tag, comm, q), type_bytes(type, n))
CENSUS_MPI(MPI_IRECV, MPI_Irecv, (void* b, int n, MPI_Datatype type, int from, int tag, MPI_Comm comm, MPI_Request* q),
           (b, n, type, from, tag, comm, q), type_bytes(type, n))
CENSUS_MPI(MPI_SEND, MPI_Send, (const void* b, int n, MPI_Datatype type, int to, int tag, MPI_Comm comm),
           (b, n, type, to, tag, comm), type_bytes(type, n))
CENSUS_MPI(MPI_RECV, MPI_Recv, (void* b, int n, MPI_Datatype type, int from, int tag, MPI_Comm comm, MPI_Status* st),
           (b, n, type, from, tag, comm, st), type_bytes(type, n))
CENSUS_MPI(MPI_WAIT, MPI_Wait, (MPI_Request* q, MPI_Status* st), (q, st), 0)
CENSUS_MPI(MPI_WAITALL, MPI_Waitall, (int n, MPI_Request* q, MPI_Status* st), (n, q, st), 0)
CENSUS_MPI(MPI_WAITANY, MPI_Waitany, (int n, MPI_Request* q, int* index, MPI_Status* st), (n, q, index, st), 0)
CENSUS_MPI(MPI_STARTALL, MPI_Startall, (int n, MPI_Request* q), (n, q), 0)

__attribute__((destructor)) static void report(void) {
  const char* rank = getenv("OMPI_COMM_WORLD_RANK");
  if (!rank) rank = getenv("PMI_RANK");
  if (!rank) rank = "0";
  FILE* out = stderr;
  const char* prefix = getenv("CENSUS_FILE");
  char path[4096];
  if (prefix) {
    snprintf(path, sizeof path, "%s.%s", prefix, rank);
    out = fopen(path, "w");
    if (!out) out = stderr;
  }
  fprintf(out, "census rank %s: %-22s %10s %10s %12s\n", rank, "call", "calls", "seconds", "MB");
  for (int k = 0; k < NUM_KINDS; ++k)
    if (calls_[k])
      fprintf(out, "census rank %s: %-22s %10ld %10.3f %12.1f\n", rank, kNames[k], (long)calls_[k],
              nanoseconds_[k] * 1e-9, bytes_[k] / 1048576.0);
  if (out != stderr) fclose(out);
}
