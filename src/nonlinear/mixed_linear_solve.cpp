#include "nonlinear/mixed_linear_solve.hpp"

// PetscObjectStateIncrease: a nest vector's sub-vectors are written directly, and PETSc caches
// norms by object state, so the nest's state must move with them (VecNestGetSubVec's manual).
#include <petsc/private/petscimpl.h>

#include <cmath>

#include "nonlinear/device_matrix.hpp"

namespace dipc {

PetscErrorCode mixed_solve_requested(MPI_Comm comm, bool has_split_elements, double stiffness_ratio, bool* use,
                                     SchurApproximation* schur) {
  PetscFunctionBeginUser;
  PetscBool flag = has_split_elements && stiffness_ratio >= kMixedSolveStiffnessRatio ? PETSC_TRUE : PETSC_FALSE;
  PetscBool set = PETSC_FALSE;
  const char* const schur_names[] = {"mass", "selfp", "SchurApproximation", "", nullptr};
  PetscEnum schur_choice = static_cast<PetscEnum>(SchurApproximation::mass);
  PetscOptionsBegin(comm, nullptr, "dipc mixed u-p linear solve (mean-dilatation elements)", "SNES");
  PetscCall(PetscOptionsBool("-dipc_mixed_solve",
                             "Solve Newton systems of mean-dilatation elements as a mixed u-p system (MINRES); "
                             "default on when such an element has lambda/mu >= 1000 (nu >= 0.4995)",
                             "MixedLinearSolve", flag, &flag, &set));
  PetscCall(PetscOptionsEnum("-dipc_mixed_schur",
                             "Preconditioner of the mixed solve's pressure block: mass (I + D W) or selfp "
                             "(AMG on I + Bs diag(A)^-1 Bs^T)",
                             "MixedLinearSolve", schur_names, schur_choice, &schur_choice, nullptr));
  PetscOptionsEnd();
  if (schur) *schur = static_cast<SchurApproximation>(schur_choice);
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
  PCDestroy(&pc_s_);
  MatDestroy(&schur_);
  MatDestroy(&scaled_bs_);
  VecDestroy(&a_diagonal_);
  MatDestroy(&K_);
  MatDestroy(&BsT_);
  MatDestroy(&Bs_);
  MatDestroy(&minus_identity_);
  for (Vec* v : {&diagonal_, &rhs_, &solution_, &rhs_u_, &rhs_s_, &sol_u_, &sol_s_, &work_s_}) VecDestroy(v);
}

PetscErrorCode MixedLinearSolve::setup(MPI_Comm comm, std::vector<const VolumetricPart*> parts,
                                       const std::vector<char>* prescribed, PetscReal rtol, PetscReal atol,
                                       PetscInt max_it, SchurApproximation schur) {
  PetscFunctionBeginUser;
  comm_ = comm;
  parts_ = std::move(parts);
  prescribed_ = prescribed;
  rtol_ = rtol, atol_ = atol, max_it_ = max_it;
  selfp_ = schur == SchurApproximation::selfp;
  num_rows_ = 0;
  for (const VolumetricPart* p : parts_) num_rows_ += p->rows;
  PetscCall(PCCreate(comm_, &pc_a_));
  PetscCall(PCSetFromOptions(pc_a_));
  PetscCall(KSPCreate(comm_, &ksp_));
  PetscCall(KSPSetType(ksp_, KSPMINRES));
  PetscCall(KSPSetTolerances(ksp_, rtol_, atol_, PETSC_DEFAULT, max_it_));
  PC pc;
  PetscCall(KSPGetPC(ksp_, &pc));
  PetscCall(PCSetType(pc, PCSHELL));
  PetscCall(PCShellSetContext(pc, this));
  PetscCall(PCShellSetApply(pc, apply_preconditioner));
  PetscCall(PCShellSetName(pc, "dipc mixed u-p: diag(A-block PC, I + D W)"));
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
  PetscCall(MatCreateConstantDiagonal(comm_, num_rows_, num_rows_, PETSC_DETERMINE, PETSC_DETERMINE, -1.0,
                                      &minus_identity_));
  PetscCall(MatCreateVecs(Bs_, &rhs_u_, &rhs_s_));
  PetscCall(VecDuplicate(rhs_u_, &sol_u_));
  PetscCall(VecDuplicate(rhs_s_, &sol_s_));
  PetscCall(VecDuplicate(rhs_s_, &work_s_));
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
  if (A != A_) {  // the first matrix, or a new one for a new contact pattern
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
  if (selfp_) {  // I + C Cᵀ with C = Bs diag(A)^{-1/2}, rebuilt with every A (its pattern is B's)
    if (!a_diagonal_) PetscCall(MatCreateVecs(A_, &a_diagonal_, nullptr));
    PetscCall(MatGetDiagonal(A_, a_diagonal_));
    PetscCall(VecReciprocal(a_diagonal_));
    PetscCall(VecSqrtAbs(a_diagonal_));
    PetscCall(MatDestroy(&scaled_bs_));
    PetscCall(MatDuplicate(Bs_, MAT_COPY_VALUES, &scaled_bs_));
    PetscCall(MatDiagonalScale(scaled_bs_, nullptr, a_diagonal_));
    PetscCall(MatDestroy(&schur_));
    PetscCall(MatMatTransposeMult(scaled_bs_, scaled_bs_, MAT_INITIAL_MATRIX, PETSC_DEFAULT, &schur_));
    PetscCall(MatShift(schur_, 1.0));
    if (!pc_s_) {
      PetscCall(PCCreate(comm_, &pc_s_));
      PetscCall(PCSetType(pc_s_, PCHYPRE));
    } else {
      PetscCall(PCReset(pc_s_));
    }
    PetscCall(PCSetOperators(pc_s_, schur_, schur_));
    PetscCall(PCSetUp(pc_s_));
  }
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
  PetscCall(PCApply(self->pc_a_, xu, yu));
  if (self->selfp_)
    PetscCall(PCApply(self->pc_s_, xs, ys));
  else
    PetscCall(VecPointwiseDivide(ys, xs, self->diagonal_));
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
