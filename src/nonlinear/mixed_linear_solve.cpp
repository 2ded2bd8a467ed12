#include "nonlinear/mixed_linear_solve.hpp"

// PetscObjectStateIncrease: a nest vector's sub-vectors are written directly, and PETSc caches
// norms by object state, so the nest's state must move with them (VecNestGetSubVec's manual).
#include <petsc/private/petscimpl.h>

#include <cmath>

#include "assembly/device_matrix.hpp"
#include "options/dipc_options.hpp"

namespace dipc {

PetscErrorCode mixed_solve_requested(MPI_Comm comm, bool has_split_elements, double stiffness_ratio, bool* use,
                                     MixedSolveOptions* options) {
  PetscFunctionBeginUser;
  PetscBool flag = has_split_elements && stiffness_ratio >= kMixedSolveStiffnessRatio ? PETSC_TRUE : PETSC_FALSE;
  PetscBool set = PETSC_FALSE;
  const MixedSolveOptions defaults;
  constexpr const OptionSpec& mixed = dipc_option("-dipc_mixed_solve");
  constexpr const OptionSpec& schur = dipc_option("-dipc_mixed_schur");
  constexpr const OptionSpec& fact = dipc_option("-dipc_mixed_schur_fact");
  // PetscOptionsEnum's lists: the choices in the order of the enum, its name, its prefix, null.
  static_assert(schur.choices.count == 2 && fact.choices.count == 2, "the choices are the enums' values");
  const char* const schur_names[] = {schur.choices.words[0], schur.choices.words[1], "SchurApproximation", "", nullptr};
  const char* const fact_names[] = {fact.choices.words[0], fact.choices.words[1], "SchurFactorization", "", nullptr};
  PetscEnum schur_choice = static_cast<PetscEnum>(defaults.schur);
  PetscEnum fact_choice = static_cast<PetscEnum>(defaults.factorization);
  PetscOptionsBegin(comm, nullptr, "dipc mixed u-p linear solve (mean-dilatation elements)", "SNES");
  PetscCall(PetscOptionsBool(mixed.name, mixed.help, mixed.manual, flag, &flag, &set));
  PetscCall(PetscOptionsEnum(schur.name, schur.help, schur.manual, schur_names, schur_choice, &schur_choice, nullptr));
  PetscCall(PetscOptionsEnum(fact.name, fact.help, fact.manual, fact_names, fact_choice, &fact_choice, nullptr));
  PetscOptionsEnd();
  if (options) {
    options->schur = static_cast<SchurApproximation>(schur_choice);
    options->factorization = static_cast<SchurFactorization>(fact_choice);
  }
  // Bad input (exit status 1, PETSC_ERR_USER_INPUT); has_split_elements is the same on every rank.
  PetscCheck(!(set && flag && !has_split_elements), comm, PETSC_ERR_USER_INPUT,
             "-dipc_mixed_solve needs mean-dilatation elements (scene key materials[].volumetric = "
             "\"mean_dilatation\"), and this scene has none");
  *use = flag && has_split_elements;
  PetscFunctionReturn(0);
}

MixedLinearSolve::~MixedLinearSolve() {
  KSPDestroy(&ksp_);
  PCDestroy(&pc_a_);
  KSPDestroy(&ksp_s_);
  MatDestroy(&schur_);
  MatDestroy(&scaled_bs_);
  VecDestroy(&a_diagonal_);
  MatDestroy(&K_);
  MatDestroy(&BsT_);
  MatDestroy(&Bs_);
  MatDestroy(&minus_identity_);
  for (Vec* v : {&diagonal_, &rhs_, &solution_, &rhs_u_, &rhs_s_, &sol_u_, &sol_s_, &work_s_, &work_u_}) VecDestroy(v);
}

PetscErrorCode MixedLinearSolve::setup(MPI_Comm comm, std::vector<const VolumetricPart*> parts,
                                       const std::vector<char>* prescribed, PetscReal rtol, PetscReal atol,
                                       PetscInt max_it, MixedSolveOptions options) {
  PetscFunctionBeginUser;
  comm_ = comm;
  parts_ = std::move(parts);
  prescribed_ = prescribed;
  rtol_ = rtol, atol_ = atol, max_it_ = max_it;
  options_ = options;
  num_rows_ = 0;
  for (const VolumetricPart* p : parts_) num_rows_ += p->rows;
  PetscCall(PCCreate(comm_, &pc_a_));
  PetscCall(PCSetFromOptions(pc_a_));
  PetscCall(KSPCreate(comm_, &ksp_));
  if (options_.schur == SchurApproximation::selfp) {
    // One BoomerAMG V-cycle by default; the -dipc_mixed_s_ prefix reaches this KSP and its PC
    // (e.g. -dipc_mixed_s_ksp_type cg -dipc_mixed_s_ksp_rtol 1e-2 for an inner solve, which
    // only FGMRES, the upper factorization, tolerates: MINRES needs a fixed linear operator).
    PetscCall(KSPCreate(comm_, &ksp_s_));
    PetscCall(KSPSetOptionsPrefix(ksp_s_, "dipc_mixed_s_"));
    PetscCall(KSPSetType(ksp_s_, KSPPREONLY));
    PC pc;
    PetscCall(KSPGetPC(ksp_s_, &pc));
    PetscCall(PCSetType(pc, PCHYPRE));
    PetscCall(KSPSetFromOptions(ksp_s_));
    PetscBool fixed;
    PetscCall(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(ksp_s_), &fixed, KSPPREONLY, KSPRICHARDSON, ""));
    PetscCheck(fixed || options_.factorization == SchurFactorization::upper, comm_, PETSC_ERR_USER_INPUT,
               "a Krylov solve of the s block (-dipc_mixed_s_ksp_type) needs -dipc_mixed_schur_fact upper "
               "(FGMRES); MINRES (diag) needs a fixed linear preconditioner: preonly or richardson");
  }
  const bool upper = options_.factorization == SchurFactorization::upper;
  if (upper) {
    // FGMRES: right preconditioning only, and it tolerates a preconditioner that is not a fixed
    // linear operator. Restart 100: the measured scenes averaged 5 to 110 iterations per solve
    // (bench/incompressible.py; 110 on 8000 hexes), so most run unrestarted; FGMRES keeps
    // 2 x 100 vectors of the (u, s) size (3 values per node and 1 per element each), which
    // matters only for millions of elements on one rank.
    PetscCall(KSPSetType(ksp_, KSPFGMRES));
    PetscCall(KSPGMRESSetRestart(ksp_, 100));
  } else {
    PetscCall(KSPSetType(ksp_, KSPMINRES));
  }
  // FGMRES stops on the unpreconditioned residual, MINRES and the primal CG on a preconditioned
  // one, which follows the error of du on the soft modes far better: at the preset's -ksp_rtol
  // 1e-4, FGMRES let Newton stop early on a static nu = 0.4999 beam (bench/locking.py's 10x1x1,
  // 0.65 % short of the deflection; 2.6e-5 at rtol x 0.1, 6e-6 at x 0.01, CG 7e-6), hence
  // kUnpreconditionedRtolFactor. GMRES preconditioned on the left instead stalled Newton on `drop`
  // at nu = 0.4999 (its preconditioned residual weighs the two blocks by Ŝ and AMG(A)).
  PetscCall(KSPSetTolerances(ksp_, upper ? rtol_ * kUnpreconditionedRtolFactor : rtol_, atol_, PETSC_DEFAULT, max_it_));
  PC pc;
  PetscCall(KSPGetPC(ksp_, &pc));
  PetscCall(PCSetType(pc, PCSHELL));
  PetscCall(PCShellSetContext(pc, this));
  PetscCall(PCShellSetApply(pc, apply_preconditioner));
  PetscCall(PCShellSetName(pc, upper ? "dipc mixed u-p: [[A-block PC, Bs^T], [0, -S-block PC]]"
                                     : "dipc mixed u-p: diag(A-block PC, S-block PC)"));
  PetscFunctionReturn(0);
}

// Bs (rows: this rank's volumetric rows, numbered after the lower ranks'; columns: A's dofs),
// the s-block vectors and the nests. Made once: only A can change (a new contact pattern).
PetscErrorCode MixedLinearSolve::create_block_matrices(Mat A) {
  PetscFunctionBeginUser;
  PetscInt m;
  PetscCall(MatGetLocalSize(A, &m, nullptr));
  PetscCall(MatCreate(comm_, &Bs_));
  PetscCall(MatSetSizes(Bs_, num_rows_, m, PETSC_DETERMINE, PETSC_DETERMINE));
#if defined(PETSC_HAVE_CUDA)
  PetscCall(MatSetType(Bs_, matrix_on_device(A) ? MATAIJCUSPARSE : MATAIJ));
#else
  PetscCall(MatSetType(Bs_, MATAIJ));
#endif
  PetscInt first = 0;
  PetscCallMPI(MPI_Exscan(&num_rows_, &first, 1, MPIU_INT, MPI_SUM, comm_));
  int rank;
  PetscCallMPI(MPI_Comm_rank(comm_, &rank));
  if (rank == 0) first = 0;
  std::vector<PetscInt> rows, cols;
  PetscInt row = first;
  for (const VolumetricPart* p : parts_)
    for (int r = 0; r < p->rows; ++r, ++row) {
      rows.insert(rows.end(), 24, row);
      cols.insert(cols.end(), p->global_dofs.begin() + 24 * r, p->global_dofs.begin() + 24 * r + 24);
    }
  PetscCall(MatSetPreallocationCOO(Bs_, static_cast<PetscCount>(rows.size()), rows.data(), cols.data()));
  bs_values_.resize(rows.size());
  diagonal_values_.resize(static_cast<std::size_t>(num_rows_));
  PetscCall(
      MatCreateConstantDiagonal(comm_, num_rows_, num_rows_, PETSC_DETERMINE, PETSC_DETERMINE, -1.0, &minus_identity_));
  PetscCall(MatCreateVecs(Bs_, &rhs_u_, &rhs_s_));
  PetscCall(VecDuplicate(rhs_u_, &sol_u_));
  PetscCall(VecDuplicate(rhs_s_, &sol_s_));
  PetscCall(VecDuplicate(rhs_s_, &work_s_));
  PetscCall(VecDuplicate(rhs_u_, &work_u_));
  PetscCall(VecDuplicate(rhs_s_, &diagonal_));
  Vec rhs_parts[2] = {rhs_u_, rhs_s_}, sol_parts[2] = {sol_u_, sol_s_};
  PetscCall(VecCreateNest(comm_, 2, nullptr, rhs_parts, &rhs_));
  PetscCall(VecCreateNest(comm_, 2, nullptr, sol_parts, &solution_));
  PetscFunctionReturn(0);
}

PetscErrorCode MixedLinearSolve::update(Mat A) {
  PetscFunctionBeginUser;
  if (!Bs_) PetscCall(create_block_matrices(A));
  // Bs = D^{1/2} B with the Dirichlet columns zeroed; the s block of P: 1 + d_e w_e.
  std::size_t k = 0, row = 0;
  for (const VolumetricPart* p : parts_)
    for (int r = 0; r < p->rows; ++r, ++row) {
      const double d = p->curvature[r], root = std::sqrt(d);
      for (int j = 0; j < 24; ++j, ++k)
        bs_values_[k] = (*prescribed_)[p->local_dofs[24 * r + j]] ? 0.0 : root * p->gradient[24 * r + j];
      diagonal_values_[row] = 1.0 + d * p->weight[r];
    }
  PetscCall(MatSetValuesCOO(Bs_, bs_values_.data(), INSERT_VALUES));
  PetscScalar* diag;
  PetscCall(VecGetArrayWrite(diagonal_, &diag));
  for (std::size_t r = 0; r < diagonal_values_.size(); ++r) diag[r] = diagonal_values_[r];
  PetscCall(VecRestoreArrayWrite(diagonal_, &diag));
  if (!BsT_) PetscCall(MatCreateTranspose(Bs_, &BsT_));  // of an assembled Bs
  if (A != A_) {                                         // the first matrix, or a new one for a new contact pattern
    A_ = A;
    PetscCall(MatDestroy(&K_));
    Mat blocks[4] = {A_, BsT_, Bs_, minus_identity_};
    PetscCall(MatCreateNest(comm_, 2, nullptr, 2, nullptr, blocks, &K_));
    PetscCall(MatAssemblyBegin(K_, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(K_, MAT_FINAL_ASSEMBLY));
    PetscCall(KSPSetOperators(ksp_, K_, K_));
    pc_a_needs_reset_ = true;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MixedLinearSolve::setup_preconditioner() {
  PetscFunctionBeginUser;
  if (pc_a_needs_reset_) {  // a new matrix (pattern): a preconditioner set up afresh
    PetscCall(PCReset(pc_a_));
    PetscCall(PCSetOperators(pc_a_, A_, A_));
    pc_a_needs_reset_ = false;
  }
  PetscCall(PCSetUp(pc_a_));
  if (options_.schur != SchurApproximation::mass) PetscCall(setup_schur_matrix());
  PetscFunctionReturn(0);
}

// selfp: Ŝ = I + (Bs diag(A)^-1/2)(Bs diag(A)^-1/2)ᵀ, rebuilt with every A (its pattern is that
// of Bs Bsᵀ: elements that share a node), and its solver set up afresh.
PetscErrorCode MixedLinearSolve::setup_schur_matrix() {
  PetscFunctionBeginUser;
  PetscCall(MatDestroy(&scaled_bs_));
  PetscCall(MatDestroy(&schur_));
  if (!a_diagonal_) PetscCall(MatCreateVecs(A_, &a_diagonal_, nullptr));
  PetscCall(MatGetDiagonal(A_, a_diagonal_));
  PetscCall(VecReciprocal(a_diagonal_));
  PetscCall(VecSqrtAbs(a_diagonal_));
  PetscCall(MatDuplicate(Bs_, MAT_COPY_VALUES, &scaled_bs_));
  PetscCall(MatDiagonalScale(scaled_bs_, nullptr, a_diagonal_));
  PetscCall(MatMatTransposeMult(scaled_bs_, scaled_bs_, MAT_INITIAL_MATRIX, PETSC_DEFAULT, &schur_));
  PetscCall(MatShift(schur_, 1.0));
  PetscCall(KSPSetOperators(ksp_s_, schur_, schur_));  // a new matrix: a new AMG hierarchy
  PetscCall(KSPSetUp(ksp_s_));
  PetscFunctionReturn(0);
}

PetscErrorCode MixedLinearSolve::apply_preconditioner(PC pc, Vec x, Vec y) {
  PetscFunctionBeginUser;
  MixedLinearSolve* self;
  PetscCall(PCShellGetContext(pc, &self));
  Vec xu, xs, yu, ys;
  PetscCall(VecNestGetSubVec(x, 0, &xu));
  PetscCall(VecNestGetSubVec(x, 1, &xs));
  PetscCall(VecNestGetSubVec(y, 0, &yu));
  PetscCall(VecNestGetSubVec(y, 1, &ys));
  // s block: ys = Ŝ⁻¹ xs (diag) or -Ŝ⁻¹ xs (upper)
  if (self->options_.schur == SchurApproximation::mass)
    PetscCall(VecPointwiseDivide(ys, xs, self->diagonal_));
  else
    PetscCall(KSPSolve(self->ksp_s_, xs, ys));
  if (self->options_.factorization == SchurFactorization::upper) {
    // [[Â, Bsᵀ], [0, -Ŝ]] [yu; ys] = [xu; xs]: ys = -Ŝ⁻¹ xs, yu = Â⁻¹ (xu - Bsᵀ ys)
    PetscCall(VecScale(ys, -1.0));
    PetscCall(MatMultTranspose(self->Bs_, ys, self->work_u_));
    PetscCall(VecAYPX(self->work_u_, -1.0, xu));
    PetscCall(PCApply(self->pc_a_, self->work_u_, yu));
  } else {
    PetscCall(PCApply(self->pc_a_, xu, yu));
  }
  PetscCall(PetscObjectStateIncrease(reinterpret_cast<PetscObject>(y)));
  PCFailedReason failed;
  PetscCall(PCGetFailedReason(self->pc_a_, &failed));
  if (failed) PetscCall(PCSetFailedReason(pc, PC_SUBPC_ERROR));
  PetscFunctionReturn(0);
}

PetscErrorCode MixedLinearSolve::solve(Vec r, Vec du, PetscInt* iterations, KSPConvergedReason* reason) {
  PetscFunctionBeginUser;
  PetscCall(VecCopy(r, rhs_u_));
  PetscCall(VecZeroEntries(rhs_s_));
  PetscCall(PetscObjectStateIncrease(reinterpret_cast<PetscObject>(rhs_)));
  PetscCall(KSPSolve(ksp_, rhs_, solution_));
  PetscCall(KSPGetIterationNumber(ksp_, iterations));
  PetscCall(KSPGetConvergedReason(ksp_, reason));
  PetscCall(VecCopy(sol_u_, du));
  PetscFunctionReturn(0);
}

PetscErrorCode MixedLinearSolve::multiply(Vec u, Vec y) {
  PetscFunctionBeginUser;
  PetscCall(MatMult(A_, u, y));
  PetscCall(MatMult(Bs_, u, work_s_));
  PetscCall(MatMultTransposeAdd(Bs_, work_s_, y, y));
  PetscFunctionReturn(0);
}

}  // namespace dipc
