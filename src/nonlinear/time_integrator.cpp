#include "nonlinear/time_integrator.hpp"

#include <algorithm>
#include <cmath>

#include "assembly/hex8_mass.hpp"
#include "nonlinear/body_force_form.hpp"
#include "nonlinear/elastic_form.hpp"
#include "nonlinear/inertia_form.hpp"

namespace dipc {

namespace {

// Lumped mass of every local node with the contributions of all ranks summed, so that
// owned-node loops (inertia, gravity) see complete masses.
PetscErrorCode assemble_node_masses(const DistributedMesh& mesh, const ElementData& elements,
                                    std::vector<double>* node_mass) {
  PetscFunctionBeginUser;
  GhostExchange scalar;
  PetscCall(scalar.setup(mesh, 1));
  Vec local, global;
  PetscCall(scalar.create_local_vec(&local));
  PetscCall(scalar.create_global_vec(&global));
  PetscScalar* m;
  PetscCall(VecZeroEntries(local));
  PetscCall(VecGetArray(local, &m));
  for (int e = 0; e < elements.num_elements(); ++e) {
    double X[24], me[8];
    elements.gather_reference(e, X);
    hex8_lumped_mass(X, elements.rho[e], me);
    for (int a = 0; a < 8; ++a) m[elements.nodes[8 * static_cast<std::size_t>(e) + a]] += me[a];
  }
  PetscCall(VecRestoreArray(local, &m));
  PetscCall(VecZeroEntries(global));
  PetscCall(scalar.add_to_global(local, global));
  PetscCall(scalar.to_local(global, local));
  const PetscScalar* mc;
  PetscCall(VecGetArrayRead(local, &mc));
  node_mass->assign(mc, mc + mesh.num_local_nodes());
  PetscCall(VecRestoreArrayRead(local, &mc));
  PetscCall(VecDestroy(&local));
  PetscCall(VecDestroy(&global));
  PetscFunctionReturn(0);
}

}  // namespace

TimeIntegrator::~TimeIntegrator() {
  VecDestroy(&X_);
  VecDestroy(&x_);
  VecDestroy(&x_n_);
  VecDestroy(&v_);
  VecDestroy(&x_hat_);
  VecDestroy(&x_local_);
}

PetscErrorCode TimeIntegrator::setup(const DistributedMesh& mesh, const ProblemSetup& problem,
                                     double velocity_tol) {
  PetscFunctionBeginUser;
  mesh_ = &mesh;
  problem_ = problem;
  elements_ = std::make_unique<ElementData>(mesh, problem.body_materials);
  PetscCall(exchange_.setup(mesh, 3));

  const bool gravity = problem.gravity[0] != 0 || problem.gravity[1] != 0 || problem.gravity[2] != 0;
  const bool inertia = !problem.is_static;
  std::vector<double> node_mass;
  if (gravity || (inertia && problem.lumped_mass)) PetscCall(assemble_node_masses(mesh, *elements_, &node_mass));

  // Only the terms this problem needs (DESIGN.md: "model only what a scene requires").
  const double h2 = problem.is_static ? 1.0 : problem.dt * problem.dt;
  std::vector<std::unique_ptr<Form>> forms;
  if (inertia && problem.lumped_mass)
    forms.push_back(std::make_unique<LumpedInertiaForm>(node_mass, mesh.num_owned_nodes, mesh.node_offset));
  else if (inertia)
    forms.push_back(std::make_unique<ConsistentInertiaForm>(*elements_));
  forms.push_back(std::make_unique<ElasticForm>(*elements_, h2));
  if (gravity) forms.push_back(std::make_unique<BodyForceForm>(node_mass, mesh.num_owned_nodes, problem.gravity, h2));
  form_names_.clear();
  for (auto& f : forms) form_names_.push_back(f->name());

  // Dirichlet sets: later sets win where they overlap.
  dirichlet_set_.assign(mesh.num_local_nodes(), -1);
  for (std::size_t s = 0; s < problem.dirichlet.size(); ++s)
    for (std::int32_t n : problem.dirichlet[s].local_nodes) dirichlet_set_[n] = static_cast<int>(s);
  std::vector<char> prescribed(3 * static_cast<std::size_t>(mesh.num_local_nodes()), 0);
  for (int n = 0; n < mesh.num_local_nodes(); ++n)
    if (dirichlet_set_[n] >= 0) prescribed[3 * n] = prescribed[3 * n + 1] = prescribed[3 * n + 2] = 1;

  // State vectors: reference positions, x, x_n, v, x̂.
  PetscCall(exchange_.create_global_vec(&X_));
  PetscCall(VecDuplicate(X_, &x_));
  PetscCall(VecDuplicate(X_, &x_n_));
  PetscCall(VecDuplicate(X_, &v_));
  PetscCall(VecDuplicate(X_, &x_hat_));
  PetscCall(exchange_.create_local_vec(&x_local_));
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
    if (dirichlet_set_[n] >= 0) vn = problem.dirichlet[dirichlet_set_[n]].motion.velocity_at(Xn, 0.0);
    for (int c = 0; c < 3; ++c) X[3 * n + c] = Xn[c], v[3 * n + c] = problem.is_static ? 0.0 : vn[c];
  }
  PetscCall(VecRestoreArray(X_, &X));
  PetscCall(VecRestoreArray(v_, &v));
  PetscCall(VecCopy(X_, x_));

  PetscCall(potential_.setup(mesh.comm, mesh, exchange_, std::move(forms), std::move(prescribed)));
  PetscCall(newton_.setup(mesh.comm, &potential_, x_, problem.is_static ? 1.0 : problem.dt, velocity_tol));
  PetscFunctionReturn(0);
}

PetscInt TimeIntegrator::num_dofs() const {
  PetscInt n = 0;
  VecGetSize(x_, &n);
  return n;
}

PetscInt TimeIntegrator::hessian_entries() const { return potential_.num_hessian_entries(); }

PetscErrorCode TimeIntegrator::apply_dirichlet(Vec x, double t) {
  PetscFunctionBeginUser;
  PetscScalar* xa;
  PetscCall(VecGetArray(x, &xa));
  for (int n = 0; n < mesh_->num_owned_nodes; ++n) {
    if (dirichlet_set_[n] < 0) continue;
    const auto p = problem_.dirichlet[dirichlet_set_[n]].motion.position(mesh_->coordinates[n], t);
    for (int c = 0; c < 3; ++c) xa[3 * n + c] = p[c];
  }
  PetscCall(VecRestoreArray(x, &xa));
  PetscFunctionReturn(0);
}

PetscErrorCode TimeIntegrator::step(StepReport* report) {
  PetscFunctionBeginUser;
  const double start = MPI_Wtime();
  const double h = problem_.dt;
  const double t = time_ + h;
  *report = StepReport{};
  report->step = steps_taken_ + 1;
  report->time = t;

  PetscCall(VecCopy(x_, x_n_));
  if (!problem_.is_static) {
    PetscCall(VecWAXPY(x_hat_, h, v_, x_n_));  // x̂ = x_n + h v_n
    PetscCall(potential_.begin_step(x_hat_));
  }
  const double solve_start = MPI_Wtime();
  PetscCall(reach_prescribed_positions(t, report));
  if (report->failure.empty()) {
    NewtonReport final_solve;
    PetscCall(newton_.solve(x_, &final_solve));
    report->newton.iterations += final_solve.iterations;
    report->newton.linear_iterations += final_solve.linear_iterations;
    report->newton.min_alpha = std::min(report->newton.min_alpha, final_solve.min_alpha);
    report->newton.step_inf_norm = final_solve.step_inf_norm;
    report->newton.reason = final_solve.reason;
    if (final_solve.reason < 0)
      report->failure = std::string("Newton did not converge: ") + SNESConvergedReasons[final_solve.reason];
  }
  solve_seconds_ += MPI_Wtime() - solve_start;
  if (!report->failure.empty()) {
    PetscCall(VecCopy(x_n_, x_));
    PetscFunctionReturn(0);
  }

  if (problem_.is_static) {
    PetscCall(VecZeroEntries(v_));
  } else {
    PetscCall(VecWAXPY(v_, -1.0, x_n_, x_));  // v_{n+1} = (x_{n+1} − x_n) / h
    PetscCall(VecScale(v_, 1.0 / h));
  }
  PetscCall(potential_.objective(x_, &report->energy));
  std::vector<double> ratio;
  PetscCall(element_volume_ratios(&ratio));
  double local_min = ratio.empty() ? 1e300 : *std::min_element(ratio.begin(), ratio.end());
  PetscCallMPI(MPI_Allreduce(&local_min, &report->min_volume_ratio, 1, MPI_DOUBLE, MPI_MIN, mesh_->comm));
  ++steps_taken_;
  time_ = t;
  report->wall_seconds = MPI_Wtime() - start;
  PetscFunctionReturn(0);
}

// The Newton solve starts from x_n with the Dirichlet nodes at their positions at t. When that
// jump inverts an element next to them (a large prescribed motion per step), the motion is
// applied in fractions instead: each admissible fraction is solved for (the minimiser with the
// Dirichlet nodes part-way), which carries the interior along, and the remaining motion is
// retried from there, halving the fraction when it still inverts (Dirichlet continuation).
// Only the last solve, with the full motion, is the step's solution; the others only build
// its initial guess.
PetscErrorCode TimeIntegrator::reach_prescribed_positions(double t, StepReport* report) {
  PetscFunctionBeginUser;
  const double t0 = time_;
  double reached = 0.0;  // fraction of the step's Dirichlet motion already solved for
  double trial = 1.0;
  Vec accepted;
  PetscCall(VecDuplicate(x_, &accepted));
  PetscCall(VecCopy(x_, accepted));
  for (int halvings = 0;;) {
    PetscCall(apply_dirichlet(x_, t0 + trial * (t - t0)));
    PetscBool valid;
    PetscCall(potential_.is_valid(x_, &valid));
    if (valid && trial == 1.0) break;
    if (valid) {
      NewtonReport partial;
      PetscCall(newton_.solve(x_, &partial));
      report->newton.iterations += partial.iterations;
      report->newton.linear_iterations += partial.linear_iterations;
      ++report->dirichlet_substeps;
      if (partial.reason < 0) {
        report->failure = std::string("Newton did not converge on a part of the prescribed motion: ") +
                          SNESConvergedReasons[partial.reason];
        break;
      }
      PetscCall(VecCopy(x_, accepted));
      reached = trial;
      trial = 1.0;
      halvings = 0;
      continue;
    }
    PetscCall(VecCopy(accepted, x_));
    trial = 0.5 * (reached + trial);
    if (++halvings > 30) {
      report->failure = "the prescribed motion of this step inverts an element next to the Dirichlet nodes even "
                        "when applied in 2^-30 fractions; reduce the time step";
      break;
    }
  }
  PetscCall(VecDestroy(&accepted));
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
