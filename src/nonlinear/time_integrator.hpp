// TimeIntegrator: implicit Euler as incremental-potential minimisation (docs/design.md §1.1), or a
// sequence of static solves. Builds the forms the problem needs (forms/form_factory.hpp), owns
// the distributed state and advances it step by step.
#pragma once
#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "forms/contact_form.hpp"
#include "forms/element_data.hpp"
#include "forms/problem.hpp"
#include "nonlinear/newton_solver.hpp"

namespace dipc {

class FrictionForm;

// What one step did. TimeIntegrator::advance fills it for one attempt; StepRecovery sums the
// attempts and sub-steps of a scene step into one (iterations and times added up, the state
// fields those at the step's end).
struct StepReport {
  int step = 0;     // 1-based index of the scene step
  double time = 0;  // time at the end of the step (exactly k·dt for a scene step)
  double dt = 0;    // the step length taken (the smallest sub-step's for a scene step)
  NewtonReport newton;
  double energy = 0;  // E at the accepted state
  double min_volume_ratio = 0;
  double wall_seconds = 0;
  int dirichlet_substeps = 0;  // partial solves needed to reach the prescribed positions
  // Contact (when the problem has it): global values at the end of the step.
  long contact_pairs = 0;                                                 // active pairs (d < d̂)
  std::array<long, ContactForm::num_pair_kinds> contact_pairs_by_kind{};  // the same by ContactForm::pair_kind_name
  double min_distance = 0;  // unsquared, over candidate pairs (∞ without any)
  double kappa = 0;         // barrier stiffness
  double alpha_ccd = 1;     // smallest CCD bound on a Newton step during the step
  double broad_phase_seconds = 0, ccd_seconds = 0, barrier_seconds = 0, exchange_seconds = 0;  // max over ranks
  // This rank's wall time in the Newton solves of the step apart from every evaluation of the
  // potential (assembly, line search, contact): KSP + AMG setup + vector work.
  double linear_solve_seconds = 0;
  std::string failure;  // empty when the step succeeded; otherwise why it did not
  bool fatal = false;   // the failure is a violated invariant: retrying with a smaller step is no cure
  // A stop request ended the attempt (StepControl::stop_requested): the step was abandoned,
  // not failed, so it is neither retried nor reported as a failure.
  bool stopped = false;
  // Step recovery (scene steps): sub-steps taken, failed attempts retried with a halved step,
  // and one line per failed attempt (time, step length, reason).
  int substeps = 1;
  int dt_cuts = 0;
  std::vector<std::string> cuts;
};

// Physical quantities of the current state, summed over ranks (lumped masses): what a user
// checks conservation with. Energies in J, momenta about the origin.
struct PhysicalQuantities {
  double kinetic_energy = 0, elastic_energy = 0, gravity_energy = 0;
  std::array<double, 3> momentum{0, 0, 0}, angular_momentum{0, 0, 0};
};

struct StepControl {
  double velocity_tol = 0;    // Newton's ‖p‖∞/h tolerance (length/s); for static solves a length
  double alpha_floor = 1e-6;  // line-search stall floor (newton_solver.hpp)
  // After every step verify det J > 0 everywhere and, with contact, no intersection and a
  // positive minimum distance (a violated invariant fails the run).
  bool check_invariants = false;
  // Collective: true on every rank when the run is to stop now (a stop signal). Asked at every
  // Newton iteration; an attempt it ends is reported as StepReport::stopped. Empty: never.
  std::function<bool()> stop_requested;
};

class TimeIntegrator {
 public:
  TimeIntegrator() = default;
  ~TimeIntegrator();
  TimeIntegrator(const TimeIntegrator&) = delete;
  TimeIntegrator& operator=(const TimeIntegrator&) = delete;

  // With contact, an initial state whose surfaces intersect or touch is bad input: a PETSc
  // error PETSC_ERR_USER_INPUT naming the bodies and nodes (app/petsc_input_errors.hpp), as is
  // -dipc_mixed_solve with device forms.
  // space: where the element and nodal forms (and contact, where ported) evaluate.
  PetscErrorCode setup(const DistributedMesh& mesh, const ProblemSetup& problem, const StepControl& control,
                       MemorySpace space = MemorySpace::host);
  // One attempt at a step from time() to t_end (a time step of length t_end − time(), or a
  // static load step to pseudo-time t_end). A step that cannot be taken (Newton failed, the
  // prescribed motion inverts an element) is reported in StepReport::failure and leaves the
  // state, the barrier stiffness included, as it was, so that it can be retried with a shorter
  // step (StepRecovery). A violated invariant is reported as fatal.
  PetscErrorCode advance(double t_end, StepReport* report);
  // Collective: the physical quantities of the current state.
  PetscErrorCode measure(PhysicalQuantities* q);

  // The state beyond positions and velocities that the next step depends on: what a
  // checkpoint stores and a restart restores. Besides these scalars it is three node fields,
  // written by the caller into positions(), velocities(), previous_positions() and, when
  // friction_lagged, friction_lag_positions() before resume(): the next step's κ balances the
  // barrier against the gradient of the other terms, friction's included, whose pairs are still
  // those frozen in the last step (at friction_lag_positions(), from previous_positions(), the
  // start of the last sub-step), so resume() freezes them again from those two fields.
  struct ResumeState {
    double time = 0;
    double step_length = 0;              // h of the last step (forms and Newton's velocity test)
    double kappa = 0;                    // barrier stiffness (contact; never lowered in a run)
    double previous_min_distance2 = -1;  // κ's growth test (initialize_barrier_stiffness)
    bool friction_lagged = false;        // friction pairs were frozen (a step was attempted)
  };
  ResumeState resume_state() const;
  PetscErrorCode resume(const ResumeState& state);
  Vec previous_positions() const { return x_n_; }
  Vec friction_lag_positions() const { return x_lag_; }  // null without friction

  double time() const { return time_; }
  double scene_dt() const { return problem_.dt; }
  // The prescribed node sets (ProblemSetup::dirichlet: the scene's Dirichlet conditions, then
  // its kinematic bodies), and a new motion for set k between steps: from now on its nodes
  // follow `motion` from where they stand, x(t) = motion.position(x_now, t − time()), so that a
  // fixed motion holds them there (not at rest) and nothing jumps. A checkpoint does not store
  // such a change: a restarted run follows the scene's motions until told again.
  const std::vector<DirichletSet>& dirichlet_sets() const { return problem_.dirichlet; }
  PetscErrorCode set_prescribed_motion(int k, const PrescribedMotion& motion);
  // NewtonSolver::set_retrying.
  PetscErrorCode set_retrying(bool retrying) { return newton_.set_retrying(retrying); }
  const std::vector<std::string>& user_snes_options() const { return newton_.user_snes_options(); }
  const std::vector<std::string>& form_names() const { return form_names_; }
  PetscInt num_dofs() const;
  std::int64_t hessian_entries() const;
  Vec positions() const { return x_; }
  // Lumped, owned nodes; empty in a static run without gravity or contact (nothing needs them).
  const std::vector<double>& node_masses() const { return node_mass_; }
  Vec velocities() const { return v_; }
  Vec reference_positions() const { return X_; }
  // Min det F per local element at the current state (output).
  PetscErrorCode element_volume_ratios(std::vector<double>* ratio);
  // Collective, contact problems only (output): the forces the barrier and friction exert on
  // each owned node at the current state, in N, prescribed nodes included, into global Vecs
  // (friction_force may be null; without a friction form it is zeroed). The potential carries
  // both terms in units of h²·energy (the barrier's κ and friction's λ_k are scaled like the
  // h²Ψ of the elastic form), so the force is −∇B/h² and −∇D/h² with h the last (sub-)step's
  // length, −∇B in a static solve. Also the active pairs by kind, summed over the ranks.
  PetscErrorCode contact_forces(Vec contact_force, Vec friction_force,
                                std::array<long, ContactForm::num_pair_kinds>* pairs_by_kind);
  // Evaluation times since setup began (setup's matrix and contact checks included)...
  const EvaluationTimes& evaluation_times() const { return potential_.times(); }
  // ... and those inside the Newton solves of advance(), which solve_seconds() encloses: the
  // timing table's phases, with the solves' remainder (KSP, AMG) solve_seconds() minus their
  // evaluation_seconds(), which cannot be negative.
  const EvaluationTimes& solve_evaluation_times() const { return solve_times_; }
  const ContactForm* contact() const { return contact_; }
  const FrictionForm* friction() const { return friction_; }
  double solve_seconds() const { return solve_seconds_; }  // whole solves of advance()
  // What the potential does beyond element and nodal terms (see IncrementalPotential).
  bool has_changing_pattern() const { return potential_.has_changing_pattern(); }
  bool has_extra_nodes() const { return potential_.has_extra_nodes(); }
  bool has_step_limit() const { return potential_.has_step_limit(); }
  SNES snes() const { return newton_.snes(); }
  Mat jacobian() const { return newton_.jacobian(); }

 private:
  // setup()'s steps, in the order it takes them. First the lumped masses of the local nodes where
  // the forms need them (node_mass_: the owned ones).
  PetscErrorCode assemble_masses_for_forms(std::vector<double>* node_mass);
  // The problem's forms (form_factory.hpp); sets contact_, friction_ and form_names_.
  PetscErrorCode build_problem_forms(const std::vector<double>& node_mass, MemorySpace space,
                                     std::vector<std::unique_ptr<Form>>* forms);
  // Before device forms are built: -dipc_mixed_solve with mean-dilatation elements is bad input
  // (PETSC_ERR_USER_INPUT).
  PetscErrorCode refuse_mixed_solve_on_device(const ElementData& deformable);
  // dirichlet_set_, and the prescribed dofs (3 flags per local node).
  void assign_dirichlet_sets(std::vector<char>* prescribed);
  PetscErrorCode create_state_vectors();
  PetscErrorCode set_initial_state();
  // With contact: intersecting or touching surfaces at the start are bad input (PETSC_ERR_USER_INPUT).
  PetscErrorCode refuse_intersecting_start();

  // Sets the step length h of the forms and of Newton's velocity test.
  void set_time_step(double h);
  PetscErrorCode apply_dirichlet(Vec x, double t);
  PetscErrorCode reach_prescribed_positions(double t, StepReport* report);
  PetscErrorCode initialize_barrier_stiffness();
  PetscErrorCode update_friction_lag(Vec x_lag);
  PetscErrorCode collect_contact_stats(StepReport* report);
  // Collective: empty when x has no edge–triangle crossing and every distance is positive,
  // otherwise what is wrong (bodies and nodes).
  PetscErrorCode contact_state_problem(Vec x, std::string* problem);

  const DistributedMesh* mesh_ = nullptr;
  ProblemSetup problem_;
  std::unique_ptr<ElementData> elements_;
  std::unique_ptr<ElementData> deformable_elements_;  // without kinematic bodies (when there are any)
  GhostExchange exchange_;
  IncrementalPotential potential_;
  NewtonSolver newton_;
  ContactForm* contact_ = nullptr;    // owned by potential_, null without contact
  FrictionForm* friction_ = nullptr;  // owned by potential_, null without friction
  std::vector<int> dirichlet_set_;    // per owned node: index into problem_.dirichlet, or −1
  // Motions set between steps (set_prescribed_motion): per set the time it started (NaN: the
  // scene's motion from the rest positions at t = 0), per owned node where it started.
  std::vector<double> motion_start_time_;
  std::vector<std::array<double, 3>> motion_start_;
  std::vector<std::string> form_names_;
  Vec X_ = nullptr, x_ = nullptr, x_n_ = nullptr, v_ = nullptr, x_hat_ = nullptr;
  Vec x_local_ = nullptr;
  Vec x_lag_ = nullptr;  // where friction's pairs were last frozen (friction runs)
  bool friction_lagged_ = false;
  bool check_invariants_ = false;
  double previous_min_distance2_ = -1;  // at the start of the previous step (κ update)
  double time_ = 0;
  double h_ = 0;                   // the current step length (dynamic runs)
  std::vector<double> node_mass_;  // lumped, owned nodes (measure()); empty when no term needs masses
  double solve_seconds_ = 0;
  EvaluationTimes solve_times_;
};

}  // namespace dipc
