// Whether MPI takes device pointers (a CUDA-aware MPI), decided once per run (issue 30).
//
// Where it does, dipc's own exchanges of device data (RemoteEntrySums: matrix entries of other
// ranks' rows) pass their device buffers to MPI as they are, and hypre is told to do the same
// (app/gpu_aware_mpi.cpp). Otherwise every exchange of device data is copied to the host, sent,
// and copied back: a few tens of microseconds per exchange however small the message, which
// BoomerAMG's V-cycle pays on every level (docs/performance.md, "Two GPUs").
//
// The answer belongs to the MPI library, so it is process-wide: the app sets it once per run,
// after every rank has agreed, and the exchanges read it.
#pragma once

namespace dipc::device {

enum class MpiCudaSupport { yes, no, unknown };

// What the MPI library says of itself at run time: Open MPI's MPIX_Query_cuda_support (mpi-ext.h),
// MPICH's MPIX_GPU_query_support; unknown for an MPI that has neither.
MpiCudaSupport query_mpi_cuda_support();
const char* to_string(MpiCudaSupport support);

// The rule. Never where the user turned it off (-use_gpu_aware_mpi 0: allowed false); yes where
// PETSc's own check sent a device buffer through MPI (petsc_checked: a PETSc with CUDA checks
// that when it first uses the device, and stops the run if MPI fails it); otherwise what MPI
// says of itself (an MPI that says nothing is taken as not CUDA-aware).
bool decide_device_direct(MpiCudaSupport mpi, bool allowed, bool petsc_checked);

// Process-wide setting, false until the app sets it.
void set_mpi_device_direct(bool direct);
bool mpi_device_direct();

}  // namespace dipc::device
