// Checkpoints of a run (issue 13): what is stored, where, and how a run resumes from one.
// File layout: io/checkpoint_file.hpp. Files are <output dir>/<name>.checkpoint.<step>.h5; the
// newest two are kept. Positions and velocities are stored in the input mesh's node numbering,
// so a checkpoint written on one rank count restarts on any other (METIS repartitions).
#pragma once
#include <petscsys.h>

#include <cstdint>
#include <string>
#include <vector>

#include "app/natural_order.hpp"
#include "io/checkpoint_file.hpp"
#include "io/scene.hpp"
#include "mesh/hex_mesh.hpp"
#include "nonlinear/step_recovery.hpp"
#include "nonlinear/time_integrator.hpp"

namespace dipc {

// What identifies a scene for a checkpoint: a 64-bit FNV-1a hash of the refined input mesh's
// digest (slice_digest of partition/mesh_slice.hpp: coordinates, connectivity, bodies, the same
// on any number of ranks) and of everything in the scene that shapes the motion
// (materials, bodies' initial motion, gravity, Dirichlet conditions, contact settings, time
// integrator and dt). The number of steps and the output settings are not in it: a restart
// may run further or write elsewhere.
std::uint64_t scene_fingerprint(const Scene& scene, std::uint64_t mesh_digest);

std::string checkpoint_path(const std::string& directory, const std::string& name, long step);

// Collective (rank 0 lists the directory): the complete checkpoints of `name` in `directory`,
// newest (highest step) first; .tmp files, which a killed run may leave, are not complete.
std::vector<std::string> list_checkpoints(MPI_Comm comm, const std::string& directory, const std::string& name);

// What a run hands to a checkpoint besides the integrator's and recovery's state.
struct CheckpointRun {
  std::uint64_t fingerprint = 0;
  long output_steps = 0;  // steps in the output HDF5/XDMF when the checkpoint was written
  std::string options;    // the run's options (PETSc database), for the record
  std::string scene;      // the scene's source
};

// Collective. Writes a checkpoint of the current state to `path` (temporary file, rename),
// then removes all but the newest `keep` checkpoints of `name` in its directory.
PetscErrorCode write_checkpoint(MPI_Comm comm, const std::string& path, NaturalOrder& order,
                                const TimeIntegrator& integrator, const StepRecovery& recovery,
                                const CheckpointRun& run, const std::string& name, int keep = 2);

// Collective. Reads `path`, refuses it when its fingerprint is not `run.fingerprint`
// (CheckpointError::Kind::mismatched) and restores the integrator's and recovery's state.
// Returns the stored run record (output_steps, options, scene) in *stored.
PetscErrorCode read_checkpoint(MPI_Comm comm, const std::string& path, NaturalOrder& order, TimeIntegrator& integrator,
                               StepRecovery& recovery, const CheckpointRun& run, CheckpointRun* stored);

}  // namespace dipc
