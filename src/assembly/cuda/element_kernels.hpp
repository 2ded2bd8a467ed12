// CUDA element kernels over an ElementBlock whose pointers are device memory: hyperelastic
// energy, gradient and PSD-projected Hessian of each element's material (materials.hpp; COO
// values in the order of elastic_coo_pattern), volume ratios, and the inertia and body-force
// terms. They call the same point functions as the CPU loops in element_loops.cpp. Plain C++
// interface; every pointer argument named d_* or documented as device memory lives on the
// current device. Scalars come back to the host through the Reducer, nothing else does.
#pragma once
#include <cstddef>

#include "assembly/element_loops.hpp"
#include "device/device_runtime.hpp"

namespace dipc::device {

// scale * (energy, gradient, Hessian) of the elements in one launch; any output
// may be null. energy (host) is overwritten, d_gradient (3 per local node) added into,
// d_hessian (576 per element) written. Returns false if an element is inverted at a Gauss
// point (det F <= 0); the outputs are then partial.
bool elastic_evaluate(const ElementBlock& block, const double* d_x, double scale, double* energy,
                      double* d_gradient, double* d_hessian, Reducer& reducer);

// min over elements of hex8_min_volume_ratio (+huge for an empty block).
double min_volume_ratio(const ElementBlock& block, const double* d_x, Reducer& reducer);

// Σ_k ½ m_k (x_k − x̂_k)² over n dofs with one mass per dof (lumped inertia, owned dofs).
double lumped_inertia_energy(const double* d_mass, const double* d_x_hat, const double* d_x, std::size_t n,
                             Reducer& reducer);
// g_k += m_k (x_k − x̂_k).
void lumped_inertia_gradient(const double* d_mass, const double* d_x_hat, const double* d_x, std::size_t n,
                             double* d_g);

// ½ Σ_e (x − x̂)_eᵀ (M_e ⊗ I₃) (x − x̂)_e with 64 scalar masses M_ab per element (consistent inertia).
double consistent_inertia_energy(const ElementBlock& block, const double* d_element_mass, const double* d_x_hat,
                                 const double* d_x, Reducer& reducer);
void consistent_inertia_gradient(const ElementBlock& block, const double* d_element_mass, const double* d_x_hat,
                                 const double* d_x, double* d_g);

// Σ_k f_k x_k over n dofs.
double dot(const double* d_f, const double* d_x, std::size_t n, Reducer& reducer);

}  // namespace dipc::device
