// Axis-aligned bounding boxes for the contact broad phase: the box of a surface primitive
// (vertex, edge, triangle) at one position or swept between two, inflated by a length, and
// the overlap test. Point functions (DIPC_HD, plain arrays) so a CUDA broad phase can reuse them.
#pragma once
#include <cstdint>

#include "host_device.hpp"

namespace dipc::contact {

struct Aabb {
  double lo[3];
  double hi[3];
};

// Closed intervals: boxes that only touch overlap, so a pair at exactly the inflation
// distance is still a candidate (a broad phase may report extra pairs, never miss one).
DIPC_HD bool aabbs_overlap(const Aabb& a, const Aabb& b) {
  return a.lo[0] <= b.hi[0] && b.lo[0] <= a.hi[0] &&
         a.lo[1] <= b.hi[1] && b.lo[1] <= a.hi[1] &&
         a.lo[2] <= b.hi[2] && b.lo[2] <= a.hi[2];
}

DIPC_HD void aabb_merge(Aabb* into, const Aabb& other) {
  for (int k = 0; k < 3; ++k) {
    into->lo[k] = other.lo[k] < into->lo[k] ? other.lo[k] : into->lo[k];
    into->hi[k] = other.hi[k] > into->hi[k] ? other.hi[k] : into->hi[k];
  }
}

// Box of the `count` vertices `ids` at positions x0 and, when x1 is not null, also x1,
// grown by `inflation` on every side. The box of both end positions contains the whole
// linear trajectory of every vertex (each coordinate moves monotonically from x0 to x1) and,
// the box being convex, every point of the primitive along the step: what the CCD of the
// IPC line search (Li et al. 2020) needs from its candidates.
DIPC_HD Aabb primitive_box(const double* x0, const double* x1, const std::int32_t* ids,
                           int count, double inflation) {
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
