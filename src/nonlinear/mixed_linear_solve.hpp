// MixedLinearSolve: the Newton system of mean-dilatation elements solved as a mixed u-p system,
// so that its Krylov iterations grow far less with lambda than CG's on the full Hessian.
//
// With mean-dilatation elements the Hessian is H = A + Bᵀ D B: A (deviatoric and p d²J terms,
// inertia, contact, friction) is free of lambda, B has one row b_e = dv_e/dx per element and
// D = diag(d_e), d_e = h² f''_e ~ h² lambda / V_e. CG + AMG on H is slow as nu -> 1/2: the
// divergence-free modes form a near-null space of the lambda part that AMG cannot represent.
// Instead H du = r is solved through the equivalent symmetric indefinite system
//
//   [ A   Bsᵀ ] [ du ]   [ r ]
//   [ Bs  -I  ] [ s  ] = [ 0 ],    Bs = D^{1/2} B,
//
// whose Schur complement on du is A + Bsᵀ Bs = H, so du is H⁻¹ r exactly. This is the usual
// mixed form K = [[A, Bᵀ], [B, -D⁻¹]] with the element pressure q = D B du rescaled to
// s = D^{-1/2} q, which keeps it finite where d_e = 0 (nu = 0, or f'' < 0 projected to 0).
// It is solved by FGMRES with the block upper-triangular preconditioner
//
//   P = [[ AMG(A), Bsᵀ ], [ 0, -Ŝ ]],   Ŝ = I + Bs diag(A)⁻¹ Bsᵀ (one BoomerAMG V-cycle),
//
// Ŝ approximating the Schur complement S = I + Bs A⁻¹ Bsᵀ as PCFIELDSPLIT's "selfp" does. Why
// this one (measured, bench/incompressible.py, docs/performance.md "Near-incompressible
// materials"): the element (Q1-P0) is not inf-sup stable, so Bs A⁻¹ Bsᵀ is nearly zero on its
// checkerboard-like pressure modes. The pressure mass over mu (W, the Stokes choice, ESW ch. 4)
// is not, and the older default diag(AMG(A), I + D W) with MINRES needed iterations that grew
// with lambda; Bs diag(A)⁻¹ Bsᵀ vanishes on those modes as Bs A⁻¹ Bsᵀ does. What it misses is
// on smooth pressures (about (h k)² too small, k the wave number, where stiffness outweighs
// inertia): a mesh-dependent but lambda-independent factor, so a milder growth with lambda
// remains, and a growth with mesh refinement that lets CG on H catch up from a few thousand
// hexes on (measured in docs/performance.md).
// The triangular form needs about half the iterations of the block diagonal one (with exact
// blocks K P⁻¹ has the single eigenvalue 1 and a minimal polynomial of degree 2; Elman,
// Silvester & Wathen, "Finite Elements and Fast Iterative Solvers", 2nd ed., sec. 9.2).
// The older choices stay available: -dipc_mixed_schur mass, -dipc_mixed_schur_fact diag (MINRES
// with the symmetric positive definite diag(AMG(A), Ŝ)).
//
// Dirichlet dofs: A carries them eliminated (unit diagonal), and their columns of B are zeroed,
// so du is zero there as in the primal solve. Everything here goes through PETSc's Vec and Mat
// operations (and MatSetValuesCOO with host values), so device vectors and matrices work.
#pragma once
#include <petscksp.h>

#include <vector>

#include "forms/volumetric_split.hpp"

namespace dipc {

// How the s block is preconditioned (Ŝ ≈ S = I + Bs A⁻¹ Bsᵀ, the Schur complement up to sign):
//  - selfp (default): one BoomerAMG V-cycle on I + Bs diag(A)⁻¹ Bsᵀ (PCFIELDSPLIT's "selfp"
//    Schur approximation in the rescaled variable), which sees the element-to-element coupling
//    that a diagonal misses; its solver takes options with the prefix -dipc_mixed_s_;
//  - mass: the diagonal I + D W, W = diag(V_e / (h² mu_e)), the pressure mass matrix over the
//    shear modulus: spectrally equivalent to Bs A⁻¹ Bsᵀ (times D) for an inf-sup stable pair only.
enum class SchurApproximation { mass, selfp };

// How the two blocks are combined (PCFIELDSPLIT's -pc_fieldsplit_schur_fact_type):
//  - diag: P = diag(AMG(A), Ŝ), symmetric positive definite, with MINRES;
//  - upper (default): P = [[AMG(A), Bsᵀ], [0, -Ŝ]], block upper triangular, with FGMRES
//    preconditioned on the right (so its residual is the unpreconditioned one, solved to
//    -ksp_rtol x kUnpreconditionedRtolFactor).
enum class SchurFactorization { diag, upper };

struct MixedSolveOptions {
  SchurApproximation schur = SchurApproximation::selfp;
  SchurFactorization factorization = SchurFactorization::upper;
};

// FGMRES (the upper factorization) solves to -ksp_rtol times this: it stops on the
// unpreconditioned residual, which needs a smaller tolerance than CG's and MINRES's
// preconditioned one for the same accuracy of du (mixed_linear_solve.cpp, setup).
constexpr double kUnpreconditionedRtolFactor = 0.01;

// The mixed solve is the default from this lambda / mu on (the largest over the mean-dilatation
// elements). Below it CG + AMG on the full Hessian took fewer Krylov iterations than MINRES on
// the mixed system (bench/incompressible.py, README "Near-incompressible materials").
constexpr double kMixedSolveStiffnessRatio = 1000;

// -dipc_mixed_solve: whether scenes with mean-dilatation elements (`has_split_elements`; the
// mixed solve needs them) take the mixed solve; `stiffness_ratio` is the largest lambda / mu
// among them (0 where the mixed solve cannot run by default: device forms or matrix). Default:
// on from kMixedSolveStiffnessRatio on.
// -dipc_mixed_schur selfp|mass and -dipc_mixed_schur_fact diag|upper: `options`. Asking for
// the mixed solve without such elements is bad input (PETSC_ERR_USER_INPUT).
PetscErrorCode mixed_solve_requested(MPI_Comm comm, bool has_split_elements, double stiffness_ratio, bool* use,
                                     MixedSolveOptions* options = nullptr);

class MixedLinearSolve {
 public:
  MixedLinearSolve() = default;
  ~MixedLinearSolve();
  MixedLinearSolve(const MixedLinearSolve&) = delete;
  MixedLinearSolve& operator=(const MixedLinearSolve&) = delete;

  // parts: the volumetric parts of the forms that split them (kept, read at every update);
  // prescribed: 3 flags per mesh-local node, the Dirichlet dofs; rtol/atol/max_it: the Krylov
  // solver's tolerances. The preconditioner of the A block is a PC read from the unprefixed options
  // (-pc_type, -pc_hypre_*: what the primal CG would use).
  PetscErrorCode setup(MPI_Comm comm, std::vector<const VolumetricPart*> parts, const std::vector<char>* prescribed,
                       PetscReal rtol, PetscReal atol, PetscInt max_it, MixedSolveOptions options);
  // After the forms' hessian(): A is the assembled Hessian without the volumetric terms, at
  // the state where the parts were computed. Fills Bs and the preconditioner's diagonal.
  PetscErrorCode update(Mat A);
  // Sets the A-block preconditioner up for the current A (a new AMG hierarchy).
  PetscErrorCode setup_preconditioner();
  // du = (A + Bsᵀ Bs)⁻¹ r to the Krylov solver's tolerance; its iterations and reason.
  PetscErrorCode solve(Vec r, Vec du, PetscInt* iterations, KSPConvergedReason* reason);
  // y = (A + Bsᵀ Bs) u, the Newton matrix H the mixed system stands for.
  PetscErrorCode multiply(Vec u, Vec y);
  KSP ksp() const { return ksp_; }

 private:
  PetscErrorCode create_block_matrices(Mat A);
  PetscErrorCode setup_schur_matrix();  // selfp
  static PetscErrorCode apply_preconditioner(PC pc, Vec x, Vec y);

  MPI_Comm comm_ = MPI_COMM_NULL;
  std::vector<const VolumetricPart*> parts_;
  const std::vector<char>* prescribed_ = nullptr;
  PetscInt num_rows_ = 0;  // this rank's volumetric rows
  std::vector<PetscScalar> bs_values_, diagonal_values_;
  Mat A_ = nullptr;  // not owned: the potential's matrix
  Mat Bs_ = nullptr, BsT_ = nullptr, minus_identity_ = nullptr, K_ = nullptr;
  Vec diagonal_ = nullptr;  // I + D W, the s block of the preconditioner (mass)
  MixedSolveOptions options_;
  Mat scaled_bs_ = nullptr, schur_ = nullptr;  // selfp: Bs diag(A)^-1/2 and Ŝ
  Vec a_diagonal_ = nullptr;
  KSP ksp_s_ = nullptr;                     // selfp: Ŝ's solver, options prefix dipc_mixed_s_
  Vec rhs_ = nullptr, solution_ = nullptr;  // nests (u, s)
  Vec rhs_u_ = nullptr, rhs_s_ = nullptr, sol_u_ = nullptr, sol_s_ = nullptr, work_s_ = nullptr, work_u_ = nullptr;
  KSP ksp_ = nullptr;
  PC pc_a_ = nullptr;
  bool pc_a_needs_reset_ = false;
  PetscReal rtol_ = 1e-8, atol_ = 1e-50;
  PetscInt max_it_ = 10000;
};

}  // namespace dipc
