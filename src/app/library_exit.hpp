// A dipc error when a library ends the process in the middle of a run.
//
// hypre handles a failed CUDA or cuSPARSE call by printing one line and calling exit(1)
// (HYPRE_CUDA_CALL and HYPRE_CUSPARSE_CALL in hypre 2.32), so neither PETSc's error path nor
// dipc's sees it, and mpirun says only that a rank exited with status 1. From the start of the
// setup to the end of the run, dipc keeps an exit handler (std::atexit) armed that adds
// what a user needs: the rank, the phase or step it was in, the rank's elements and the device
// memory in use when that phase began, the output that is complete, and what to change. The
// process then ends with status 1, also where the library asked for 0.
#pragma once
#include <cstddef>
#include <string>

namespace dipc::library_exit {

// Arms the handler (registered once per process) while it lives: a run of `elements` elements
// on this rank, on the GPU named `device` ("" on the CPU), entering its setup. Every way out of its scope (the
// run's end, an error returned, an exception) disarms it, so dipc's own errors and normal ends
// are not reported as a library's.
class ArmedRun {
 public:
  ArmedRun(long long elements, const std::string& device);
  ~ArmedRun();
  ArmedRun(const ArmedRun&) = delete;
  ArmedRun& operator=(const ArmedRun&) = delete;
};
// The phase the rank enters ("setup", "step 12"); on a GPU the device memory in use is taken now.
void enter(const std::string& phase);
// The output written so far: `frames` complete time frames in `xdmf_path`.
void output_complete(const std::string& xdmf_path, std::size_t frames);

}  // namespace dipc::library_exit
