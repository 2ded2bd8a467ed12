// CPU element loops over an ElementBlock (see element_loops.hpp). Each loop gathers one
// element's node coordinates into stack arrays, calls the host/device point function and
// scatters; nothing is allocated inside a loop.
#include "assembly/element_loops.hpp"

#include <limits>
#include <type_traits>

#include "physics/hex8_mass.hpp"
#include "physics/hex8_mean_dilatation.hpp"

namespace dipc {

namespace {

void gather(const double* field, const std::int32_t* element_nodes, double out[24]) {
  for (int a = 0; a < 8; ++a) {
    const double* p = field + 3 * static_cast<std::int64_t>(element_nodes[a]);
    out[3 * a] = p[0];
    out[3 * a + 1] = p[1];
    out[3 * a + 2] = p[2];
  }
}

void scatter_add(const double values[24], const std::int32_t* element_nodes, double* field) {
  for (int a = 0; a < 8; ++a) {
    double* p = field + 3 * static_cast<std::int64_t>(element_nodes[a]);
    p[0] += values[3 * a];
    p[1] += values[3 * a + 1];
    p[2] += values[3 * a + 2];
  }
}

// The row-major 24x24 element Hessian H into the element's COO values (elastic_coo_offset).
void scatter_hessian(const double H[576], double* coo) {
  for (int a = 0; a < 8; ++a)
    for (int k = 0; k < 3; ++k)
      for (int b = 0; b < 8; ++b)
        for (int l = 0; l < 3; ++l) coo[elastic_coo_offset(a, k, b, l)] = H[24 * (3 * a + k) + 3 * b + l];
}

// Element e's energy, gradient and PSD Hessian (any may be nullptr) with its own volumetric
// term and material (hex8_elastic). AnyModel false: the block is all neo-Hookean
// (block.model null) and the element routine is fixed at compile time.
template <bool AnyModel>
bool element_terms(const ElementBlock& block, int e, const double Xe[24], const double xe[24], double* energy,
                   double* gradient, double* hessian) {
  if constexpr (AnyModel)
    return hex8_elastic(block.volumetric_term(e), block.model[e], Xe, xe, block.lambda[e], block.mu[e], energy,
                        gradient, hessian);
  else
    return hex8_elastic<NeoHookean>(block.volumetric_term(e), Xe, xe, block.lambda[e], block.mu[e], energy, gradient,
                                    hessian);
}

// Runs loop(std::bool_constant<AnyModel>) with AnyModel true when the block has a per-element
// material (block.model): a loop over an all-neo-Hookean block has no per-element dispatch, so
// its code is what it was before there were materials (a per-element switch made GCC stop
// inlining hex8_quadrature_point into some loops).
template <class Loop>
bool dispatch_models(const ElementBlock& block, Loop&& loop) {
  return block.model ? loop(std::true_type{}) : loop(std::false_type{});
}

// Global dof ids 3*l2g[node] + c of one element, checked against PETSc's 32-bit PetscInt.
void element_dofs(const ElementBlock& block, int e, const std::int64_t* local_to_global, std::int32_t dofs[24]) {
  const std::int32_t* en = block.nodes + 8 * static_cast<std::int64_t>(e);
  for (int a = 0; a < 8; ++a) {
    const std::int64_t global_node = local_to_global[en[a]];
    const std::int64_t first = 3 * global_node;
    if (global_node < 0 || first + 2 > std::numeric_limits<std::int32_t>::max())
      throw DofIndexOverflow("element_loops: element " + std::to_string(e) + " local node " + std::to_string(en[a]) +
                             " has global id " + std::to_string(global_node) + " whose dofs do not fit a 32-bit index");
    for (int c = 0; c < 3; ++c) dofs[3 * a + c] = static_cast<std::int32_t>(first + c);
  }
}

}  // namespace

bool elastic_energy(const ElementBlock& block, const double* x, double* energy) {
  return dispatch_models(block, [&](auto any_model) {
    double total = 0;
    for (int e = 0; e < block.num_elements; ++e) {
      const std::int32_t* en = block.nodes + 8 * static_cast<std::int64_t>(e);
      double Xe[24], xe[24], ee;
      gather(block.reference, en, Xe);
      gather(x, en, xe);
      if (!element_terms<decltype(any_model)::value>(block, e, Xe, xe, &ee, nullptr, nullptr)) return false;
      total += ee;
    }
    *energy = total;
    return true;
  });
}

bool elastic_gradient(const ElementBlock& block, const double* x, double* g) {
  return dispatch_models(block, [&](auto any_model) {
    for (int e = 0; e < block.num_elements; ++e) {
      const std::int32_t* en = block.nodes + 8 * static_cast<std::int64_t>(e);
      double Xe[24], xe[24], ge[24];
      gather(block.reference, en, Xe);
      gather(x, en, xe);
      if (!element_terms<decltype(any_model)::value>(block, e, Xe, xe, nullptr, ge, nullptr)) return false;
      scatter_add(ge, en, g);
    }
    return true;
  });
}

bool elastic_hessian(const ElementBlock& block, const double* x, double* coo_values) {
  return dispatch_models(block, [&](auto any_model) {
    for (int e = 0; e < block.num_elements; ++e) {
      const std::int32_t* en = block.nodes + 8 * static_cast<std::int64_t>(e);
      double Xe[24], xe[24];
      gather(block.reference, en, Xe);
      gather(x, en, xe);
      double He[576];
      if (!element_terms<decltype(any_model)::value>(block, e, Xe, xe, nullptr, nullptr, He)) return false;
      scatter_hessian(He, coo_values + kElasticCooPerElement * static_cast<std::int64_t>(e));
    }
    return true;
  });
}

bool elastic_energy_gradient_hessian(const ElementBlock& block, const double* x, double* energy, double* g,
                                     double* coo_values) {
  return dispatch_models(block, [&](auto any_model) {
    double total = 0;
    for (int e = 0; e < block.num_elements; ++e) {
      const std::int32_t* en = block.nodes + 8 * static_cast<std::int64_t>(e);
      double Xe[24], xe[24], ge[24], ee, He[576];
      gather(block.reference, en, Xe);
      gather(x, en, xe);
      if (!element_terms<decltype(any_model)::value>(block, e, Xe, xe, &ee, ge, He)) return false;
      scatter_hessian(He, coo_values + kElasticCooPerElement * static_cast<std::int64_t>(e));
      total += ee;
      scatter_add(ge, en, g);
    }
    *energy = total;
    return true;
  });
}

bool elastic_hessian_split(const ElementBlock& block, const double* x, double* coo_values, double* volume_gradients,
                           double* volume_curvatures) {
  return dispatch_models(block, [&](auto any_model) {
    for (int e = 0; e < block.num_elements; ++e) {
      const std::int32_t* en = block.nodes + 8 * static_cast<std::int64_t>(e);
      double Xe[24], xe[24], He[576];
      gather(block.reference, en, Xe);
      gather(x, en, xe);
      double* b = volume_gradients + 24 * static_cast<std::int64_t>(e);
      bool ok;
      if (block.volumetric_term(e) == VolumetricTerm::mean_dilatation) {
        ok = detail::hex8_mean_dilatation<true>(Xe, xe, block.lambda[e], block.mu[e], nullptr, nullptr, He, b,
                                                &volume_curvatures[e]);
      } else {
        ok = element_terms<decltype(any_model)::value>(block, e, Xe, xe, nullptr, nullptr, He);
        for (int k = 0; k < 24; ++k) b[k] = 0;
        volume_curvatures[e] = 0;
      }
      if (!ok) return false;
      scatter_hessian(He, coo_values + kElasticCooPerElement * static_cast<std::int64_t>(e));
    }
    return true;
  });
}

void reference_volumes(const ElementBlock& block, double* volumes) {
  for (int e = 0; e < block.num_elements; ++e) {
    double Xe[24], G[24], F[9], V = 0;
    gather(block.reference, block.nodes + 8 * static_cast<std::int64_t>(e), Xe);
    for (int q = 0; q < hex8::kQuadraturePoints; ++q) V += hex8_quadrature_point(Xe, Xe, q, G, F);
    volumes[e] = V;
  }
}

void elastic_coo_pattern(const ElementBlock& block, const std::int64_t* local_to_global,
                         std::vector<std::int32_t>* rows, std::vector<std::int32_t>* cols) {
  const std::size_t n = static_cast<std::size_t>(kElasticCooPerElement) * block.num_elements;
  rows->resize(n);
  cols->resize(n);
  for (int e = 0; e < block.num_elements; ++e) {
    std::int32_t dofs[24];
    element_dofs(block, e, local_to_global, dofs);
    std::int32_t* r = rows->data() + kElasticCooPerElement * static_cast<std::size_t>(e);
    std::int32_t* c = cols->data() + kElasticCooPerElement * static_cast<std::size_t>(e);
    for (int a = 0; a < 8; ++a)
      for (int k = 0; k < 3; ++k)
        for (int b = 0; b < 8; ++b)
          for (int l = 0; l < 3; ++l) {
            const int o = elastic_coo_offset(a, k, b, l);
            r[o] = dofs[3 * a + k];
            c[o] = dofs[3 * b + l];
          }
  }
}

double min_volume_ratio(const ElementBlock& block, const double* x, double* per_element) {
  double m = std::numeric_limits<double>::max();
  for (int e = 0; e < block.num_elements; ++e) {
    const std::int32_t* en = block.nodes + 8 * static_cast<std::int64_t>(e);
    double Xe[24], xe[24];
    gather(block.reference, en, Xe);
    gather(x, en, xe);
    const double r = hex8_min_volume_ratio(Xe, xe);
    if (per_element) per_element[e] = r;
    m = r < m ? r : m;
  }
  return m;
}

void lumped_mass(const ElementBlock& block, const double* rho, double* node_mass) {
  for (int e = 0; e < block.num_elements; ++e) {
    const std::int32_t* en = block.nodes + 8 * static_cast<std::int64_t>(e);
    double Xe[24], me[8];
    gather(block.reference, en, Xe);
    hex8_lumped_mass(Xe, rho[e], me);
    for (int a = 0; a < 8; ++a) node_mass[en[a]] += me[a];
  }
}

void consistent_mass_values(const ElementBlock& block, const double* rho, double* coo_values) {
  for (int e = 0; e < block.num_elements; ++e) {
    const std::int32_t* en = block.nodes + 8 * static_cast<std::int64_t>(e);
    double Xe[24], Me[64];
    gather(block.reference, en, Xe);
    hex8_consistent_mass(Xe, rho[e], Me);
    double* v = coo_values + kMassCooPerElement * static_cast<std::int64_t>(e);
    for (int ab = 0; ab < 64; ++ab)
      for (int c = 0; c < 3; ++c) v[3 * ab + c] = Me[ab];
  }
}

void consistent_mass_coo_pattern(const ElementBlock& block, const std::int64_t* local_to_global,
                                 std::vector<std::int32_t>* rows, std::vector<std::int32_t>* cols) {
  const std::size_t n = static_cast<std::size_t>(kMassCooPerElement) * block.num_elements;
  rows->resize(n);
  cols->resize(n);
  for (int e = 0; e < block.num_elements; ++e) {
    std::int32_t dofs[24];
    element_dofs(block, e, local_to_global, dofs);
    std::int32_t* r = rows->data() + kMassCooPerElement * static_cast<std::size_t>(e);
    std::int32_t* c = cols->data() + kMassCooPerElement * static_cast<std::size_t>(e);
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b)
        for (int k = 0; k < 3; ++k) {
          r[3 * (8 * a + b) + k] = dofs[3 * a + k];
          c[3 * (8 * a + b) + k] = dofs[3 * b + k];
        }
  }
}

}  // namespace dipc
