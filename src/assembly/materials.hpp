// The hyperelastic materials an element can have, and the one place that maps a per-element
// material id to its material type.
//
// A material type is a stateless struct of DIPC_HD static functions of the deformation
// gradient F (row-major 3x3) and the element's linear-elastic Lame parameters (lambda, mu):
//   energy(F, lambda, mu) -> psi,   stress(F, lambda, mu, P[9]),
//   stress_derivative(F, lambda, mu, dPdF[81])       exact, symmetric,
//   stress_derivative_psd(F, lambda, mu, dPdF[81])   projected to positive semi-definite.
// The hex8 element routines (hex8_elasticity.hpp), the CPU loops (element_loops.cpp) and the
// CUDA kernel (cuda/element_kernels.cu) take it as a template parameter; visit_material
// turns the runtime id into that parameter. Adding a material: its header with the struct, an
// enumerator, a case in visit_material and a name in material_model_name.
#pragma once
#include "assembly/neo_hookean.hpp"
#include "assembly/stable_neo_hookean.hpp"
#include "host_device.hpp"

namespace dipc {

// Per-element material id (scene key materials[].model).
enum class MaterialModel : unsigned char { neo_hookean = 0, stable_neo_hookean = 1 };

// Calls visitor(Material{}) with the material type of `model` and returns its result. Ids come
// from the scene parser's names only; the default branch exists for the compiler.
template <class Visitor>
DIPC_HD auto visit_material(MaterialModel model, Visitor&& visitor) {
  switch (model) {
    case MaterialModel::stable_neo_hookean:
      return visitor(StableNeoHookean{});
    case MaterialModel::neo_hookean:
    default:
      return visitor(NeoHookean{});
  }
}

// The scene file's name of each model ("neo_hookean", "stable_neo_hookean").
inline const char* material_model_name(MaterialModel model) {
  switch (model) {
    case MaterialModel::stable_neo_hookean:
      return "stable_neo_hookean";
    case MaterialModel::neo_hookean:
    default:
      return "neo_hookean";
  }
}

}  // namespace dipc
