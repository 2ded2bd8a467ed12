#include "forms/form_factory.hpp"

#include <algorithm>

#include "forms/body_force_form.hpp"
#include "forms/contact_form.hpp"
#include "forms/elastic_form.hpp"
#include "forms/friction_form.hpp"
#include "forms/inertia_form.hpp"
#include "options/dipc_options.hpp"

namespace dipc {

namespace {

bool has_inertia(const ProblemSetup& problem) { return !problem.is_static; }

bool has_gravity(const ProblemSetup& problem) {
  return problem.gravity[0] != 0 || problem.gravity[1] != 0 || problem.gravity[2] != 0;
}

// The barrier, then friction where μ > 0 in a dynamic run.
PetscErrorCode add_contact_forms(const DistributedMesh& mesh, const ProblemSetup& problem,
                                 const std::vector<double>& node_mass, const GhostExchange& nodal, MemorySpace space,
                                 bool majorize_reversals, ProblemForms* built) {
  PetscFunctionBeginUser;
  auto contact = std::make_unique<ContactForm>(mesh, problem.contact_parameters, space, &nodal);
  // κ bounds from the average nodal mass (IPC supplement).
  double local[2] = {0, static_cast<double>(mesh.num_owned_nodes)}, total[2];
  for (int n = 0; n < mesh.num_owned_nodes; ++n) local[0] += node_mass[n];
  PetscCallMPI(MPI_Allreduce(local, total, 2, MPI_DOUBLE, MPI_SUM, mesh.comm));
  contact->set_kappa_bounds(total[0] / std::max(1.0, total[1]), problem.length_scale);
  built->contact = contact.get();
  built->forms.push_back(std::move(contact));
  if (problem.friction > 0 && !problem.is_static) {
    auto friction = std::make_unique<FrictionForm>(*built->contact, problem.friction, problem.friction_epsv,
                                                   problem.dt, majorize_reversals);
    built->friction = friction.get();
    built->forms.push_back(std::move(friction));
  }
  PetscFunctionReturn(0);
}

}  // namespace

bool forms_need_node_masses(const ProblemSetup& problem) {
  return has_inertia(problem) || has_gravity(problem) || problem.contact;
}

std::unique_ptr<ElementData> deformable_elements(const DistributedMesh& mesh, const ProblemSetup& problem) {
  bool any_kinematic = false;
  for (char k : problem.body_kinematic) any_kinematic = any_kinematic || k;
  if (!any_kinematic) return nullptr;
  return std::make_unique<ElementData>(mesh, problem.body_materials, problem.body_kinematic);
}

PetscErrorCode build_forms(const DistributedMesh& mesh, const ProblemSetup& problem, const ElementData& elements,
                           const ElementData& deformable, const std::vector<double>& node_mass,
                           const GhostExchange& nodal, MemorySpace space, ProblemForms* built) {
  PetscFunctionBeginUser;
  const double h2 = problem.is_static ? 1.0 : problem.dt * problem.dt;
  std::vector<std::unique_ptr<Form>>& forms = built->forms;
  if (has_inertia(problem) && problem.lumped_mass)
    forms.push_back(std::make_unique<LumpedInertiaForm>(node_mass, mesh.num_owned_nodes, mesh.node_offset, space));
  else if (has_inertia(problem))
    forms.push_back(std::make_unique<ConsistentInertiaForm>(elements, space));
  forms.push_back(std::make_unique<ElasticForm>(deformable, h2, space));
  if (has_gravity(problem))
    forms.push_back(std::make_unique<BodyForceForm>(node_mass, mesh.num_owned_nodes, problem.gravity, h2, space));
  // Read for every scene, so that -help lists it whatever the scene holds.
  constexpr const OptionSpec& majorize = dipc_option("-dipc_friction_majorize_reversals");
  PetscBool majorize_reversals = PETSC_TRUE;
  PetscOptionsBegin(mesh.comm, nullptr, "dipc friction", "dipc");
  PetscCall(PetscOptionsBool(majorize.name, majorize.help, majorize.manual, majorize_reversals, &majorize_reversals,
                             nullptr));
  PetscOptionsEnd();
  if (problem.contact)
    PetscCall(add_contact_forms(mesh, problem, node_mass, nodal, space, majorize_reversals == PETSC_TRUE, built));
  PetscFunctionReturn(0);
}

}  // namespace dipc
