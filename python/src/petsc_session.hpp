// PETSc inside a Python process: one initialisation per process (at `import dipc`), one
// finalisation at interpreter exit, and an options database of its own for each Simulation, so
// that two simulations of one script (a parameter sweep) do not see each other's options.
#pragma once
#include <petscsys.h>

#include <string>
#include <vector>

namespace dipc::python {

// PetscInitialize without command-line arguments (PETSC_OPTIONS is read, as by `dipc`), MPI
// too unless mpi4py or the caller started it; PETSc's signal handlers stay off so that Ctrl-C
// stays Python's. Idempotent; the first Simulation calls it.
void initialize_petsc();
// PetscFinalize (and MPI_Finalize when PETSc started MPI); once, after every Simulation is gone.
void finalize_petsc();
bool petsc_finalized();

// A Simulation's options: PETSC_OPTIONS first, then the list (["-dipc_steps", "5", ...], an
// -options_file FILE read in its place), later values winning as on a command line.
class OptionsDatabase {
 public:
  OptionsDatabase(MPI_Comm comm, const std::vector<std::string>& args);
  ~OptionsDatabase();
  OptionsDatabase(const OptionsDatabase&) = delete;
  OptionsDatabase& operator=(const OptionsDatabase&) = delete;
  PetscOptions get() const { return options_; }

 private:
  PetscOptions options_ = nullptr;
};

// While it lives, `database` is PETSc's default options database: every call into the solver
// runs inside one, since PETSc objects read the default database when they are set up.
class OptionsScope {
 public:
  explicit OptionsScope(const OptionsDatabase& database);
  ~OptionsScope();
  OptionsScope(const OptionsScope&) = delete;
  OptionsScope& operator=(const OptionsScope&) = delete;
};

}  // namespace dipc::python
