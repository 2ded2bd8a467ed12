// IncrementalPotential: E(x) = Σ forms, evaluated on distributed PETSc Vecs.
//
// Per evaluation it gathers x to this rank's local nodes once (GhostExchange), lets every
// form work on local arrays, reduces the energy over ranks once and scatters gradient
// contributions of ghost nodes back to their owners once. The local nodes are the mesh's
// (owned, then element ghosts) followed by the extra nodes forms ask for (contact surfaces of
// other ranks); the exchange is rebuilt when those change. The Hessian's matrix is the
// HessianAssembler's (assembly/hessian_assembler.hpp): the potential asks it whether the forms'
// patterns changed, has each form write its Hessian values where the assembler says, and lets
// it sum them into the matrix.
//
// Forms evaluate in their own memory space (form.hpp): the potential hands each the local
// arrays where it needs them, copying across at most once per evaluation (LocalViews), adds
// device gradients into host ones (or the reverse) once, and the assembler takes Hessian values
// in each form's space. Along a line-search segment x + αp the start x and direction p are kept
// in both spaces, so a trial evaluation moves only α and scalars (segment_objective,
// segment_is_valid).
//
// Dirichlet dofs are eliminated symmetrically: their gradient entries are zero, their Hessian
// rows and columns are zero with a unit diagonal (DirichletElimination), so Newton never moves
// them and CG sees an SPD matrix. The time integrator sets their prescribed values in x before
// each solve.
#pragma once
#include <petscmat.h>

#include <functional>
#include <memory>
#include <vector>

#include "assembly/hessian_assembler.hpp"
#include "device/device_runtime.hpp"
#include "forms/form.hpp"
#include "partition/ghost_exchange.hpp"
#include "potential/local_views.hpp"

namespace dipc {

// Wall time spent in each kind of evaluation on this rank (seconds), and PETSc log events
// of the same names so -log_view shows them. The intervals are disjoint (none is counted
// inside another, apart from coo_insert, which is part of hessian), so that a caller can
// subtract them all from a wall time that encloses them (the timing table's remainder).
struct EvaluationTimes {
  double energy = 0, gradient = 0, hessian = 0, validity = 0;
  double coo_insert = 0;  // summing duplicates and MatSetValuesCOO (part of hessian)
  // The matrix's pattern: the terms' active sets, changed patterns mapped onto the matrix's
  // entries (remaps), and new matrices (CooReduction::build, the matrix's creation).
  double preallocation = 0;
  long preallocations = 0;   // how many times a matrix was made (1 at setup, then patterns that did not fit)
  long remaps = 0;           // changed patterns that fitted the matrix
  double segment = 0;        // gathering a line-search segment's x and p where the forms evaluate
  double neighbourhood = 0;  // forms' update_extra_nodes + prepare_segment (ghost surfaces, broad phase)
  double max_step = 0;       // forms' max_step (CCD); zero without a form that limits the step
};
// after − before, field by field (the counts too).
EvaluationTimes operator-(const EvaluationTimes& after, const EvaluationTimes& before);
EvaluationTimes& operator+=(EvaluationTimes& sum, const EvaluationTimes& add);
// The wall time of all the disjoint intervals (coo_insert is inside hessian).
inline double evaluation_seconds(const EvaluationTimes& t) {
  return t.energy + t.gradient + t.hessian + t.validity + t.preallocation + t.segment + t.neighbourhood + t.max_step;
}

class IncrementalPotential {
 public:
  IncrementalPotential() = default;
  ~IncrementalPotential();
  IncrementalPotential(const IncrementalPotential&) = delete;
  IncrementalPotential& operator=(const IncrementalPotential&) = delete;

  // dirichlet_dof: 3 flags per mesh-local node (owned and ghost) marking prescribed dofs.
  // nodal (optional): a set-up exchange of the mesh's nodes with 3 values per node, shared
  // instead of building the same scatter again.
  PetscErrorCode setup(const DistributedMesh& mesh, std::vector<std::unique_ptr<Form>> forms,
                       std::vector<char> dirichlet_dof, const GhostExchange* nodal = nullptr);
  // A matrix with the combined COO pattern preallocated (type from -mat_type, default aij).
  // The potential keeps a reference to re-preallocate it when a pattern changes.
  PetscErrorCode create_matrix(Mat* J);
  PetscErrorCode create_global_vec(Vec* v) const { return exchange_.create_global_vec(v); }

  // E(x) over all ranks; +inf when x is not admissible (inverted element).
  PetscErrorCode objective(Vec x, PetscReal* energy);
  // E split into the contributions of each form (summed over ranks), at x.
  PetscErrorCode form_values(Vec x, std::vector<double>* values);
  PetscErrorCode gradient(Vec x, Vec g);
  // Gradient of the forms for which include(form) is true; Dirichlet rows zeroed unless
  // keep_prescribed (output: the contact force on a kinematic body's nodes is its reaction).
  PetscErrorCode partial_gradient(Vec x, Vec g, const std::function<bool(const Form&)>& include,
                                  bool keep_prescribed = false);
  PetscErrorCode hessian(Vec x, Mat J);
  // Lets the forms fix their Hessian patterns at x; *changed (on every rank) when a changed
  // pattern does not fit the current matrix, which the caller must then replace with
  // create_matrix(); *remapped (on every rank) when it fitted and the matrix was kept
  // (-dipc_pattern_remap: HessianAssembler), so that the caller can set the preconditioner up
  // afresh.
  PetscErrorCode refresh_pattern(Vec x, PetscBool* changed, PetscBool* remapped);
  // The next refresh keeps the matrix only where its entries are exactly the current pattern's
  // (HessianAssembler::require_exact_pattern): at each time step's start.
  void require_exact_pattern() { assembler_.require_exact_pattern(); }
  // True on every rank iff every form accepts x on every rank.
  PetscErrorCode is_valid(Vec x, PetscBool* valid);
  // Collective. The smallest volume ratio over the elements of the forms that have them
  // (Form::min_volume_ratio, each in its own space), over all ranks; *found false where no form
  // has elements.
  PetscErrorCode min_volume_ratio(Vec x, double* ratio, bool* found);
  // Prepares the forms for evaluations on the segment x + αp, α ∈ [0, 1] (see Form), then
  // returns min over forms and ranks of the admissible step fraction along p.
  PetscErrorCode max_step(Vec x, Vec p, PetscReal* alpha);
  // E(x + αp) and is_valid(x + αp) on the segment of the last max_step(x, p); the trial state
  // is built in each form's memory space from the kept x and p, entry by entry as VecWAXPY
  // builds it, so it equals the state the caller then forms with VecWAXPY.
  PetscErrorCode segment_objective(PetscReal alpha, PetscReal* energy);
  PetscErrorCode segment_is_valid(PetscReal alpha, PetscBool* valid);
  // Prepares the forms for evaluations at x alone (start of a step).
  PetscErrorCode prepare_point(Vec x);
  // Passes the predicted positions x̂ (distributed) to every form.
  PetscErrorCode begin_step(Vec x_hat);
  // Calls every form's begin_iteration at x; *changed is true on every rank if any form
  // changed its definition there.
  PetscErrorCode begin_iteration(Vec x, PetscBool* changed);
  // Every form's set_exact_hessian (form.hpp): the Hessians that follow use unprojected
  // contact terms while `exact` is set. True if a form has such terms (every rank has the same
  // forms, so the answer is the same on every rank).
  bool set_exact_hessian(bool exact) {
    bool any = false;
    for (auto& form : forms_) any = form->set_exact_hessian(exact) || any;
    return any;
  }

  // Gathers x over the local nodes (mesh and extra) and calls f with the local array.
  // f(local array, its length).
  PetscErrorCode with_local(Vec x, const std::function<void(const double*, std::size_t)>& f);

  const std::vector<std::unique_ptr<Form>>& forms() const { return forms_; }
  // What the forms need beyond element and nodal terms (set by setup): nodes of other ranks
  // (contact's ghost surfaces; never on one rank), a bound on the step (CCD), a pattern that
  // changes after setup.
  // Without them the potential skips those hooks and their reductions over the ranks.
  bool has_extra_nodes() const { return any_extra_nodes_; }
  bool has_step_limit() const { return any_step_limit_; }
  bool has_changing_pattern() const { return any_pattern_change_; }
  // 3 flags per local node (mesh nodes first), the Dirichlet dofs.
  const std::vector<char>& prescribed_dofs() const { return dirichlet_dof_; }
  // Raw Hessian values the forms write per assembly (576 per hex for the elastic form).
  std::int64_t num_hessian_entries() const { return static_cast<std::int64_t>(assembler_.num_raw_entries()); }
  const EvaluationTimes& times() const { return times_; }

 private:
  PetscErrorCode gather(Vec x);  // x -> x_local_
  // The assembler's update_patterns at the gathered x (x_views_ begun), timed as preallocation;
  // nothing where the last call was at the same x (vector and state).
  PetscErrorCode update_patterns(Vec x, bool* new_matrix);
  PetscErrorCode assemble_hessian(Vec x, Mat J);  // hessian() without its timer
  bool uses(MemorySpace space) const { return space == MemorySpace::device ? any_device_ : any_host_; }
  // Sums the forms' values at the local arrays x (one per space); false if any rejects x.
  bool local_values(const double* x_host, const double* x_device, double* values);
  bool local_valid(const double* x_host, const double* x_device);
  // Sums the forms' local values (and a rejection anywhere) over the ranks: values[f] per form,
  // all +inf when any rank rejected its state.
  PetscErrorCode reduce_values(const std::vector<double>& local, bool ok, std::vector<double>* values);
  // *all = ok on every rank.
  PetscErrorCode all_ranks(bool ok, PetscBool* all);
  // Builds w = x + αp of the kept segment in every space the forms use.
  void segment_point(PetscReal alpha);
  // Hessian values of every form at x, written where the assembler takes them.
  bool assemble_values(LocalViews& x);
  PetscErrorCode rebuild_exchange();             // after the forms' extra nodes changed
  PetscErrorCode prepare_segment(Vec x, Vec p);  // update_extra_nodes / prepare_segment loop

  MPI_Comm comm_ = MPI_COMM_NULL;
  const DistributedMesh* mesh_ = nullptr;
  GhostExchange exchange_;
  std::vector<std::int64_t> local_to_global_;  // mesh local nodes, then the forms' extra nodes
  std::vector<std::unique_ptr<Form>> forms_;
  std::vector<char> dirichlet_dof_;  // over local_to_global_ (3 per node)
  Vec dirichlet_global_ = nullptr;   // 1 at prescribed dofs, to flag extra nodes
  int num_owned_dofs_ = 0;
  Vec x_local_ = nullptr, g_local_ = nullptr, p_local_ = nullptr;
  HessianAssembler assembler_;
  // The x of the last update_patterns() (vector and state), reset where forms may change.
  Vec patterns_x_ = nullptr;
  PetscObjectState patterns_state_ = 0;
  bool any_host_ = false, any_device_ = false;  // memory spaces the forms evaluate in
  bool any_extra_nodes_ = false, any_step_limit_ = false, any_pattern_change_ = false;
  LocalViews x_views_;
  Vec dirichlet_keep_ = nullptr;                // 0 at prescribed owned dofs, 1 elsewhere
  std::vector<double> g_host_;                  // gradient scratch of host forms (device Vec)
  device::Array<double> g_device_{"gradient"};  // gradient scratch of device forms (host Vec)
  // The segment x + αp of the last max_step, in the spaces the forms use, and its trial point.
  std::vector<double> seg_x_host_, seg_p_host_, seg_w_host_;
  device::Array<double> seg_x_device_{"segment start"}, seg_p_device_{"segment direction"},
      seg_w_device_{"trial state"};
  EvaluationTimes times_;
};

}  // namespace dipc
