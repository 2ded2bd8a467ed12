#include "petsc_session.hpp"

#include <cctype>
#include <cstdlib>
#include <stdexcept>

#include "app/petsc_input_errors.hpp"

namespace dipc::python {
namespace {

bool finalized = false;

// A PETSc error code as an exception: dipc's input errors (PETSC_ERR_USER_INPUT) with their
// message, others with PETSc's.
void check(PetscErrorCode code, const char* what) {
  if (!code) return;
  throw std::runtime_error(std::string(what) + ": " + last_petsc_error_message());
}

// "-name" (a letter after the dash) starts an option; anything else is the previous one's value
// (so "-1" and "-0.5" are values).
bool is_option_name(const std::string& s) { return s.size() > 1 && s[0] == '-' && std::isalpha((unsigned char)s[1]); }

}  // namespace

void initialize_petsc() {
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (initialized) return;
  if (finalized) throw std::runtime_error("dipc: PETSc was finalised in this process; it cannot start again");
  // Options given before PetscInitialize are kept; Python handles SIGINT and friends itself.
  check(PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr), "PETSc options");
  check(PetscInitializeNoArguments(), "PetscInitialize");
  check(push_input_error_handler(), "PETSc error handler");
}

void finalize_petsc() {
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (!initialized || finalized) return;
  finalized = true;
  PetscFinalize();
}

bool petsc_finalized() { return finalized; }

OptionsDatabase::OptionsDatabase(MPI_Comm comm, const std::vector<std::string>& args) {
  check(PetscOptionsCreate(&options_), "PetscOptionsCreate");
  if (const char* environment = std::getenv("PETSC_OPTIONS"))
    check(PetscOptionsInsertString(options_, environment), "PETSC_OPTIONS");
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& name = args[i];
    if (!is_option_name(name))
      throw std::runtime_error("options: \"" + name + "\" is not an option name (\"-name\") and follows no option");
    const bool has_value = i + 1 < args.size() && !is_option_name(args[i + 1]);
    const std::string value = has_value ? args[++i] : std::string();
    if (name == "-options_file") {
      if (!has_value) throw std::runtime_error("options: -options_file needs a file name");
      check(PetscOptionsInsertFile(comm, options_, value.c_str(), PETSC_TRUE), ("-options_file " + value).c_str());
    } else {
      check(PetscOptionsSetValue(options_, name.c_str(), has_value ? value.c_str() : nullptr), name.c_str());
    }
  }
}

OptionsDatabase::~OptionsDatabase() {
  if (!finalized) PetscOptionsDestroy(&options_);
}

OptionsScope::OptionsScope(const OptionsDatabase& database) {
  check(PetscOptionsPush(database.get()), "PetscOptionsPush");
}
OptionsScope::~OptionsScope() { PetscOptionsPop(); }

}  // namespace dipc::python
