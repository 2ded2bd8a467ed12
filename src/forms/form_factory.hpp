// The forms of one problem: only the terms its scene needs (docs/design.md §1.1: "model only
// what a scene requires"). No inertia in a static solve, no body force when g = 0, no barrier
// without contact, no friction when μ = 0 or in a static solve; kinematic bodies (every node
// prescribed) get no elastic energy. The order is fixed — inertia, elastic, body force, contact
// barrier, friction — since the potential sums the forms in it.
#pragma once
#include <petscsys.h>

#include <memory>
#include <vector>

#include "device/memory_space.hpp"
#include "forms/element_data.hpp"
#include "forms/form.hpp"
#include "forms/problem.hpp"
#include "partition/distributed_mesh.hpp"
#include "partition/ghost_exchange.hpp"

namespace dipc {

class ContactForm;
class FrictionForm;

struct ProblemForms {
  std::vector<std::unique_ptr<Form>> forms;
  ContactForm* contact = nullptr;    // among forms; null without contact
  FrictionForm* friction = nullptr;  // among forms; null without friction
};

// Lumped masses serve inertia, gravity and the contact stiffness's bounds; a static run
// without gravity or contact has none (its momenta and kinetic energy are zero: v = 0).
bool forms_need_node_masses(const ProblemSetup& problem);

// The elements of the bodies that are not kinematic, which the elastic form covers; null when
// no body is kinematic (then it covers all elements).
std::unique_ptr<ElementData> deformable_elements(const DistributedMesh& mesh, const ProblemSetup& problem);

// Collective (with contact). elements: all of this rank's; deformable: those of the elastic form;
// node_mass: complete lumped masses of the local nodes where forms_need_node_masses(); nodal:
// the mesh's halo exchange, which contact's rest areas travel through. The element forms keep
// references to their elements. space: where the forms evaluate.
PetscErrorCode build_forms(const DistributedMesh& mesh, const ProblemSetup& problem, const ElementData& elements,
                           const ElementData& deformable, const std::vector<double>& node_mass,
                           const GhostExchange& nodal, MemorySpace space, ProblemForms* built);

}  // namespace dipc
