// Whether MPI takes device pointers (issue 30): the rule, and the run's answer on this machine's
// MPI. The device-direct path is chosen only where MPI or PETSc's device check says MPI takes
// device buffers, never against -use_gpu_aware_mpi 0, and never for a run on the CPU. The GPU
// trajectory tests run both paths on GPUs (bench/gpu_runs.sh tests, with and without a CUDA-aware
// MPI).
#include <gtest/gtest.h>
#include <petscdevice.h>
#include <petscsys.h>

#include "app/gpu_aware_mpi.hpp"
#include "device/mpi_device_buffers.hpp"

namespace dipc {
namespace {

using device::MpiCudaSupport;

TEST(GpuAwareMpi, TheRuleFollowsMpiAndPetscAndTheSwitch) {
  // What MPI says, when nothing else is known.
  EXPECT_TRUE(device::decide_device_direct(MpiCudaSupport::yes, true, false));
  EXPECT_FALSE(device::decide_device_direct(MpiCudaSupport::no, true, false));
  EXPECT_FALSE(device::decide_device_direct(MpiCudaSupport::unknown, true, false));
  // PETSc's check sent a device buffer through MPI: that is taken over an MPI that says nothing
  // or no (an MPI whose CUDA support comes from UCX reports no through Open MPI's query).
  EXPECT_TRUE(device::decide_device_direct(MpiCudaSupport::unknown, true, true));
  EXPECT_TRUE(device::decide_device_direct(MpiCudaSupport::no, true, true));
  // -use_gpu_aware_mpi 0 wins over everything.
  for (MpiCudaSupport mpi : {MpiCudaSupport::yes, MpiCudaSupport::no, MpiCudaSupport::unknown})
    for (bool checked : {false, true}) EXPECT_FALSE(device::decide_device_direct(mpi, false, checked));
}

TEST(GpuAwareMpi, ThisMachinesMpiDecidesForADeviceRunAndNothingIsDirectOnTheCpu) {
  const MpiCudaSupport mpi = device::query_mpi_cuda_support();
  const bool petsc_checked = PetscDeviceInitialized(PETSC_DEVICE_CUDA);
  GpuAwareMpi cpu_run;
  ASSERT_EQ(settle_gpu_aware_mpi(PETSC_COMM_WORLD, false, &cpu_run), 0);
  EXPECT_FALSE(cpu_run.direct);
  EXPECT_FALSE(device::mpi_device_direct());
  EXPECT_TRUE(cpu_run.description.empty());

  GpuAwareMpi device_run;
  ASSERT_EQ(settle_gpu_aware_mpi(PETSC_COMM_WORLD, true, &device_run), 0);
  EXPECT_EQ(device_run.direct, mpi == MpiCudaSupport::yes || petsc_checked) << device_run.description;
  EXPECT_EQ(device::mpi_device_direct(), device_run.direct);
  EXPECT_NE(device_run.description.find(std::string("MPI reports CUDA support: ") + device::to_string(mpi)),
            std::string::npos)
      << device_run.description;

  PetscOptionsSetValue(nullptr, "-use_gpu_aware_mpi", "0");
  GpuAwareMpi switched_off;
  ASSERT_EQ(settle_gpu_aware_mpi(PETSC_COMM_WORLD, true, &switched_off), 0);
  PetscOptionsClearValue(nullptr, "-use_gpu_aware_mpi");
  EXPECT_FALSE(switched_off.direct);
  EXPECT_FALSE(device::mpi_device_direct());
  EXPECT_NE(switched_off.description.find("-use_gpu_aware_mpi 0"), std::string::npos) << switched_off.description;
  device::set_mpi_device_direct(false);
}

}  // namespace
}  // namespace dipc
