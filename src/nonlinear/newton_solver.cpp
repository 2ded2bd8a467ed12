#include "nonlinear/newton_solver.hpp"

#include <petscversion.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <stdexcept>

#include "forms/volumetric_split.hpp"
#include "logging/log_stages.hpp"
#include "options/dipc_options.hpp"

namespace dipc {

namespace {

PetscErrorCode objective_callback(SNES, Vec x, PetscReal* energy, void* ctx) {
  StageScope stage(log_stages().assembly);
  return static_cast<IncrementalPotential*>(ctx)->objective(x, energy);
}
PetscErrorCode gradient_callback(SNES, Vec x, Vec g, void* ctx) {
  StageScope stage(log_stages().assembly);
  return static_cast<IncrementalPotential*>(ctx)->gradient(x, g);
}
}  // namespace

// P: the assembled matrix; J: P itself, or the shell H of the mixed solve, whose volumetric part
// is taken from the forms here, at the same x as P.
PetscErrorCode NewtonSolver::hessian_callback(SNES, Vec x, Mat J, Mat P, void* ctx) {
  StageScope stage(log_stages().assembly);
  PetscFunctionBeginUser;
  auto* self = static_cast<NewtonSolver*>(ctx);
  PetscCall(self->ls_.potential->hessian(x, P));
  if (self->mixed_) PetscCall(self->mixed_->update(P));
  if (J != P) {
    PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  }
  PetscFunctionReturn(0);
}

// At the start of every Newton iteration: forms may adapt, and then the gradient at x is
// recomputed with them; and when the Hessian's nonzero pattern at x differs from the current
// matrix's (the contact active set changed), the solver gets a new matrix, so that every
// preconditioner sets itself up for the new pattern from scratch. Then the iteration's Hessian
// is chosen (projected or exact contact terms, see the header) and with it the linear solve's
// preconditioner and failure allowance.
PetscErrorCode NewtonSolver::update_callback(SNES snes, PetscInt iteration) {
  EventScope event(log_events().newton_update);
  PetscFunctionBeginUser;
  void* ctx;
  PetscCall(SNESGetApplicationContext(snes, &ctx));
  auto* self = static_cast<NewtonSolver*>(ctx);
  IncrementalPotential* potential = self->ls_.potential;
  Vec x, f;
  PetscCall(SNESGetSolution(snes, &x));
  PetscCall(SNESGetFunction(snes, &f, nullptr, nullptr));
  PetscBool changed;
  PetscCall(potential->begin_iteration(x, &changed));
  if (changed) PetscCall(SNESComputeFunction(snes, x, f));
  PetscBool new_pattern, remapped;
  PetscCall(potential->refresh_pattern(x, &new_pattern, &remapped));
  if (new_pattern || remapped) {
    // A changed active set gets a fresh preconditioner, also where it kept the matrix: a lagged
    // one (-snes_lag_preconditioner) would otherwise be kept across the change, holding on to
    // the old matrix, and one kept across it cost CG and Newton iterations on the contact-rich
    // family (docs/performance.md, "Keeping the matrix across active-set changes"). Reset
    // before a new matrix is made, so that the old AMG hierarchy is not held beside it.
    KSP ksp;
    PC pc;
    PetscCall(SNESGetKSP(snes, &ksp));
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PCReset(pc));
  }
  if (new_pattern) {
    Mat J;
    PetscCall(potential->create_matrix(&J));
    PetscCall(SNESSetJacobian(snes, self->mixed_ ? self->newton_matrix_ : J, J, hessian_callback, self));
    PetscCall(MatDestroy(&self->J_));
    self->J_ = J;
    PetscCall(self->attach_near_null_space(x));
  }
  LineSearchContext& ls = self->ls_;
  if (iteration == 0) ls.forgiven = 0, ls.exact_iterations = 0, ls.exact_failures = 0, ls.exact_resume = 2;
  // After the k-th failure the next 2^k iterations project: a solve tries the exact Hessian
  // again as it nears the minimiser, where the Hessian turns definite, and loses at most about
  // log2 of its iterations to failures.
  const bool dropped = ls.discarded;  // the last (exact) iteration's direction was not taken
  if (ls.exact_failed)
    ls.exact_resume = iteration + (PetscInt{1} << std::min<PetscInt>(ls.exact_failures, 20));
  const bool settled = iteration >= ls.exact_resume && !new_pattern && !remapped;
  const bool exact = self->exact_contact_hessian_ && !self->retrying_ && settled;
  // Exact only where a form has projected terms: elsewhere nothing changes, not even the
  // failure allowance below.
  ls.exact_hessian = potential->set_exact_hessian(exact) && exact;
  if (ls.exact_hessian) {
    ++ls.exact_iterations;
    PetscCall(PetscInfo(snes, "iteration %" PetscInt_FMT ": exact contact Hessian\n", iteration));
  }
  // After a failed solve with the exact Hessian the preconditioner is rebuilt for the projected one.
  PetscCall(self->pc_reuse_.begin_iteration(snes, new_pattern || remapped || dropped));
  ls.failure_forgiven = self->pc_reuse_.reusing() || ls.exact_hessian;
  // SNES stops once its count of failed linear solves reaches the maximum: the forgiven ones
  // so far, and this one where it may be forgiven, are added to the user's.
  PetscCall(SNESSetMaxLinearSolveFailures(snes, self->user_max_failures_ + ls.forgiven + (ls.failure_forgiven ? 1 : 0)));
  PetscFunctionReturn(0);
}

namespace {

// Sets `name` to `value` in the options database unless the user already set it, so every
// default stays a PETSc option that the command line or an options file overrides.
PetscErrorCode default_option(const char* name, const char* value) {
  PetscBool set;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, name, &set));
  if (!set) PetscCall(PetscOptionsSetValue(nullptr, name, value));
  PetscFunctionReturn(0);
}

}  // namespace

NewtonSolver::~NewtonSolver() {
  SNESDestroy(&snes_);
  MatDestroy(&newton_matrix_);
  MatDestroy(&J_);
  VecDestroy(&r_);
}

PetscErrorCode NewtonSolver::set_default_options() {
  PetscFunctionBeginUser;
  PetscCall(default_option("-ksp_type", "cg"));
  PetscCall(default_option("-ksp_rtol", "1e-8"));
  PetscCall(default_option("-pc_type", "hypre"));
  PetscCall(default_option("-pc_hypre_type", "boomeramg"));
  // BoomerAMG: HMIS coarsening, extended+i interpolation truncated to 4 entries per row,
  // hypre's strength threshold for 3D problems, matrix block size 3. Measured on a 97,556-hex
  // box (bench_step_breakdown, 2 ranks, README "Benchmarks"): plain unknown-based coarsening needed 4.1 s per Newton iteration,
  // nodal coarsening (-pc_hypre_boomeramg_nodal_coarsen 6) 14.1 s and nodal coarsening with
  // vector interpolation of the rigid-body modes (…_vec_interp_variant 3) 35 s, so the nodal
  // and vector-interpolation options are available (scenes/solver/*.opts) but not the default.
  // Aggressive coarsening is off: with it BoomerAMG turned indefinite on contact Hessians on
  // 4 ranks (CG stopped with DIVERGED_INDEFINITE_PC on the default scene's impact step).
  PetscCall(default_option("-pc_hypre_boomeramg_strong_threshold", "0.5"));
  // A device matrix (CUSPARSE, or MATHYPRE with a GPU hypre) runs BoomerAMG on the GPU, where
  // hypre sets up only PMIS coarsening and smooths only with Jacobi-type relaxation (hypre's GPU
  // documentation).
  const bool device_matrix = device_matrix_requested();
  if (device_matrix) PetscCall(default_option("-pc_hypre_boomeramg_relax_type_all", "l1scaled-Jacobi"));
  PetscCall(default_option("-pc_hypre_boomeramg_coarsen_type", device_matrix ? "PMIS" : "HMIS"));
  PetscCall(default_option("-pc_hypre_boomeramg_interp_type", "ext+i"));
  // On the GPU, interpolation truncated to 2 entries per row: BoomerAMG's setup, made afresh at
  // every contact pattern change, took 35 % less on the 1M-hex box and the linear solve 22 % less
  // per Newton iteration on the contact-rich 1M stack (8 steps), for 8-10 % more CG iterations
  // (one H200, docs/performance.md, "Pattern changes at 8 steps"). The host keeps 4.
  PetscCall(default_option("-pc_hypre_boomeramg_P_max", device_matrix ? "2" : "4"));
  // On the GPU, PETSc 3.22 has hypre form the coarse operators (RAP) with cuSPARSE's SpGEMM
  // unless told otherwise. On the contact-rich stack at 1M hexes on one H200 that failed in
  // the fourth step's AMG setup with CUSPARSE_STATUS_INSUFFICIENT_RESOURCES, with 34 of 139 GB
  // in use; hypre's own SpGEMM ran the same steps (docs/performance.md, "Contact-rich family").
  if (device_matrix && PetscDefined(HAVE_HYPRE_DEVICE))
    PetscCall(default_option("-pc_mg_galerkin_mat_product_algorithm", "hypre"));
  PetscFunctionReturn(0);
}

// Before the defaults are set, so that only what the user gave is listed. PETSc's residual and
// small-update tests take part in the convergence decision only when the user asks for one.
PetscErrorCode NewtonSolver::record_user_snes_options() {
  PetscFunctionBeginUser;
  char* all = nullptr;
  PetscCall(PetscOptionsGetAll(nullptr, &all));
  user_snes_options_.clear();
  std::string text = all ? all : "";
  PetscCall(PetscFree(all));
  // "-a 1 -b -c x": each option is a token starting with '-' and a letter, its value the tokens
  // up to the next option (a negative number is a value).
  std::size_t pos = 0;
  while ((pos = text.find("-snes_", pos)) != std::string::npos) {
    if (pos > 0 && text[pos - 1] != ' ') {
      ++pos;
      continue;
    }
    std::size_t end = pos + 1;
    while (end < text.size()) {
      const std::size_t next = text.find(" -", end);
      if (next == std::string::npos) {
        end = text.size();
        break;
      }
      const char c = next + 2 < text.size() ? text[next + 2] : '\0';
      if (std::isalpha(static_cast<unsigned char>(c))) {
        end = next;
        break;
      }
      end = next + 2;
    }
    std::string option = text.substr(pos, end - pos);
    option.erase(option.find_last_not_of(' ') + 1);
    user_snes_options_.push_back(option);
    pos = end;
  }
  PetscBool rtol, atol, stol;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-snes_rtol", &rtol));
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-snes_atol", &atol));
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-snes_stol", &stol));
  ls_.petsc_tests = rtol || atol || stol;
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::setup(MPI_Comm comm, IncrementalPotential* potential, Vec template_vec, double step_length,
                                   double velocity_tol, double alpha_floor) {
  PetscFunctionBeginUser;
  ls_.potential = potential;
  ls_.step_length = step_length;
  ls_.velocity_tol = velocity_tol;
  ls_.alpha_floor = alpha_floor;
  PetscCall(record_user_snes_options());
  PetscCall(set_default_options());
  PetscCall(potential->create_matrix(&J_));
  PetscCall(VecDuplicate(template_vec, &r_));
  PetscCall(SNESCreate(comm, &snes_));
  PetscCall(SNESSetType(snes_, SNESNEWTONLS));
  PetscCall(SNESSetObjective(snes_, objective_callback, potential));
  PetscCall(SNESSetFunction(snes_, r_, gradient_callback, potential));
  // [can split anywhere, largest lambda/mu of such elements] over the ranks
  double local[2] = {0, 0}, global[2];
  for (const auto& form : potential->forms())
    if (const VolumetricSplit* split = form->volumetric_split())
      local[0] = 1, local[1] = std::max(local[1], split->split_stiffness_ratio());
  PetscCallMPI(MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_MAX, comm));
  bool mixed = false;
  // With a device matrix (which the mixed solve refuses) it is off unless asked for.
  PetscCall(mixed_solve_requested(comm, global[0] > 0, matrix_on_device(J_) ? 0.0 : global[1], &mixed));
  if (mixed) {
    mixed_ = std::make_unique<MixedLinearSolve>();
    PetscInt m, M;
    PetscCall(MatGetLocalSize(J_, &m, nullptr));
    PetscCall(MatGetSize(J_, &M, nullptr));
    PetscCall(MatCreateShell(comm, m, m, M, M, this, &newton_matrix_));
    PetscCall(
        MatShellSetOperation(newton_matrix_, MATOP_MULT, reinterpret_cast<void (*)(void)>(newton_matrix_multiply)));
  }
  PetscCall(SNESSetJacobian(snes_, mixed ? newton_matrix_ : J_, J_, hessian_callback, this));
  // -snes_max_it 100 unless the user says otherwise (SNESSetFromOptions below); set here rather
  // than in the options database so that the run header lists only the user's -snes_ options.
  PetscCall(SNESSetTolerances(snes_, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, 100, PETSC_DEFAULT));
  PetscCall(SNESSetConvergenceTest(snes_, velocity_convergence_test, &ls_, nullptr));
  PetscCall(SNESSetApplicationContext(snes_, this));
  PetscCall(SNESSetUpdate(snes_, NewtonSolver::update_callback));
  SNESLineSearch ls;
  PetscCall(SNESGetLineSearch(snes_, &ls));
  PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHSHELL));
#if PETSC_VERSION_GE(3, 21, 0)
  PetscCall(SNESLineSearchShellSetApply(ls, ipc_line_search, &ls_));
#else
  PetscCall(SNESLineSearchShellSetUserFunc(ls, ipc_line_search, &ls_));
#endif
  PetscCall(SNESSetFromOptions(snes_));
  PetscCall(SNESGetMaxLinearSolveFailures(snes_, &user_max_failures_));
  {
    KSP ksp;
    PetscReal abstol, dtol;
    PetscInt max_it;
    PetscCall(SNESGetKSP(snes_, &ksp));
    PetscCall(KSPGetTolerances(ksp, &user_rtol_, &abstol, &dtol, &max_it));
  }
  if (mixed_)
    PetscCall(setup_mixed_solve());
  else
    PetscCall(pc_reuse_.setup(snes_));
  // On by default: the contact-rich family took fewer Newton iterations with it (the 1M stack's
  // heaviest step 13 instead of 16; docs/performance.md, "The exact contact Hessian once the
  // active set settles").
  PetscBool exact = PETSC_TRUE;
  PetscOptionsBegin(comm, nullptr, "dipc Newton solver", "SNES");
  constexpr const OptionSpec& exact_option = dipc_option("-dipc_contact_exact_hessian");
  PetscCall(PetscOptionsBool(exact_option.name, exact_option.help, exact_option.manual, exact, &exact, nullptr));
  PetscOptionsEnd();
  // The mixed solve's blocks assume a positive definite A; it keeps the projected Hessian.
  exact_contact_hessian_ = exact && !mixed_;
  PetscFunctionReturn(0);
}

// The forms split their volumetric terms off; the SNES's KSP becomes a PCSHELL that runs the
// mixed solve with the tolerances the KSP was given (-ksp_rtol, -ksp_atol, -ksp_max_it).
PetscErrorCode NewtonSolver::setup_mixed_solve() {
  PetscFunctionBeginUser;
  MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(snes_));
  // -dipc_pc_reuse (on in the default preset) counts the outer KSP's iterations, which the mixed
  // solve hides behind a PCSHELL, so it does not apply here: the mixed solve sets its
  // preconditioners up at every Newton iteration. Said once, rather than refused, since the
  // default preset asks for it; the options are read so that they do not count as unknown.
  PetscBool reuse = PETSC_FALSE, cost_set;
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-dipc_pc_reuse", &reuse, nullptr));
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-dipc_pc_reuse_setup_cost", &cost_set));
  if (reuse || cost_set)
    PetscCall(PetscPrintf(comm, "dipc: note: -dipc_pc_reuse does not apply to the mixed u-p solve of mean-dilatation "
                                "elements, which rebuilds its preconditioner at every Newton iteration\n"));
  // Its code uses only PETSc's Vec/Mat operations (device-ready), but it has been run only with
  // host matrices, so a device one (-mat_type, or the types dipc sets for a PETSc whose hypre
  // runs only on the GPU) is refused rather than trusted untested.
  if (matrix_on_device(J_)) {
    MatType type;
    PetscCall(MatGetType(J_, &type));
    throw std::invalid_argument(
        std::string("the mixed solve of mean-dilatation elements has been run only with host ") +
        "matrices, and this run's matrix is a device one (" + type +
        "): give -dipc_mixed_solve 0 for the plain Krylov solve of the full Hessian");
  }
  std::vector<const VolumetricPart*> parts;
  for (const auto& form : ls_.potential->forms())
    if (VolumetricSplit* split = form->volumetric_split()) {
      split->split_volumetric();
      parts.push_back(split->volumetric_part());
    }
  KSP ksp;
  PC pc;
  PetscCall(SNESGetKSP(snes_, &ksp));
  PetscReal rtol, atol, dtol;
  PetscInt max_it;
  PetscCall(KSPGetTolerances(ksp, &rtol, &atol, &dtol, &max_it));
  bool use;
  MixedSolveOptions options;
  PetscCall(mixed_solve_requested(comm, true, kMixedSolveStiffnessRatio, &use, &options));
  PetscCall(mixed_->setup(comm, std::move(parts), &ls_.potential->prescribed_dofs(), rtol, atol, max_it, options));
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCSHELL));
  PetscCall(PCShellSetContext(pc, this));
  PetscCall(PCShellSetSetUp(pc, mixed_setup));
  PetscCall(PCShellSetApply(pc, mixed_apply));
  PetscCall(PCShellSetName(pc, "dipc mixed u-p solve (mixed_linear_solve.hpp)"));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::mixed_setup(PC pc) {
  PetscFunctionBeginUser;
  NewtonSolver* self;
  PetscCall(PCShellGetContext(pc, &self));
  PetscCall(self->mixed_->setup_preconditioner());
  PetscFunctionReturn(0);
}

// One Newton system: du = H⁻¹ r through the mixed system. A Krylov solve (FGMRES or MINRES) that
// stops short fails the linear solve (KSPPREONLY reports the PC failure to SNES).
PetscErrorCode NewtonSolver::mixed_apply(PC pc, Vec r, Vec du) {
  PetscFunctionBeginUser;
  NewtonSolver* self;
  PetscCall(PCShellGetContext(pc, &self));
  PetscInt its;
  KSPConvergedReason reason;
  PetscCall(self->mixed_->solve(r, du, &its, &reason));
  self->mixed_iterations_ += its;
  if (reason < 0) PetscCall(PCSetFailedReason(pc, PC_SUBPC_ERROR));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::newton_matrix_multiply(Mat H, Vec u, Vec y) {
  PetscFunctionBeginUser;
  NewtonSolver* self;
  PetscCall(MatShellGetContext(H, &self));
  PetscCall(self->mixed_->multiply(u, y));
  PetscFunctionReturn(0);
}

// Rigid-body modes at the configuration x, attached as near-null space only where the
// preconditioner reads it: GAMG builds its coarse spaces from it, BoomerAMG only with vector
// interpolation (-pc_hypre_boomeramg_vec_interp_variant > 0). Attaching it otherwise is not
// just wasted work: with a CUSPARSE matrix, PETSc 3.22.5 copies the modes into hypre 2.32 IJ
// vectors, and that copy fails on the device ("CUDA ERROR ... memory.c", then invalid device
// ordinal; measured on an H200 with a 27,000-node Laplacian, which BoomerAMG solves on the
// device without the modes), so that combination is refused with a message instead.
PetscErrorCode NewtonSolver::attach_near_null_space(Vec x) {
  PetscFunctionBeginUser;
  KSP ksp;
  PC pc;
  PetscCall(SNESGetKSP(snes_, &ksp));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscBool gamg, hypre;
  PetscCall(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCGAMG, &gamg));
  PetscCall(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCHYPRE, &hypre));
  PetscInt variant = 0;
  if (hypre)
    PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-pc_hypre_boomeramg_vec_interp_variant", &variant, nullptr));
  if (!gamg && variant <= 0) PetscFunctionReturn(0);
  PetscCheck(!(hypre && device_matrix_requested()), PetscObjectComm(reinterpret_cast<PetscObject>(x)), PETSC_ERR_SUP,
             "-pc_hypre_boomeramg_vec_interp_variant needs the rigid-body modes in hypre, which fails with a "
             "device matrix (PETSc 3.22 + hypre 2.32 on CUDA); drop the option or use -pc_type gamg");
  MatNullSpace rigid;
  PetscCall(MatNullSpaceCreateRigidBody(x, &rigid));
  PetscCall(MatSetNearNullSpace(J_, rigid));
  PetscCall(MatNullSpaceDestroy(&rigid));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::set_retrying(bool retrying) {
  PetscFunctionBeginUser;
  retrying_ = retrying;
  KSP ksp;
  PetscReal rtol, abstol, dtol;
  PetscInt max_it;
  PetscCall(SNESGetKSP(snes_, &ksp));
  PetscCall(KSPGetTolerances(ksp, &rtol, &abstol, &dtol, &max_it));
  PetscCall(KSPSetTolerances(ksp, retrying ? 0.1 * user_rtol_ : user_rtol_, abstol, dtol, max_it));
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::solve(Vec x, NewtonReport* report) {
  PetscFunctionBeginUser;
  PetscCall(attach_near_null_space(x));

  ls_.min_alpha = 1.0;
  ls_.min_alpha_ccd = 1.0;
  ls_.direction_inf_norm = 0.0;
  ls_.small_steps_in_a_row = 0;
  ls_.stopped = false;
  ls_.discarded = false;
  ls_.exact_hessian = false;
  ls_.exact_failed = false;
  ls_.ended_by.clear();
  const PetscInt rebuilds_before = pc_reuse_.rebuilds();
  const PetscInt mixed_before = mixed_iterations_;
  {
    StageScope stage(log_stages().solve);
    PetscCall(SNESSolve(snes_, nullptr, x));
  }
  PetscCall(SNESGetIterationNumber(snes_, &report->iterations));
  PetscCall(SNESGetLinearSolveIterations(snes_, &report->linear_iterations));
  // KSPPREONLY counts one per solve; the work is the mixed solve's Krylov method's.
  if (mixed_) report->linear_iterations = mixed_iterations_ - mixed_before;
  PetscCall(SNESGetConvergedReason(snes_, &report->reason));
  report->preconditioner_rebuilds = pc_reuse_.rebuilds() - rebuilds_before;
  report->min_alpha = ls_.min_alpha;
  report->min_alpha_ccd = ls_.min_alpha_ccd;
  report->step_inf_norm = ls_.direction_inf_norm;
  report->exact_hessian_iterations = ls_.exact_iterations;
  report->exact_hessian_fallbacks = ls_.exact_failures;
  report->stopped = ls_.stopped;
  // Failures SNES detects itself (line search, linear solve) bypass the convergence test.
  if (!ls_.ended_by.empty())
    report->ended_by = ls_.ended_by;
  else if (report->reason == SNES_DIVERGED_LINE_SEARCH)
    report->ended_by = "line search found no admissible decrease";
  else if (report->reason == SNES_DIVERGED_LINEAR_SOLVE)
    report->ended_by = "linear solve failed";
  else
    report->ended_by = SNESConvergedReasons[report->reason];
  PetscFunctionReturn(0);
}

}  // namespace dipc
