// Default parameters of the additive CCD narrow phase (additive_ccd.hpp). Plain constants so
// that host code and CUDA kernels share them.
#pragma once

namespace dipc::contact::ccd_defaults {

// Fraction s of the certified collision-free step taken per iteration; the iteration also
// stops once the gap d - xi has shrunk below (1 - s) of its initial value (Li, Kaufman and
// Jiang 2021, "Codimensional Incremental Potential Contact", sec. 5, Algorithm 1; IPC
// Toolkit uses the same 0.9). Larger s means fewer iterations but a smaller guaranteed
// gap at the returned time.
constexpr double conservative_rescaling = 0.9;

// Iteration guard. Each iteration that does not stop advances t by at least
// s (1 - s) (d0 - xi) / l_p, so the guard only truncates a pair whose relative motion over
// the step, l_p t_max, exceeds max_iterations * s * (1 - s) = 9000 initial gaps (sliding or
// grazing far longer than the gap), and even then it returns the conservative time reached.
// The worst case costs about 100000 distance evaluations (~5 ms on one CPU core).
constexpr int max_iterations = 100000;

// Resolution limit. Coordinates carry a rounding error of about one ulp of the largest
// coordinate magnitude L, and the distances computed from them a few more; a gap d - xi
// below resolution_ulps * DBL_EPSILON * L cannot be told from contact, so the CCD treats it
// as contact (t* = 0 at the start, stop during the iteration). 64 ulps leaves a margin over
// the few ulps of error the distance evaluations add (ccd_distances.hpp).
constexpr double resolution_ulps = 64.0;

constexpr double machine_epsilon = 2.220446049250313e-16;  // DBL_EPSILON, usable on device

}  // namespace dipc::contact::ccd_defaults
