// The hyperelastic materials an element can have, and the one place that maps a per-element
// material id to its material type.
//
// A material type is a stateless struct of DIPC_HD static functions of the deformation
// gradient F (row-major 3x3) and the element's linear-elastic Lame parameters (lambda, mu):
//   energy(F, lambda, mu) -> psi,   stress(F, lambda, mu, P[9]),
//   stress_derivative(F, lambda, mu, dPdF[81])       exact, symmetric,
//   eigensystem(F, lambda, mu, IsotropicEigensystem*) the analytic eigensystem of dP/dF
//                                                     (isotropic_eigensystem.hpp).
// stress_derivative_psd<Material> below composes the last two into the PSD-projected tangent
// of the Newton Hessian, the same way for every material. The hex8 element routines
// (hex8_elasticity.hpp), the CPU loops (element_loops.cpp) and the CUDA kernel
// (cuda/element_kernels.cu) take the type as a template parameter; visit_material turns the
// runtime id into that parameter. Adding a material: its header with the struct, an
// enumerator, a case in visit_material and a name in material_model_name.
#pragma once
#include "math/host_device.hpp"
#include "physics/isotropic_eigensystem.hpp"
#include "physics/neo_hookean.hpp"
#include "physics/stable_neo_hookean.hpp"

namespace dipc {

// dP/dF projected to positive semi-definite for the Newton Hessian: the exact tangent plus the
// correction that clamps the negative eigenvalues of its analytic eigensystem at 0 (Smith,
// de Goes & Kim 2019; add_psd_correction).
template <class Material>
DIPC_HD void stress_derivative_psd(const double F[9], double lambda, double mu, double dPdF[81]) {
  Material::stress_derivative(F, lambda, mu, dPdF);
  IsotropicEigensystem es;
  Material::eigensystem(F, lambda, mu, &es);
  add_psd_correction(es, dPdF);
}

// Per-element material id (scene key materials[].model).
enum class MaterialModel : unsigned char { neo_hookean = 0, stable_neo_hookean = 1 };

// Calls visitor(Material{}) with the material type of `model` and returns its result. Ids come
// from the scene parser's names only; the default branch exists for the compiler.
template <class Visitor>
DIPC_HD auto visit_material(MaterialModel model, Visitor&& visitor) {
  switch (model) {
    case MaterialModel::stable_neo_hookean: return visitor(StableNeoHookean{});
    case MaterialModel::neo_hookean:
    default: return visitor(NeoHookean{});
  }
}

// The scene file's name of each model ("neo_hookean", "stable_neo_hookean").
inline const char* material_model_name(MaterialModel model) {
  switch (model) {
    case MaterialModel::stable_neo_hookean: return "stable_neo_hookean";
    case MaterialModel::neo_hookean:
    default: return "neo_hookean";
  }
}

}  // namespace dipc
