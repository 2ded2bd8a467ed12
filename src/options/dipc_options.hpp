// Every -dipc_ option that dipc reads, declared once: its name, its kind and range (or its
// choices), the help text that `dipc -help` prints and the manual section PETSc prints after it
// in parentheses (the struct or class that holds the setting).
//
// The code that reads an option looks its row up by name with dipc_option, at compile time, so
// a read without a row does not compile; app/option_checks.cpp checks the values given against
// the rows before anything reads them. docs/options.md lists the same options (a test of
// tests/app/help_options_test.cpp compares the two), with what the defaults are: those are the
// readers' (app/run_options.hpp and the classes named as the manual sections), since some are the
// scene's or depend on the matrix.
#pragma once

#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string_view>

namespace dipc {

enum class OptionKind {
  flag,     // no value, or 1/0, true/false, yes/no, on/off (PETSc's booleans)
  integer,  // a decimal integer >= min that fits an int
  real,     // a finite number > min and < max
  text,     // a non-empty string
  choice,   // one of the words in `choices`
};

// The words of a choice option, in the order of the reader's index (PetscOptionsEList) or enum
// (PetscOptionsEnum).
struct OptionChoices {
  const char* const* words = nullptr;
  int count = 0;
  constexpr OptionChoices() = default;
  template <std::size_t N>
  constexpr OptionChoices(const char* const (&list)[N]) : words(list), count(static_cast<int>(N)) {}
  constexpr const char* const* begin() const { return words; }
  constexpr const char* const* end() const { return words + count; }
};

struct OptionSpec {
  const char* name;  // with the dash: "-dipc_steps"
  OptionKind kind;
  const char* manual;  // -help's parenthesis: what holds the setting
  const char* help;    // -help's text; null where the reader still holds it (see its row)
  double min = 0;      // integer: smallest value; real: values must exceed it
  double max = std::numeric_limits<double>::infinity();  // real: values must stay below it
  OptionChoices choices = {};                            // choice: the words
};

namespace option_rows {

constexpr const char* kRunOptions = "RunOptions";

constexpr OptionSpec flag(const char* name, const char* manual, const char* help) {
  return {name, OptionKind::flag, manual, help};
}
constexpr OptionSpec integer_at_least(const char* name, long min, const char* manual, const char* help) {
  return {name, OptionKind::integer, manual, help, double(min)};
}
constexpr OptionSpec positive_real(const char* name, const char* manual, const char* help) {
  return {name, OptionKind::real, manual, help, 0.0};
}
constexpr OptionSpec fraction(const char* name, const char* manual, const char* help) {
  return {name, OptionKind::real, manual, help, 0.0, 1.0};
}
constexpr OptionSpec text(const char* name, const char* manual, const char* help) {
  return {name, OptionKind::text, manual, help};
}
constexpr OptionSpec one_of(const char* name, OptionChoices choices, const char* manual, const char* help) {
  return {name, OptionKind::choice, manual, help, 0.0, std::numeric_limits<double>::infinity(), choices};
}

constexpr const char* kBackends[] = {"cpu", "cuda", "auto"};                   // app/backend.hpp
constexpr const char* kPresets[] = {"fast", "balanced", "accurate"};           // app/solver_presets.hpp
constexpr const char* kPartitioners[] = {"metis", "ptscotch", "rcb", "auto"};  // partition/slice_partition.hpp
constexpr const char* kSchurApproximations[] = {"mass", "selfp"};              // nonlinear/mixed_linear_solve.hpp
constexpr const char* kSchurFactorizations[] = {"diag", "upper"};              // the same
constexpr const char* kPatternRemaps[] = {"off", "fit", "candidates"};         // assembly/hessian_assembler.hpp

// The table. Its order is -help's within each options block and the order of the checks.
inline constexpr OptionSpec kTable[] = {
    // Read in app/run_options.cpp.
    positive_real("-dipc_velocity_tol", kRunOptions,
                  "Newton tolerance on |p|_inf/h (length/s); default: -dipc_velocity_tol_rel x the "
                  "scene's bounding-box diagonal"),
    positive_real("-dipc_velocity_tol_rel", kRunOptions,
                  "Newton tolerance relative to the bounding-box diagonal (1/s): -dipc_velocity_tol is "
                  "this times the diagonal unless given"),
    integer_at_least("-dipc_steps", 1, kRunOptions, "Number of time steps (default: the scene's time.steps)"),
    integer_at_least("-dipc_refine", 1, kRunOptions, "Multiply the resolution of every generated box by this factor"),
    text("-dipc_output", kRunOptions, "Output directory (default: the scene's output.directory)"),
    flag("-dipc_no_output", kRunOptions, "Write no HDF5/XDMF/CSV output"),
    flag("-dipc_quiet", kRunOptions, "Do not print one line per time step"),
    flag("-dipc_setup_only", kRunOptions,
         "Build the mesh, partition and solver setup, report them and take no step (setup benchmarks)"),
    flag("-dipc_check_invariants", kRunOptions,
         "After every step verify det J > 0, no edge-triangle intersection and d_min > 0"),
    one_of("-dipc_backend", kBackends, kRunOptions, "Where elements and contact are evaluated"),
    integer_at_least("-dipc_auto_gpu_elements", 0, kRunOptions,
                     "Elements per rank from which -dipc_backend auto uses the GPU"),
    // Read in nonlinear/preconditioner_reuse.cpp.
    flag("-dipc_pc_reuse", "PreconditionerReuse",
         "Keep the preconditioner across Newton iterations while that is cheaper"),
    positive_real("-dipc_pc_reuse_setup_cost", "PreconditionerReuse",
                  "What one preconditioner setup costs, in CG iterations (-dipc_pc_reuse's rule)"),
    // Read in nonlinear/newton_solver.cpp.
    flag("-dipc_contact_exact_hessian", "NewtonSolver",
         "Once a Newton solve's contact active set has settled, assemble the contact pairs' Hessians "
         "unprojected (dropped, and projected for a while, where that fails); default on"),
    // Read in forms/form_factory.cpp.
    flag("-dipc_friction_majorize_reversals", "FrictionForm",
         "In the Newton Hessian, give a friction pair whose slip the last step reversed the isotropic "
         "majorizer of its energy (fewer Newton iterations where sliding bodies come to rest)"),
    // Read in nonlinear/mixed_linear_solve.cpp.
    flag("-dipc_mixed_solve", "MixedLinearSolve",
         "Solve Newton systems of mean-dilatation elements as a mixed u-p system; default on when such "
         "an element has lambda/mu >= 1000 (nu >= 0.4995)"),
    // Read in assembly/hessian_assembler.cpp.
    flag("-dipc_direct_matrix", "DirectMatrix",
         "Make host AIJ (and device hypre) Hessians from dipc's own pattern instead of PETSc's COO preallocation"),
    // Read in app/hypre_device_memory.cpp.
    flag("-dipc_hypre_block_cache", "HypreDeviceMemory",
         "Give hypre's device temporaries from dipc's cache of device blocks instead of a cudaMalloc and cudaFree "
         "each (GPU hypre only)"),
    one_of("-dipc_pattern_remap", kPatternRemaps, "HessianAssembler",
           "When the contact active set changes: off makes a new matrix; fit keeps the matrix where the new pattern "
           "fits its entries and maps the contact values onto them; candidates also reserves entries for every "
           "contact candidate pair when a matrix is made (the preconditioner is set up afresh either way)"),
    one_of("-dipc_mixed_schur", kSchurApproximations, "MixedLinearSolve",
           "Preconditioner of the mixed solve's pressure block: selfp (AMG on I + Bs diag(A)^-1 Bs^T) "
           "or mass (I + D W)"),
    one_of("-dipc_mixed_schur_fact", kSchurFactorizations, "MixedLinearSolve",
           "Block preconditioner of the mixed solve: diag (block diagonal, MINRES) or upper (block "
           "upper triangular, FGMRES)"),
    // Read in app/run_options.cpp.
    positive_real("-dipc_dt_min", kRunOptions,
                  "Shortest sub-step of step recovery: a failed step is retried with dt halved down to "
                  "this (default: the scene's dt / 1024)"),
    fraction("-dipc_alpha_floor", kRunOptions,
             "A Newton solve has stalled (and the step fails) when the line-search step stays below "
             "this in 5 iterations in a row"),
    flag("-dipc_output_substeps", kRunOptions, "Also write the sub-steps of steps that recovery cut"),
    // Read in app/solver_presets.cpp; the choices are the presets compiled in, in their order
    // (src/app/CMakeLists.txt, DIPC_PRESET_NAMES; tests/app/solver_presets_test.cpp compares them).
    one_of("-dipc_preset", kPresets, "SolverPreset",
           "Solver preset (scenes/solver/presets/<name>.opts); options you give win over it"),
    // Read in app/run_options.cpp.
    integer_at_least("-dipc_checkpoint_every", 1, kRunOptions,
                     "Write a checkpoint every N steps into the output directory (the newest two are "
                     "kept; 0: not by step count)"),
    positive_real("-dipc_checkpoint_minutes", kRunOptions,
                  "Write a checkpoint at the first step boundary after M wall-clock minutes since the "
                  "last (rank 0's clock; 0: not by time)"),
    text("-dipc_restart", kRunOptions,
         "Continue from a checkpoint: a file, auto (the newest in the output directory; none there: "
         "start from step 0) or none"),
    one_of("-dipc_partitioner", kPartitioners, kRunOptions,
           "Element partitioner: metis (on rank 0), ptscotch (parallel), rcb (parallel recursive "
           "coordinate bisection) or auto (metis up to -dipc_metis_max_elements elements, above "
           "ptscotch where PETSc has it, rcb otherwise)"),
    integer_at_least("-dipc_metis_max_elements", 1, kRunOptions,
                     "Largest mesh (elements) that -dipc_partitioner auto partitions with METIS on rank 0"),
    integer_at_least("-dipc_host_threads", 0, kRunOptions,
                     "Threads per rank of the partition's and the setup's host loops (0: the cores this "
                     "rank may run on, shared with the node's other ranks on them)"),
};

}  // namespace option_rows

inline constexpr const auto& kDipcOptions = option_rows::kTable;

// The row of `name`. Called where a constant is needed (constexpr const OptionSpec& x =
// dipc_option("-dipc_steps");), a name without a row is a compile error.
constexpr const OptionSpec& dipc_option(std::string_view name) {
  for (const OptionSpec& spec : kDipcOptions)
    if (name == spec.name) return spec;
  throw std::logic_error("not a -dipc_ option of options/dipc_options.hpp");
}

}  // namespace dipc
