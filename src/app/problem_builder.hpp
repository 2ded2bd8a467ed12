// Turns a validated Scene into the ProblemSetup of one rank: Lamé parameters per body,
// initial velocities, gravity, and Dirichlet conditions resolved to this rank's local nodes.
#pragma once
#include "forms/problem.hpp"
#include "io/scene.hpp"
#include "partition/distributed_mesh.hpp"

namespace dipc {

// Collective over mesh.comm. Throws SceneError (on every rank alike) for a selection name
// the mesh does not have or a selection that holds no node on any rank.
ProblemSetup build_problem(const Scene& scene, const DistributedMesh& mesh, double length_scale);

// The solver's form of a scene motion (Dirichlet conditions, kinematic bodies, obstacles).
PrescribedMotion prescribed_motion(const Motion& motion);

}  // namespace dipc
