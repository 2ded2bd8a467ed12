#include "app/checked_run_options.hpp"

#include <string>
#include <vector>

#include "app/option_checks.hpp"
#include "app/petsc_input_errors.hpp"
#include "app/scene_size.hpp"
#include "app/solver_presets.hpp"

namespace dipc {

PetscErrorCode checked_run_options(MPI_Comm comm, const Scene& scene, RunOptions* options) {
  PetscFunctionBeginUser;
  check_option_values();  // before anything reads them
  check_petsc_option_values();
  std::vector<std::string> preset_inserted;
  PetscCall(apply_solver_preset(comm, &options->preset, &preset_inserted));  // before the options are read
  PetscCall(read_run_options(comm, scene, options));
  check_scene_size(scene, options->refine, comm);
  PetscFunctionReturn(0);
}

}  // namespace dipc
