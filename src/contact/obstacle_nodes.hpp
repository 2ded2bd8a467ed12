// Node ids of triangle-mesh obstacle vertices in contact pairs (contact_obstacles.hpp) and the
// body part of a pair's terms, as host/device point functions: ContactForm's CPU loops, the
// friction form and the CUDA contact kernels (cuda/contact_kernels.cu) share them.
//
// A pair names body nodes by ext-local id (>= 0) and obstacle vertex k by −2 − k, so −1 keeps
// meaning "unused slot". Obstacle nodes have no unknowns: only the body nodes' blocks of a
// pair's gradient and Hessian are assembled.
#pragma once
#include <cstdint>

#include "math/host_device.hpp"

namespace dipc {

DIPC_HD bool is_obstacle_node(std::int64_t node) { return node <= -2; }
DIPC_HD std::int32_t obstacle_node(std::int32_t vertex) { return -2 - vertex; }
DIPC_HD std::int32_t obstacle_vertex(std::int64_t node) { return static_cast<std::int32_t>(-2 - node); }

// Body (non-obstacle, non-unused) slots of a pair's nodes; returns how many.
template <class Id>
DIPC_HD int body_slots(const Id* nodes, int count, int* slots) {
  int n = 0;
  for (int k = 0; k < count; ++k)
    if (nodes[k] >= 0) slots[n++] = k;
  return n;
}

// The body nodes' block of a pair Hessian H (3·count square, row-major), in the order
// (slot a, component i, slot b, component j) of the COO patterns.
DIPC_HD void body_block(const double* H, int count, const int* slots, int num_slots, double* out) {
  const int n = 3 * count;
  int r = 0;
  for (int a = 0; a < num_slots; ++a)
    for (int i = 0; i < 3; ++i)
      for (int b = 0; b < num_slots; ++b)
        for (int j = 0; j < 3; ++j) out[r++] = H[(3 * slots[a] + i) * n + 3 * slots[b] + j];
}

}  // namespace dipc
