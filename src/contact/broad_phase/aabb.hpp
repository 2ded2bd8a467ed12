// Bounding boxes of surface primitives for the contact broad phase: the box of a vertex, edge or
// triangle at one position or swept between two, inflated by a length (the box type and the
// overlap test are math/aabb.hpp's). Point functions (DIPC_HD, plain arrays) so a CUDA broad
// phase can reuse them.
#pragma once
#include <cstdint>

#include "math/aabb.hpp"
#include "math/host_device.hpp"

namespace dipc::contact {

// Box of the `count` vertices `ids` at positions x0 and, when x1 is not null, also x1,
// grown by `inflation` on every side. The box of both end positions contains the whole
// linear trajectory of every vertex (each coordinate moves monotonically from x0 to x1) and,
// the box being convex, every point of the primitive along the step: what the CCD of the
// IPC line search (Li et al. 2020) needs from its candidates.
DIPC_HD Aabb primitive_box(const double* x0, const double* x1, const std::int32_t* ids, int count, double inflation) {
  Aabb box;
  const double* p = x0 + 3 * static_cast<std::int64_t>(ids[0]);
  for (int k = 0; k < 3; ++k) box.lo[k] = box.hi[k] = p[k];
  for (int pass = 0; pass < 2; ++pass) {
    const double* x = pass == 0 ? x0 : x1;
    if (x == nullptr) continue;
    for (int i = 0; i < count; ++i) {
      const double* q = x + 3 * static_cast<std::int64_t>(ids[i]);
      for (int k = 0; k < 3; ++k) {
        box.lo[k] = q[k] < box.lo[k] ? q[k] : box.lo[k];
        box.hi[k] = q[k] > box.hi[k] ? q[k] : box.hi[k];
      }
    }
  }
  for (int k = 0; k < 3; ++k) {
    box.lo[k] -= inflation;
    box.hi[k] += inflation;
  }
  return box;
}

}  // namespace dipc::contact
