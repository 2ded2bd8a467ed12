// A dipc error when a library ends the process in the middle of a run.
//
// hypre handles a failed CUDA or cuSPARSE call by printing one line and calling exit(1)
// (HYPRE_CUDA_CALL and HYPRE_CUSPARSE_CALL in hypre 2.32), so neither PETSc's error path nor
// dipc's sees it, and mpirun says only that a rank exited with status 1. From the start of the
// setup to the end of the last step, dipc keeps an exit handler (std::atexit) armed that adds
// what a user needs: the rank, the phase or step it was in, the rank's elements and the device
// memory in use when that phase began, the output that is complete, and what to change. The
// process then ends with status 1, also where the library asked for 0. Leaving main (any return
// path) disarms it, so dipc's own errors and normal ends are not reported twice.
#pragma once
#include <cstddef>
#include <string>

namespace dipc::library_exit {

// Registers the handler (once per process) and arms it for a run of `elements` elements on
// this rank; `device` names the GPU the rank uses ("" on the CPU).
void arm(long long elements, const std::string& device);
// The phase the rank enters ("setup", "step 12"); on a GPU the device memory in use is taken now.
void enter(const std::string& phase);
// The output written so far: `frames` complete time frames in `xdmf_path`.
void output_complete(const std::string& xdmf_path, std::size_t frames);
void disarm();

// Disarms on every way out of the scope (main's returns).
class DisarmOnExit {
 public:
  DisarmOnExit() = default;
  DisarmOnExit(const DisarmOnExit&) = delete;
  DisarmOnExit& operator=(const DisarmOnExit&) = delete;
  ~DisarmOnExit() { disarm(); }
};

}  // namespace dipc::library_exit
