#include "nonlinear/time_integrator.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "forms/form_factory.hpp"
#include "forms/friction_form.hpp"
#include "logging/log_stages.hpp"
#include "math/vector3.hpp"
#include "nonlinear/mixed_linear_solve.hpp"
#include "physics/hex8_mass.hpp"
#include "threads/host_threads.hpp"

namespace dipc {

namespace {

// Lumped mass of every local node with the contributions of all ranks summed, so that
// owned-node loops (inertia, gravity) see complete masses. They travel as the first of 3
// components through the integrator's nodal exchange (block size 3): a scalar exchange of its
// own cost a second scatter setup (0.14 s per million nodes) for 2/3 less data.
PetscErrorCode assemble_node_masses(const DistributedMesh& mesh, const ElementData& elements,
                                    const GhostExchange& nodal, std::vector<double>* node_mass) {
  PetscFunctionBeginUser;
  const PetscInt bs = nodal.block_size();
  Vec local, global;
  PetscCall(nodal.create_local_vec(&local));
  PetscCall(nodal.create_global_vec(&global));
  PetscScalar* m;
  PetscCall(VecZeroEntries(local));
  PetscCall(VecGetArray(local, &m));
  // The element masses of a batch on the host threads, then their sums in element order on
  // one, so that every node's sum has the same terms in the same order for any thread count.
  const std::size_t ne = static_cast<std::size_t>(elements.num_elements()), batch = std::size_t{1} << 16;
  std::vector<double> element_mass(8 * std::min(ne, batch));
  for (std::size_t first = 0; first < ne; first += batch) {
    const std::size_t count = std::min(batch, ne - first);
    parallel_for(count, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const int e = static_cast<int>(first + i);
        double X[24];
        elements.gather_reference(e, X);
        hex8_lumped_mass(X, elements.rho[e], &element_mass[8 * i]);
      }
    });
    for (std::size_t i = 0; i < count; ++i)
      for (int a = 0; a < 8; ++a) m[bs * elements.nodes[8 * (first + i) + a]] += element_mass[8 * i + a];
  }
  PetscCall(VecRestoreArray(local, &m));
  PetscCall(VecZeroEntries(global));
  PetscCall(nodal.add_to_global(local, global));
  PetscCall(nodal.to_local(global, local));
  const PetscScalar* mc;
  PetscCall(VecGetArrayRead(local, &mc));
  node_mass->resize(mesh.num_local_nodes());
  for (int n = 0; n < mesh.num_local_nodes(); ++n) (*node_mass)[n] = mc[bs * n];
  PetscCall(VecRestoreArrayRead(local, &mc));
  PetscCall(VecDestroy(&local));
  PetscCall(VecDestroy(&global));
  PetscFunctionReturn(0);
}

}  // namespace

TimeIntegrator::~TimeIntegrator() {
  // A destructor cannot return the error: a failing destroy (a defect) aborts.
  for (Vec* v : {&X_, &x_, &x_n_, &v_, &x_hat_, &x_local_, &x_lag_}) PetscCallAbort(PETSC_COMM_SELF, VecDestroy(v));
}

PetscErrorCode TimeIntegrator::setup(const DistributedMesh& mesh, const ProblemSetup& problem,
                                     const StepControl& control, MemorySpace space) {
  PetscFunctionBeginUser;
  check_invariants_ = control.check_invariants;
  h_ = problem.dt;
  mesh_ = &mesh;
  problem_ = problem;
  // One -log_view event per phase (log_stages.hpp), what the run header's "setup" row sums.
  const LogEvents& events = log_events();
  std::optional<EventScope> phase(std::in_place, events.setup_elements);
  elements_ = std::make_unique<ElementData>(mesh, problem.body_materials);
  PetscCall(exchange_.setup(mesh, 3));
  phase.emplace(events.setup_masses);
  std::vector<double> node_mass;
  PetscCall(assemble_masses_for_forms(&node_mass));
  phase.emplace(events.setup_forms);
  std::vector<std::unique_ptr<Form>> forms;
  PetscCall(build_problem_forms(node_mass, space, &forms));
  phase.emplace(events.setup_state);
  std::vector<char> prescribed;
  assign_dirichlet_sets(&prescribed);
  PetscCall(create_state_vectors());
  PetscCall(set_initial_state());
  phase.emplace(events.setup_solver);
  PetscCall(potential_.setup(mesh, std::move(forms), std::move(prescribed), &exchange_));
  PetscCall(newton_.setup(mesh.comm, &potential_, x_, problem.is_static ? 1.0 : problem.dt, control.velocity_tol,
                          control.alpha_floor));
  newton_.set_stop_check(control.stop_requested);
  phase.emplace(events.contact_check);
  if (contact_) PetscCall(refuse_intersecting_start());
  PetscFunctionReturn(0);
}

PetscErrorCode TimeIntegrator::assemble_masses_for_forms(std::vector<double>* node_mass) {
  PetscFunctionBeginUser;
  if (!forms_need_node_masses(problem_)) PetscFunctionReturn(0);
  PetscCall(assemble_node_masses(*mesh_, *elements_, exchange_, node_mass));
  node_mass_.assign(node_mass->begin(), node_mass->begin() + mesh_->num_owned_nodes);
  PetscFunctionReturn(0);
}

PetscErrorCode TimeIntegrator::build_problem_forms(const std::vector<double>& node_mass, MemorySpace space,
                                                   std::vector<std::unique_ptr<Form>>* forms) {
  PetscFunctionBeginUser;
  deformable_elements_ = deformable_elements(*mesh_, problem_);
  const ElementData& deformable = deformable_elements_ ? *deformable_elements_ : *elements_;
  if (space == MemorySpace::device) PetscCall(refuse_mixed_solve_on_device(deformable));
  ProblemForms built;
  PetscCall(build_forms(*mesh_, problem_, *elements_, deformable, node_mass, exchange_, space, &built));
  contact_ = built.contact;
  friction_ = built.friction;
  form_names_.clear();
  for (auto& f : built.forms) form_names_.push_back(f->name());
  *forms = std::move(built.forms);
  PetscFunctionReturn(0);
}

// The device elastic form does not hand over its volumetric terms (B and D), which the mixed
// solve needs: a GPU run solves the full Hessian by CG unless the mixed solve is asked for
// (stiffness ratio 0: off by default), which is refused rather than ignored.
PetscErrorCode TimeIntegrator::refuse_mixed_solve_on_device(const ElementData& deformable) {
  PetscFunctionBeginUser;
  int local = 0, any_mean_dilatation;  // over the ranks
  for (int e = 0; e < deformable.num_elements(); ++e)
    if (deformable.volumetric[e] == VolumetricTerm::mean_dilatation) local = 1;
  PetscCallMPI(MPI_Allreduce(&local, &any_mean_dilatation, 1, MPI_INT, MPI_MAX, mesh_->comm));
  if (!any_mean_dilatation) PetscFunctionReturn(0);
  bool mixed = false;
  PetscCall(mixed_solve_requested(mesh_->comm, true, 0.0, &mixed));
  // Bad input: raised as PETSC_ERR_USER_INPUT, which the program reports with exit status 1
  // (a C++ exception would unwind through PETSc's call stack).
  PetscCheck(!mixed, mesh_->comm, PETSC_ERR_USER_INPUT,
             "-dipc_mixed_solve: the mixed u-p linear solve of mean-dilatation elements runs with the CPU elastic "
             "form only: run with -dipc_backend cpu, or drop -dipc_mixed_solve for the Krylov solve of the full "
             "Hessian on the GPU");
  PetscFunctionReturn(0);
}

// Dirichlet sets: later sets win where they overlap. prescribed: 3 flags per local node.
void TimeIntegrator::assign_dirichlet_sets(std::vector<char>* prescribed) {
  const int num_local_nodes = mesh_->num_local_nodes();
  dirichlet_set_.assign(num_local_nodes, -1);
  for (std::size_t s = 0; s < problem_.dirichlet.size(); ++s)
    for (std::int32_t n : problem_.dirichlet[s].local_nodes) dirichlet_set_[n] = static_cast<int>(s);
  prescribed->assign(3 * static_cast<std::size_t>(num_local_nodes), 0);
  for (int n = 0; n < num_local_nodes; ++n)
    if (dirichlet_set_[n] >= 0) (*prescribed)[3 * n] = (*prescribed)[3 * n + 1] = (*prescribed)[3 * n + 2] = 1;
}

// State vectors: reference positions, x, x_n, v, x̂, and friction's lag positions.
PetscErrorCode TimeIntegrator::create_state_vectors() {
  PetscFunctionBeginUser;
  PetscCall(exchange_.create_global_vec(&X_));
  PetscCall(VecDuplicate(X_, &x_));
  PetscCall(VecDuplicate(X_, &x_n_));
  PetscCall(VecDuplicate(X_, &v_));
  if (!problem_.is_static) PetscCall(VecDuplicate(X_, &x_hat_));  // x̂ = x_n + h v_n: dynamic runs only
  PetscCall(exchange_.create_local_vec(&x_local_));
  if (friction_) PetscCall(VecDuplicate(X_, &x_lag_));
  PetscFunctionReturn(0);
}

// X from the mesh and x = X; v from the bodies' initial velocity and spin, the Dirichlet nodes'
// from their motion at t = 0, zero in a static solve.
PetscErrorCode TimeIntegrator::set_initial_state() {
  PetscFunctionBeginUser;
  const DistributedMesh& mesh = *mesh_;
  const ProblemSetup& problem = problem_;
  std::vector<int> node_body(mesh.num_local_nodes(), 0);
  for (int e = 0; e < mesh.num_elements(); ++e)
    for (std::int32_t n : mesh.elements[e]) node_body[n] = mesh.element_body[e];
  PetscScalar *X, *v;
  PetscCall(VecGetArray(X_, &X));
  PetscCall(VecGetArray(v_, &v));
  for (int n = 0; n < mesh.num_owned_nodes; ++n) {
    const Vec3& Xn = mesh.coordinates[n];
    std::array<double, 3> vn{0, 0, 0};
    if (!problem.is_static && !problem.body_velocity.empty()) vn = problem.body_velocity[node_body[n]];
    if (!problem.is_static && !problem.body_angular_velocity.empty()) {
      const auto& w = problem.body_angular_velocity[node_body[n]];
      const auto& c = problem.body_spin_center[node_body[n]];
      const double r[3] = {Xn[0] - c[0], Xn[1] - c[1], Xn[2] - c[2]};
      double wxr[3];
      cross3(w.data(), r, wxr);
      for (int c = 0; c < 3; ++c) vn[c] += wxr[c];
    }
    if (dirichlet_set_[n] >= 0) vn = problem.dirichlet[dirichlet_set_[n]].motion.velocity_at(Xn, 0.0);
    for (int c = 0; c < 3; ++c) X[3 * n + c] = Xn[c], v[3 * n + c] = problem.is_static ? 0.0 : vn[c];
  }
  PetscCall(VecRestoreArray(X_, &X));
  PetscCall(VecRestoreArray(v_, &v));
  PetscCall(VecCopy(X_, x_));
  PetscFunctionReturn(0);
}

PetscErrorCode TimeIntegrator::refuse_intersecting_start() {
  PetscFunctionBeginUser;
  std::string problem_at_start;
  PetscCall(contact_state_problem(x_, &problem_at_start));
  // Bad input (exit status 1); the message is the same on every rank.
  PetscCheck(problem_at_start.empty(), mesh_->comm, PETSC_ERR_USER_INPUT,
             "the initial state is not intersection-free: %s", problem_at_start.c_str());
  PetscFunctionReturn(0);
}

PetscErrorCode TimeIntegrator::contact_state_problem(Vec x, std::string* problem) {
  PetscFunctionBeginUser;
  problem->clear();
  PetscCall(potential_.prepare_point(x));
  long crossings = 0;
  double d_min = 0;
  std::string first;
  PetscCall(potential_.with_local(x, [&](const double* xl, std::size_t) {
    crossings = contact_->set().count_intersections(xl, &first);
    d_min = contact_->min_distance(xl);
  }));
  long total = 0;
  double global_min = 0;
  PetscCallMPI(MPI_Allreduce(&crossings, &total, 1, MPI_LONG, MPI_SUM, mesh_->comm));
  PetscCallMPI(MPI_Allreduce(&d_min, &global_min, 1, MPI_DOUBLE, MPI_MIN, mesh_->comm));
  if (total == 0 && global_min > 0) PetscFunctionReturn(0);
  // The message of the lowest rank that saw a crossing.
  int rank, size;
  PetscCallMPI(MPI_Comm_rank(mesh_->comm, &rank));
  PetscCallMPI(MPI_Comm_size(mesh_->comm, &size));
  int mine = crossings > 0 ? rank : size, lowest = size;
  PetscCallMPI(MPI_Allreduce(&mine, &lowest, 1, MPI_INT, MPI_MIN, mesh_->comm));
  if (lowest < size) {
    int length = rank == lowest ? static_cast<int>(first.size()) : 0;
    PetscCallMPI(MPI_Bcast(&length, 1, MPI_INT, lowest, mesh_->comm));
    first.resize(length);
    PetscCallMPI(MPI_Bcast(first.data(), length, MPI_CHAR, lowest, mesh_->comm));
    *problem = std::to_string(total) + " edge-triangle crossing(s), e.g. " + first;
  } else {
    std::string pair;
    PetscCall(
        potential_.with_local(x, [&](const double* xl, std::size_t) { pair = contact_->set().closest_pair(xl); }));
    *problem = "two surfaces touch: " + pair;
  }
  PetscFunctionReturn(0);
}

PetscInt TimeIntegrator::num_dofs() const {
  PetscInt n = 0;
  PetscCallAbort(PetscObjectComm(reinterpret_cast<PetscObject>(x_)), VecGetSize(x_, &n));
  return n;
}

std::int64_t TimeIntegrator::hessian_entries() const { return potential_.num_hessian_entries(); }

PetscErrorCode TimeIntegrator::apply_dirichlet(Vec x, double t) {
  PetscFunctionBeginUser;
  PetscScalar* xa;
  PetscCall(VecGetArray(x, &xa));
  for (int n = 0; n < mesh_->num_owned_nodes; ++n) {
    const int k = dirichlet_set_[n];
    if (k < 0) continue;
    const PrescribedMotion& motion = problem_.dirichlet[k].motion;
    const bool restarted = !motion_start_time_.empty() && !std::isnan(motion_start_time_[k]);
    const auto p = restarted ? motion.position(motion_start_[n], t - motion_start_time_[k])
                             : motion.position(mesh_->coordinates[n], t);
    for (int c = 0; c < 3; ++c) xa[3 * n + c] = p[c];
  }
  PetscCall(VecRestoreArray(x, &xa));
  PetscFunctionReturn(0);
}

PetscErrorCode TimeIntegrator::set_prescribed_motion(int k, const PrescribedMotion& motion) {
  PetscFunctionBeginUser;
  PetscCheck(k >= 0 && k < static_cast<int>(problem_.dirichlet.size()), mesh_->comm, PETSC_ERR_USER_INPUT,
             "prescribed motion: no prescribed node set %d (the run has %d)", k,
             static_cast<int>(problem_.dirichlet.size()));
  if (motion_start_time_.empty()) {
    motion_start_time_.assign(problem_.dirichlet.size(), std::nan(""));
    motion_start_.resize(mesh_->num_owned_nodes);
  }
  const PetscScalar* xa;
  PetscCall(VecGetArrayRead(x_, &xa));
  for (int n = 0; n < mesh_->num_owned_nodes; ++n)
    if (dirichlet_set_[n] == k) motion_start_[n] = {xa[3 * n], xa[3 * n + 1], xa[3 * n + 2]};
  PetscCall(VecRestoreArrayRead(x_, &xa));
  motion_start_time_[k] = time_;
  problem_.dirichlet[k].motion = motion;
  PetscFunctionReturn(0);
}

void TimeIntegrator::set_time_step(double h) {
  if (problem_.is_static || h == h_) return;
  h_ = h;
  for (const auto& form : potential_.forms()) form->set_time_step(h);
  newton_.set_step_length(h);
}

TimeIntegrator::ResumeState TimeIntegrator::resume_state() const {
  ResumeState s;
  s.time = time_;
  s.step_length = h_;
  s.kappa = contact_ ? contact_->kappa() : 0.0;
  s.previous_min_distance2 = previous_min_distance2_;
  s.friction_lagged = friction_lagged_;
  return s;
}

PetscErrorCode TimeIntegrator::resume(const ResumeState& s) {
  PetscFunctionBeginUser;
  time_ = s.time;
  set_time_step(s.step_length);
  if (contact_) contact_->set_kappa(s.kappa);
  previous_min_distance2_ = s.previous_min_distance2;
  // Friction's pairs as the last step left them: frozen at x_lag_ from x_n_ with this κ and h.
  // Not lagged (a state before the first step, put back by StepSnapshot): the flag says so,
  // and a checkpoint then stores no lag positions.
  friction_lagged_ = s.friction_lagged;
  if (friction_ && s.friction_lagged) PetscCall(update_friction_lag(x_lag_));
  PetscFunctionReturn(0);
}

PetscErrorCode TimeIntegrator::advance(double t_end, StepReport* report) {
  PetscFunctionBeginUser;
  const double start = MPI_Wtime();
  const double t = t_end;
  set_time_step(t_end - time_);
  const double h = h_;
  *report = StepReport{};
  report->time = t;
  report->dt = t_end - time_;
  // What a failed attempt must leave as it found (x is restored from x_n below).
  const double kappa_before = contact_ ? contact_->kappa() : 0;
  const double previous_min_distance2_before = previous_min_distance2_;

  PetscCall(VecCopy(x_, x_n_));
  // The step's matrices depend on its state alone, so that a restart from a checkpoint of this
  // step makes the same ones (a kept matrix can hold entries of earlier steps' pairs).
  potential_.require_exact_pattern();
  // Obstacles stand where they were at the step's start until reach_prescribed_positions moves
  // them (also after a failed attempt, which leaves them at its end).
  if (contact_) contact_->set().start_obstacle_step(time_);
  if (!problem_.is_static) {
    PetscCall(VecWAXPY(x_hat_, h, v_, x_n_));  // x̂ = x_n + h v_n
    PetscCall(potential_.begin_step(x_hat_));
  }
  const double solve_start = MPI_Wtime();
  const EvaluationTimes before = potential_.times();
  if (contact_) {
    contact_->reset_stats();
    PetscCall(initialize_barrier_stiffness());
  }
  if (friction_) PetscCall(update_friction_lag(x_n_));
  PetscCall(reach_prescribed_positions(t, report));
  // Lagged friction (IPC §5): solve, re-freeze the friction pairs at the solution, solve again.
  const int lag_iterations = friction_ ? std::max(1, problem_.friction_iterations) : 1;
  for (int lag = 0; lag < lag_iterations && report->failure.empty(); ++lag) {
    if (lag > 0) {
      PetscCall(update_friction_lag(x_));
      PetscCall(potential_.prepare_point(x_));
    }
    NewtonReport solve;
    PetscCall(newton_.solve(x_, &solve));
    report->newton.iterations += solve.iterations;
    report->newton.linear_iterations += solve.linear_iterations;
    report->newton.preconditioner_rebuilds += solve.preconditioner_rebuilds;
    report->newton.exact_hessian_iterations += solve.exact_hessian_iterations;
    report->newton.exact_hessian_fallbacks += solve.exact_hessian_fallbacks;
    report->newton.min_alpha = std::min(report->newton.min_alpha, solve.min_alpha);
    report->newton.min_alpha_ccd = std::min(report->newton.min_alpha_ccd, solve.min_alpha_ccd);
    report->newton.step_inf_norm = solve.step_inf_norm;
    report->newton.reason = solve.reason;
    report->newton.ended_by = solve.ended_by;
    report->stopped = solve.stopped;
    if (solve.reason < 0) report->failure = solve.stopped ? "stopped on request" : "Newton failed: " + solve.ended_by;
  }
  const double solve_wall = MPI_Wtime() - solve_start;
  solve_seconds_ += solve_wall;
  {
    // Evaluation intervals are disjoint and lie within the solves: the rest is KSP, AMG and
    // vector work (≥ 0 up to rounding).
    const EvaluationTimes in_solves = potential_.times() - before;
    solve_times_ += in_solves;
    report->linear_solve_seconds = solve_wall - evaluation_seconds(in_solves);
  }
  if (!report->failure.empty()) {
    PetscCall(VecCopy(x_n_, x_));
    // The retry starts from the same state. When CCD held the attempt back (surfaces closing
    // faster than the barrier could stop them within the step) the retry gets twice the
    // barrier stiffness, as IPC doubles κ when distances keep shrinking; otherwise κ is as
    // before the attempt. min_alpha_ccd is a global minimum, so every rank decides alike.
    if (contact_) {
      // (A stopped attempt is not retried: nothing to learn from it.)
      const bool held_back = report->newton.min_alpha_ccd < 1.0 && !report->stopped;
      contact_->set_kappa(held_back ? std::min(contact_->kappa_max(), 2 * contact_->kappa()) : kappa_before);
    }
    previous_min_distance2_ = previous_min_distance2_before;
    report->wall_seconds = MPI_Wtime() - start;
    PetscFunctionReturn(0);
  }

  if (problem_.is_static) {
    PetscCall(VecZeroEntries(v_));
  } else {
    PetscCall(VecWAXPY(v_, -1.0, x_n_, x_));  // v_{n+1} = (x_{n+1} − x_n) / h
    PetscCall(VecScale(v_, 1.0 / h));
  }
  PetscCall(potential_.objective(x_, &report->energy));
  // J_min where the elements' form evaluates (on the GPU in device runs, on the host threads
  // otherwise); the host pass over the mesh only for a potential without an element form.
  bool found = false;
  PetscCall(potential_.min_volume_ratio(x_, &report->min_volume_ratio, &found));
  if (!found) {
    std::vector<double> ratio;
    PetscCall(element_volume_ratios(&ratio));
    double local_min = ratio.empty() ? 1e300 : *std::min_element(ratio.begin(), ratio.end());
    PetscCallMPI(MPI_Allreduce(&local_min, &report->min_volume_ratio, 1, MPI_DOUBLE, MPI_MIN, mesh_->comm));
  }
  if (contact_) PetscCall(collect_contact_stats(report));
  if (check_invariants_) {
    std::string violated;
    if (report->min_volume_ratio <= 0)
      violated = "an element is inverted (min det F = " + std::to_string(report->min_volume_ratio) + ")";
    if (contact_ && violated.empty()) PetscCall(contact_state_problem(x_, &violated));
    if (!violated.empty()) {
      report->failure = "invariant violated: " + violated;
      report->fatal = true;
      PetscFunctionReturn(0);
    }
  }
  time_ = t;
  report->wall_seconds = MPI_Wtime() - start;
  PetscFunctionReturn(0);
}

// The Newton solve starts from x_n with the Dirichlet nodes at their positions at t. When that
// jump inverts an element next to them, or drives them into a contact (plates closing on a body
// by more than the gap in a step), the motion is applied in fractions instead: each admissible
// fraction is solved for (the minimiser with the Dirichlet nodes part-way), which carries the
// interior along, and the remaining motion is retried from there (Dirichlet continuation). Only
// the last solve, with the full motion, is the step's solution; the others build its initial
// guess. Triangle-mesh obstacles move with the same fractions of the step: their motion from the
// accepted fraction to the trial one is part of the CCD check, so an obstacle that moves into a
// body pushes it along in partial solves instead of jumping through it.
//
// Each fraction is tried in two states: the free nodes where the last solve left them, and (in
// a dynamic problem) carried on at the rate they moved so far in the step (v_n before the first
// partial solve), as a body the plates push moves along with them. Moving the Dirichlet nodes
// alone fits only the gap, so a squeezed body needed as many partial solves as the plates'
// travel holds gaps (40 and more per step, hundreds of Newton iterations, issue 32). A fraction
// that fits neither way is cut to 0.8 of the collision-free part CCD found for the better of the
// two (halved when an inverted element, not a contact, stopped it).
PetscErrorCode TimeIntegrator::reach_prescribed_positions(double t, StepReport* report) {
  PetscFunctionBeginUser;
  const double t0 = time_;
  double reached = 0.0;  // fraction of the step's Dirichlet motion already solved for
  double trial = 1.0;
  Vec accepted, jump, carry = nullptr;
  PetscCall(VecDuplicate(x_, &accepted));
  PetscCall(VecCopy(x_, accepted));
  PetscCall(VecDuplicate(x_, &jump));
  if (!problem_.is_static) {
    PetscCall(VecDuplicate(x_, &carry));
    PetscCall(VecWAXPY(carry, -1.0, x_n_, x_hat_));  // h v_n: the free nodes' motion per whole step
  }
  // x := accepted (+ the carry for the trial fraction), the Dirichlet nodes at the trial time;
  // *alpha the collision-free fraction of accepted -> x, *valid when all of it is admissible.
  // The obstacles stand at the trial time afterwards if it is valid, else where they were.
  auto try_state = [&](bool carried, double t_from, double t_to, PetscReal* alpha, PetscBool* valid) {
    PetscFunctionBeginUser;
    PetscCall(VecCopy(accepted, x_));
    if (carried) PetscCall(VecAXPY(x_, trial - reached, carry));
    PetscCall(apply_dirichlet(x_, t_to));
    if (contact_) contact_->set().move_obstacles(t_from, t_to);
    // CCD along accepted -> x (this also prepares the contact candidates around x).
    PetscCall(VecWAXPY(jump, -1.0, accepted, x_));
    PetscCall(potential_.max_step(accepted, jump, alpha));
    *valid = PETSC_FALSE;
    if (*alpha >= 1.0) PetscCall(potential_.is_valid(x_, valid));
    if (contact_) contact_->set().move_obstacles(*valid ? t_to : t_from, *valid ? t_to : t_from);
    PetscFunctionReturn(0);
  };
  for (;;) {
    const double t_from = t0 + reached * (t - t0), t_to = t0 + trial * (t - t0);
    PetscReal alpha, alpha_carried = 0;
    PetscBool valid;
    PetscCall(try_state(false, t_from, t_to, &alpha, &valid));
    if (!valid && carry) {
      PetscCall(try_state(true, t_from, t_to, &alpha_carried, &valid));
      alpha = std::max(alpha, alpha_carried);
    }
    if (valid && trial == 1.0) break;
    if (valid) {
      NewtonReport partial;
      PetscCall(newton_.solve(x_, &partial));
      report->newton.iterations += partial.iterations;
      report->newton.linear_iterations += partial.linear_iterations;
      report->newton.min_alpha_ccd = std::min(report->newton.min_alpha_ccd, partial.min_alpha_ccd);
      ++report->dirichlet_substeps;
      if (partial.reason < 0) {
        report->stopped = partial.stopped;
        report->failure = partial.stopped ? "stopped on request"
                                          : "Newton failed on a part of the prescribed motion: " + partial.ended_by;
        break;
      }
      PetscCall(VecCopy(x_, accepted));
      if (carry) {  // the rate the free nodes moved at in the step so far, per whole step
        PetscCall(VecWAXPY(carry, -1.0, x_n_, accepted));
        PetscCall(VecScale(carry, 1.0 / trial));
      }
      reached = trial;
      trial = 1.0;
      continue;
    }
    PetscCall(VecCopy(accepted, x_));
    const double cut = alpha < 1.0 ? std::min(0.5, 0.8 * static_cast<double>(alpha)) : 0.5;
    trial = reached + cut * (trial - reached);
    if (!(trial - reached > 0x1p-30)) {
      report->failure = "the prescribed motion of this step inverts an element next to the Dirichlet nodes, or "
                        "drives them into a contact, even when applied in 2^-30 fractions";
      break;
    }
  }
  PetscCall(VecDestroy(&accepted));
  PetscCall(VecDestroy(&jump));
  PetscCall(VecDestroy(&carry));
  PetscFunctionReturn(0);
}

// The barrier stiffness of a step (IPC, Li et al. 2020, supplement, "adaptive barrier
// stiffness"), fixed for the whole step:
//  - the κ that balances the barrier gradient against the rest of the incremental potential's
//    gradient at x_n, κ = −∇B₁·∇E / ‖∇B₁‖² (∇B₁ the barrier gradient for κ = 1), clamped to
//    [κ_min, κ_max]; dipc never lowers κ during a run;
//  - doubled (up to κ_max) when the minimum distance is below IPC's tiny threshold and still
//    shrinking. IPC applies this test between Newton iterations; dipc applies it between time
//    steps, so that every step minimises one fixed potential: its solution then does not depend
//    on the Newton path, which the line search's CCD bounds make sensitive to round-off (and so
//    to the number of ranks).
PetscErrorCode TimeIntegrator::initialize_barrier_stiffness() {
  PetscFunctionBeginUser;
  if (!contact_->kappa_adaptive()) PetscFunctionReturn(0);
  PetscCall(potential_.prepare_point(x_));
  Vec ge, gb;
  PetscCall(VecDuplicate(x_, &ge));
  PetscCall(VecDuplicate(x_, &gb));
  const Form* contact = contact_;
  PetscCall(potential_.partial_gradient(x_, ge, [contact](const Form& f) { return &f != contact; }));
  double kappa = contact_->kappa();
  contact_->set_kappa(1.0);
  PetscCall(potential_.partial_gradient(x_, gb, [contact](const Form& f) { return &f == contact; }));
  PetscReal dot, nn;
  PetscCall(VecDot(gb, ge, &dot));
  PetscCall(VecDot(gb, gb, &nn));
  double balanced = nn > 0 ? -dot / nn : contact_->kappa_min();
  balanced = std::min(contact_->kappa_max(), std::max(contact_->kappa_min(), balanced));
  kappa = std::max(kappa, balanced);

  double local = 0, d2 = 0;
  PetscCall(potential_.with_local(x_, [&](const double* xl, std::size_t) { local = contact_->min_distance(xl); }));
  local *= local;
  PetscCallMPI(MPI_Allreduce(&local, &d2, 1, MPI_DOUBLE, MPI_MIN, mesh_->comm));
  const double eps2 = contact_->min_distance_threshold2();
  if (previous_min_distance2_ >= 0 && previous_min_distance2_ < eps2 && d2 < eps2 && d2 < previous_min_distance2_)
    kappa = std::min(contact_->kappa_max(), 2 * kappa);
  previous_min_distance2_ = d2;
  contact_->set_kappa(kappa);
  PetscCall(VecDestroy(&ge));
  PetscCall(VecDestroy(&gb));
  PetscFunctionReturn(0);
}

// Freezes the friction pairs at x_lag (with x_n the start of the step), then lets the
// potential gather their nodes.
PetscErrorCode TimeIntegrator::update_friction_lag(Vec x_lag) {
  PetscFunctionBeginUser;
  PetscCall(potential_.prepare_point(x_lag));
  if (x_lag != x_lag_) PetscCall(VecCopy(x_lag, x_lag_));  // for a checkpoint (resume_state)
  friction_lagged_ = true;
  std::vector<double> start;
  PetscCall(potential_.with_local(x_n_, [&](const double* xl, std::size_t n) { start.assign(xl, xl + n); }));
  PetscCall(
      potential_.with_local(x_lag, [&](const double* xl, std::size_t) { friction_->update_lag(xl, start.data()); }));
  PetscCall(potential_.prepare_point(x_lag));
  PetscFunctionReturn(0);
}

PetscErrorCode TimeIntegrator::collect_contact_stats(StepReport* report) {
  PetscFunctionBeginUser;
  PetscCall(potential_.prepare_point(x_));
  double local_d = 0;
  std::array<long, ContactForm::num_pair_kinds> local_kinds{};
  PetscCall(potential_.with_local(x_, [&](const double* xl, std::size_t) {
    local_d = contact_->min_distance(xl);
    local_kinds = contact_->active_pair_counts(xl);
  }));
  PetscCallMPI(MPI_Allreduce(local_kinds.data(), report->contact_pairs_by_kind.data(), ContactForm::num_pair_kinds,
                             MPI_LONG, MPI_SUM, mesh_->comm));
  long local_pairs = 0;
  for (long n : local_kinds) local_pairs += n;
  const ContactStats& st = contact_->stats();
  double times[4] = {st.broad_phase_seconds, st.ccd_seconds, st.barrier_seconds, st.exchange_seconds}, worst[4];
  PetscCallMPI(MPI_Allreduce(times, worst, 4, MPI_DOUBLE, MPI_MAX, mesh_->comm));
  PetscCallMPI(MPI_Allreduce(&local_pairs, &report->contact_pairs, 1, MPI_LONG, MPI_SUM, mesh_->comm));
  PetscCallMPI(MPI_Allreduce(&local_d, &report->min_distance, 1, MPI_DOUBLE, MPI_MIN, mesh_->comm));
  report->kappa = contact_->kappa();
  report->alpha_ccd = report->newton.min_alpha_ccd;
  report->broad_phase_seconds = worst[0], report->ccd_seconds = worst[1];
  report->barrier_seconds = worst[2], report->exchange_seconds = worst[3];
  PetscFunctionReturn(0);
}

PetscErrorCode TimeIntegrator::contact_forces(Vec contact_force, Vec friction_force,
                                              std::array<long, ContactForm::num_pair_kinds>* pairs_by_kind) {
  PetscFunctionBeginUser;
  PetscCheck(contact_, mesh_->comm, PETSC_ERR_ARG_WRONGSTATE, "contact_forces: the problem has no contact");
  PetscCall(potential_.prepare_point(x_));
  const double h2 = problem_.is_static ? 1.0 : h_ * h_;
  const Form* contact = contact_;
  PetscCall(potential_.partial_gradient(
      x_, contact_force, [contact](const Form& f) { return &f == contact; }, true));
  PetscCall(VecScale(contact_force, -1.0 / h2));
  if (friction_force && friction_) {
    const Form* friction = friction_;
    PetscCall(potential_.partial_gradient(
        x_, friction_force, [friction](const Form& f) { return &f == friction; }, true));
    PetscCall(VecScale(friction_force, -1.0 / h2));
  } else if (friction_force) {
    PetscCall(VecZeroEntries(friction_force));
  }
  std::array<long, ContactForm::num_pair_kinds> local{};
  PetscCall(
      potential_.with_local(x_, [&](const double* xl, std::size_t) { local = contact_->active_pair_counts(xl); }));
  PetscCallMPI(
      MPI_Allreduce(local.data(), pairs_by_kind->data(), ContactForm::num_pair_kinds, MPI_LONG, MPI_SUM, mesh_->comm));
  PetscFunctionReturn(0);
}

PetscErrorCode TimeIntegrator::measure(PhysicalQuantities* q) {
  PetscFunctionBeginUser;
  *q = PhysicalQuantities{};
  // Energies of the terms that carry h² in the potential, per unit h² (a static solve has none).
  std::vector<double> values;
  PetscCall(potential_.form_values(x_, &values));
  const double h2 = problem_.is_static ? 1.0 : h_ * h_;
  for (std::size_t f = 0; f < form_names_.size(); ++f) {
    if (form_names_[f] == "elastic") q->elastic_energy = values[f] / h2;
    if (form_names_[f] == "body force") q->gravity_energy = values[f] / h2;
  }
  const PetscScalar *x, *v;
  PetscCall(VecGetArrayRead(x_, &x));
  PetscCall(VecGetArrayRead(v_, &v));
  double local[7] = {0, 0, 0, 0, 0, 0, 0};
  for (std::size_t n = 0; n < node_mass_.size(); ++n) {
    const double m = node_mass_[n], *xn = x + 3 * n, *vn = v + 3 * n;
    double xv[3];
    cross3(xn, vn, xv);
    local[0] += 0.5 * m * squared_norm3(vn);
    for (int c = 0; c < 3; ++c) local[1 + c] += m * vn[c];
    for (int c = 0; c < 3; ++c) local[4 + c] += m * xv[c];
  }
  PetscCall(VecRestoreArrayRead(x_, &x));
  PetscCall(VecRestoreArrayRead(v_, &v));
  double total[7];
  PetscCallMPI(MPI_Allreduce(local, total, 7, MPI_DOUBLE, MPI_SUM, mesh_->comm));
  q->kinetic_energy = total[0];
  for (int c = 0; c < 3; ++c) q->momentum[c] = total[1 + c], q->angular_momentum[c] = total[4 + c];
  PetscFunctionReturn(0);
}

PetscErrorCode TimeIntegrator::element_volume_ratios(std::vector<double>* ratio) {
  PetscFunctionBeginUser;
  PetscCall(exchange_.to_local(x_, x_local_));
  const PetscScalar* xl;
  ratio->assign(elements_->num_elements(), 0.0);
  PetscCall(VecGetArrayRead(x_local_, &xl));
  min_volume_ratio(elements_->block(), xl, ratio->data());
  PetscCall(VecRestoreArrayRead(x_local_, &xl));
  PetscFunctionReturn(0);
}

}  // namespace dipc
