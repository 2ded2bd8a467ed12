// Axis-aligned bounding boxes: the box type, growing a box by points and by a length, merging
// and the overlap test. Host/device point functions on plain arrays, used by the contact broad
// phase (CPU and device BVHs, contact/broad_phase/aabb.hpp builds primitives' boxes on them),
// the ghost-surface exchange (partition/ghost_surface_exchange.hpp) and the contact form.
#pragma once
#include <cmath>

#include "math/host_device.hpp"

namespace dipc {

struct Aabb {
  double lo[3];
  double hi[3];
};

// The empty box (lo = +inf, hi = -inf): growing it by a point gives that point's box, and it
// overlaps nothing.
DIPC_HD Aabb aabb_empty() { return {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}}; }

DIPC_HD bool aabb_is_empty(const Aabb& b) { return b.lo[0] > b.hi[0]; }

// Closed intervals: boxes that only touch overlap, so a pair at exactly the inflation
// distance is still a candidate (a broad phase may report extra pairs, never miss one).
DIPC_HD bool aabbs_overlap(const Aabb& a, const Aabb& b) {
  return a.lo[0] <= b.hi[0] && b.lo[0] <= a.hi[0] && a.lo[1] <= b.hi[1] && b.lo[1] <= a.hi[1] && a.lo[2] <= b.hi[2] &&
         b.lo[2] <= a.hi[2];
}

DIPC_HD void aabb_merge(Aabb* into, const Aabb& other) {
  for (int k = 0; k < 3; ++k) {
    into->lo[k] = other.lo[k] < into->lo[k] ? other.lo[k] : into->lo[k];
    into->hi[k] = other.hi[k] > into->hi[k] ? other.hi[k] : into->hi[k];
  }
}

// Grows the box to contain the point p (3 coordinates).
DIPC_HD void aabb_add_point(Aabb* into, const double* p) {
  for (int k = 0; k < 3; ++k) {
    into->lo[k] = p[k] < into->lo[k] ? p[k] : into->lo[k];
    into->hi[k] = p[k] > into->hi[k] ? p[k] : into->hi[k];
  }
}

// Moves every side out by r.
DIPC_HD void aabb_inflate(Aabb* box, double r) {
  for (int k = 0; k < 3; ++k) {
    box->lo[k] -= r;
    box->hi[k] += r;
  }
}

}  // namespace dipc
