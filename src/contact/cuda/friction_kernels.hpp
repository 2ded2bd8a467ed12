// Lagged friction on the CUDA device: the friction pairs of a lag iteration in device memory and
// the passes over them — energy, gradient, Hessian values in COO order, and the slip-reversal
// test of a segment — each calling the point functions of contact/friction/friction_potential.hpp
// that FrictionForm's CPU loops call (forms/friction_form.hpp).
//
// Plain C++: host code includes this header. The passes live in friction_kernels.cu, or, in
// builds without CUDA, in friction_kernels_host.cpp, where they throw dipc::device::DeviceError.
// x, p, g and the Hessian values are device arrays (3 values per ext-local node, as the contact
// form numbers them); obstacle vertices (node −2 − k, obstacle_nodes.hpp) are read from
// `obstacle_end`, the obstacles' positions at the end of the segment (DeviceContactObstacles).
#pragma once
#include <cstddef>
#include <cstdint>

#include "contact/friction/lagged_friction.hpp"
#include "device/device_runtime.hpp"

namespace dipc::device {

// Pair i: count[i] nodes (4: point–triangle or edge–edge, `pair[i]`; 1: point–plane,
// `plane[i]`), their ext-local ids slot-major (node k at nodes[k·n + i], −1 where the rank does
// not know the node), their 12 start-of-step coordinates at x_start[12 i..], the first of its
// Hessian values at hessian_offset[i] (the body nodes' block, (3 b)² values), and reversing[i]
// = 1 where its next Hessian is the majorizer's.
struct DeviceFrictionPairs {
  Array<std::int32_t> count{"friction pair node counts"};
  Array<std::int32_t> nodes{"friction pair nodes"};
  Array<double> x_start{"friction pair start positions"};
  Array<contact::LaggedPairFriction> pair{"friction pairs"};
  Array<contact::LaggedPointPlaneFriction> plane{"friction plane pairs"};
  Array<std::size_t> hessian_offset{"friction Hessian offsets"};
  Array<std::int32_t> reversing{"friction reversal flags"};
  Array<double> scratch{"friction pair energies"};  // one per pair
  std::size_t size = 0;
};

// Σ_i D_i(x). Returns false (energy unset) if a pair has a node the rank does not know.
bool friction_energy(DeviceFrictionPairs& pairs, const double* obstacle_end, const double* x, Reducer& reducer,
                     double* energy);
// Adds ∇D(x) into g (atomics; body nodes only). Returns false as friction_energy.
bool add_friction_gradient(const DeviceFrictionPairs& pairs, const double* obstacle_end, const double* x, double* g,
                           Reducer& reducer);
// Writes every pair's Hessian (its body nodes' block; the majorizer's where reversing[i]) at
// values + hessian_offset[i]. Returns false as friction_energy.
bool friction_hessian_values(const DeviceFrictionPairs& pairs, const double* obstacle_end, const double* x,
                             double* values, Reducer& reducer);
// reversing[i] = 1 where the segment x -> x + p reverses pair i's slip (obstacles stand still
// along a segment), else 0; eps_u the smoothing displacement.
void mark_friction_reversals(DeviceFrictionPairs& pairs, const double* obstacle_end, const double* x, const double* p,
                             double eps_u);

}  // namespace dipc::device
