#include "device/mpi_device_buffers.hpp"

#include <mpi.h>
#if __has_include(<mpi-ext.h>)
#include <mpi-ext.h>  // Open MPI's extensions, among them MPIX_Query_cuda_support
#endif

namespace dipc::device {

namespace {
bool direct_ = false;
}  // namespace

MpiCudaSupport query_mpi_cuda_support() {
#if defined(OMPI_HAVE_MPI_EXT_CUDA) && OMPI_HAVE_MPI_EXT_CUDA
  // Open MPI: 1 when the library was built with CUDA support (--with-cuda) and it is enabled.
  return MPIX_Query_cuda_support() ? MpiCudaSupport::yes : MpiCudaSupport::no;
#elif defined(MPIX_GPU_SUPPORT_CUDA)
  // MPICH 4 and its derivatives (Cray MPICH with MPICH_GPU_SUPPORT_ENABLED=1).
  int supported = 0;
  MPIX_GPU_query_support(MPIX_GPU_SUPPORT_CUDA, &supported);
  return supported ? MpiCudaSupport::yes : MpiCudaSupport::no;
#else
  return MpiCudaSupport::unknown;
#endif
}

const char* to_string(MpiCudaSupport support) {
  switch (support) {
    case MpiCudaSupport::yes:
      return "yes";
    case MpiCudaSupport::no:
      return "no";
    case MpiCudaSupport::unknown:
      break;
  }
  return "unknown";
}

bool decide_device_direct(MpiCudaSupport mpi, bool allowed, bool petsc_checked) {
  if (!allowed) return false;
  if (petsc_checked) return true;
  return mpi == MpiCudaSupport::yes;
}

void set_mpi_device_direct(bool direct) { direct_ = direct; }
bool mpi_device_direct() { return direct_; }

}  // namespace dipc::device
