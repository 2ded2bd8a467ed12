// The -options_file arguments checked before PetscInitialize: PETSc reads a file it cannot
// open inside PetscInitialize and stops the run with MPI_Abort (exit status 83 and a trace),
// so dipc looks for every named file first and reports a missing one itself.
#pragma once
#include <string>
#include <vector>

namespace dipc {

// The first problem with the options files named by `args` (the command line after the
// program name) or by `petsc_options` (the PETSC_OPTIONS environment variable, may be null),
// followed into -options_file lines inside those files as PETSc does; "" when every file can
// be read. Relative names are taken from the working directory, like PETSc. Names that PETSc
// rewrites (${...}, ~) are left for PETSc to judge. Example:
//   "-options_file solver.opts (named in base.opts): no such file"
std::string options_file_problem(const std::vector<std::string>& args, const char* petsc_options);

// The options file, among those `args` and `petsc_options` name (followed as above), that
// gives `option` (a name as PETSc lists it, with its dash), so that a message about the option can name the file;
// "" when it came from the command line or PETSC_OPTIONS.
std::string options_file_holding(const std::string& option, const std::vector<std::string>& args,
                                 const char* petsc_options);

}  // namespace dipc
