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
cudaError_t cudaMemcpyAsync(void* dst, const void* src, size_t bytes, enum cudaMemcpyKind kind, cudaStream_t s) {
  REAL(cudaMemcpyAsync);
  const long t = now_ns();
  const cudaError_t e = real_cudaMemcpyAsync(dst, src, bytes, kind, s);
  count(MEMCPY_ASYNC, t, (long)bytes);
  return e;
}
cudaError_t cudaMemset(void* p, int value, size_t bytes) {
  REAL(cudaMemset);
  const long t = now_ns();
  const cudaError_t e = real_cudaMemset(p, value, bytes);
  count(MEMSET, t, (long)bytes);
  return e;
}
cudaError_t cudaMemsetAsync(void* p, int value, size_t bytes, cudaStream_t s) {
  REAL(cudaMemsetAsync);
  const long t = now_ns();
  const cudaError_t e = real_cudaMemsetAsync(p, value, bytes, s);
  count(MEMSET_ASYNC, t, (long)bytes);
  return e;
}
cudaError_t cudaMalloc(void** p, size_t bytes) {
  REAL(cudaMalloc);
  const long t = now_ns();
  const cudaError_t e = real_cudaMalloc(p, bytes);
  count(MALLOC, t, (long)bytes);
  return e;
}
cudaError_t cudaFree(void* p) {
  REAL(cudaFree);
  const long t = now_ns();
  const cudaError_t e = real_cudaFree(p);
  count(FREE, t, 0);
  return e;
}
cudaError_t cudaMallocHost(void** p, size_t bytes) {
  REAL(cudaMallocHost);
  const long t = now_ns();
  const cudaError_t e = real_cudaMallocHost(p, bytes);
  count(MALLOC_HOST, t, (long)bytes);
  return e;
}
cudaError_t cudaFreeHost(void* p) {
  REAL(cudaFreeHost);
  const long t = now_ns();
  const cudaError_t e = real_cudaFreeHost(p);
  count(FREE_HOST, t, 0);
  return e;
}
cudaError_t cudaHostAlloc(void** p, size_t bytes, unsigned int flags) {
  REAL(cudaHostAlloc);
  const long t = now_ns();
  const cudaError_t e = real_cudaHostAlloc(p, bytes, flags);
  count(HOST_ALLOC, t, (long)bytes);
  return e;
}
cudaError_t cudaMallocAsync(void** p, size_t bytes, cudaStream_t s) {
  REAL(cudaMallocAsync);
  const long t = now_ns();
  const cudaError_t e = real_cudaMallocAsync(p, bytes, s);
  count(MALLOC_ASYNC, t, (long)bytes);
  return e;
}
cudaError_t cudaFreeAsync(void* p, cudaStream_t s) {
  REAL(cudaFreeAsync);
  const long t = now_ns();
  const cudaError_t e = real_cudaFreeAsync(p, s);
  count(FREE_ASYNC, t, 0);
  return e;
}
cudaError_t cudaStreamSynchronize(cudaStream_t s) {
  REAL(cudaStreamSynchronize);
  const long t = now_ns();
  const cudaError_t e = real_cudaStreamSynchronize(s);
  count(STREAM_SYNC, t, 0);
  return e;
}
cudaError_t cudaDeviceSynchronize(void) {
  REAL(cudaDeviceSynchronize);
  const long t = now_ns();
  const cudaError_t e = real_cudaDeviceSynchronize();
  count(DEVICE_SYNC, t, 0);
  return e;
}
cudaError_t cudaEventSynchronize(cudaEvent_t ev) {
  REAL(cudaEventSynchronize);
  const long t = now_ns();
  const cudaError_t e = real_cudaEventSynchronize(ev);
  count(EVENT_SYNC, t, 0);
  return e;
}
cudaError_t cudaLaunchKernel(const void* f, dim3 grid, dim3 block, void** args, size_t shared, cudaStream_t s) {
  REAL(cudaLaunchKernel);
  const long t = now_ns();
  const cudaError_t e = real_cudaLaunchKernel(f, grid, block, args, shared, s);
  count(LAUNCH, t, 0);
  return e;
}

/* MPI through its profiling interface. */
static long type_bytes(MPI_Datatype type, int n) {
  int size = 0;
  PMPI_Type_size(type, &size);
  return (long)size * n;
}
int MPI_Allreduce(const void* s, void* r, int n, MPI_Datatype type, MPI_Op op, MPI_Comm comm) {
  const long t = now_ns();
  const int e = PMPI_Allreduce(s, r, n, type, op, comm);
  count(MPI_ALLREDUCE, t, type_bytes(type, n));
  return e;
}
int MPI_Iallreduce(const void* s, void* r, int n, MPI_Datatype type, MPI_Op op, MPI_Comm comm, MPI_Request* q) {
  const long t = now_ns();
  const int e = PMPI_Iallreduce(s, r, n, type, op, comm, q);
  count(MPI_IALLREDUCE, t, type_bytes(type, n));
  return e;
}
int MPI_Reduce(const void* s, void* r, int n, MPI_Datatype type, MPI_Op op, int root, MPI_Comm comm) {
  const long t = now_ns();
  const int e = PMPI_Reduce(s, r, n, type, op, root, comm);
  count(MPI_REDUCE, t, type_bytes(type, n));
  return e;
}
int MPI_Bcast(void* b, int n, MPI_Datatype type, int root, MPI_Comm comm) {
  const long t = now_ns();
  const int e = PMPI_Bcast(b, n, type, root, comm);
  count(MPI_BCAST, t, type_bytes(type, n));
  return e;
}
int MPI_Barrier(MPI_Comm comm) {
  const long t = now_ns();
  const int e = PMPI_Barrier(comm);
  count(MPI_BARRIER, t, 0);
  return e;
}
int MPI_Allgather(const void* s, int sn, MPI_Datatype st, void* r, int rn, MPI_Datatype rt, MPI_Comm comm) {
  const long t = now_ns();
  const int e = PMPI_Allgather(s, sn, st, r, rn, rt, comm);
  count(MPI_ALLGATHER, t, type_bytes(st, sn));
  return e;
}
int MPI_Allgatherv(const void* s, int sn, MPI_Datatype st, void* r, const int* rn, const int* displs,
                   MPI_Datatype rt, MPI_Comm comm) {
  const long t = now_ns();
  const int e = PMPI_Allgatherv(s, sn, st, r, rn, displs, rt, comm);
  count(MPI_ALLGATHERV, t, type_bytes(st, sn));
  return e;
}
int MPI_Alltoall(const void* s, int sn, MPI_Datatype st, void* r, int rn, MPI_Datatype rt, MPI_Comm comm) {
  const long t = now_ns();
  const int e = PMPI_Alltoall(s, sn, st, r, rn, rt, comm);
  count(MPI_ALLTOALL, t, type_bytes(st, sn));
  return e;
}
int MPI_Alltoallv(const void* s, const int* sn, const int* sd, MPI_Datatype st, void* r, const int* rn,
                  const int* rd, MPI_Datatype rt, MPI_Comm comm) {
  const long t = now_ns();
  const int e = PMPI_Alltoallv(s, sn, sd, st, r, rn, rd, rt, comm);
  count(MPI_ALLTOALLV, t, 0);
  return e;
}
int MPI_Isend(const void* b, int n, MPI_Datatype type, int to, int tag, MPI_Comm comm, MPI_Request* q) {
  const long t = now_ns();
  const int e = PMPI_Isend(b, n, type, to, tag, comm, q);
  count(MPI_ISEND, t, type_bytes(type, n));
  return e;
}
int MPI_Irecv(void* b, int n, MPI_Datatype type, int from, int tag, MPI_Comm comm, MPI_Request* q) {
  const long t = now_ns();
  const int e = PMPI_Irecv(b, n, type, from, tag, comm, q);
  count(MPI_IRECV, t, type_bytes(type, n));
  return e;
}
int MPI_Send(const void* b, int n, MPI_Datatype type, int to, int tag, MPI_Comm comm) {
  const long t = now_ns();
  const int e = PMPI_Send(b, n, type, to, tag, comm);
  count(MPI_SEND, t, type_bytes(type, n));
  return e;
}
int MPI_Recv(void* b, int n, MPI_Datatype type, int from, int tag, MPI_Comm comm, MPI_Status* st) {
  const long t = now_ns();
  const int e = PMPI_Recv(b, n, type, from, tag, comm, st);
  count(MPI_RECV, t, type_bytes(type, n));
  return e;
}
int MPI_Wait(MPI_Request* q, MPI_Status* st) {
  const long t = now_ns();
  const int e = PMPI_Wait(q, st);
  count(MPI_WAIT, t, 0);
  return e;
}
int MPI_Waitall(int n, MPI_Request* q, MPI_Status* st) {
  const long t = now_ns();
  const int e = PMPI_Waitall(n, q, st);
  count(MPI_WAITALL, t, 0);
  return e;
}
int MPI_Waitany(int n, MPI_Request* q, int* index, MPI_Status* st) {
  const long t = now_ns();
  const int e = PMPI_Waitany(n, q, index, st);
  count(MPI_WAITANY, t, 0);
  return e;
}
int MPI_Startall(int n, MPI_Request* q) {
  const long t = now_ns();
  const int e = PMPI_Startall(n, q);
  count(MPI_STARTALL, t, 0);
  return e;
}

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
