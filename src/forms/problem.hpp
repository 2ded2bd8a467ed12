// ProblemSetup: the physics of one run on one rank, in the numbering of its
// DistributedMesh. The app builds it from a scene file; tests build it directly.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "contact/distributed/contact_parameters.hpp"
#include "mesh/prescribed_motion.hpp"
#include "physics/hex8_mean_dilatation.hpp"
#include "physics/materials.hpp"

namespace dipc {

struct BodyMaterial {
  double lambda = 0, mu = 0, rho = 0;  // Lamé parameters [Pa] and density [kg/m³]
  VolumetricTerm volumetric = VolumetricTerm::gauss_points;
  MaterialModel model = MaterialModel::neo_hookean;  // mean dilatation: neo_hookean only
};

struct DirichletSet {
  std::vector<std::int32_t> local_nodes;  // local node ids on this rank (owned or ghost)
  PrescribedMotion motion;
};

struct ProblemSetup {
  std::vector<BodyMaterial> body_materials;          // indexed by body id
  std::vector<std::array<double, 3>> body_velocity;  // initial velocity per body id
  // Initial spin per body id: velocity += ω × (X − center) (empty: none).
  std::vector<std::array<double, 3>> body_angular_velocity, body_spin_center;
  std::vector<char> body_kinematic;  // per body id: prescribed entirely (no elastic energy)
  std::array<double, 3> gravity{0, 0, 0};
  std::vector<DirichletSet> dirichlet;  // later sets win where they overlap
  bool is_static = false;               // minimise Ψ(x) − fᵀx once instead of stepping in time
  double dt = 0.01;
  int steps = 1;
  bool lumped_mass = true;
  double length_scale = 1.0;  // bounding-box diagonal, scales default tolerances
  // Contact: built only when enabled (IPC barrier; friction only when friction > 0).
  bool contact = false;
  ContactParameters contact_parameters;
  double friction = 0;          // Coulomb coefficient μ
  double friction_epsv = 1e-3;  // ε_v [m/s]: below this relative sliding speed friction is smoothed
  int friction_iterations = 1;  // lagging iterations per step
};

}  // namespace dipc
