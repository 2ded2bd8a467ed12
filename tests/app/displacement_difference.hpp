// How far two runs of one scene end apart: the largest difference of their final displacements
// against the largest displacement of the reference run, both from the positions gathered on
// rank 0 (RunResult::positions) and the rest positions of a setup-only run.
#pragma once
#include <algorithm>
#include <cmath>

#include "app/simulation.hpp"

namespace dipc {

struct DisplacementDifference {
  double max_difference = 0;    // max |u_other - u_reference|
  double max_displacement = 0;  // max |u_reference|
  double relative() const { return max_difference / max_displacement; }
};

inline DisplacementDifference displacement_difference(const RunResult& reference, const RunResult& other,
                                                      const RunResult& rest) {
  DisplacementDifference d;
  for (std::size_t i = 0; i < reference.positions.size(); ++i) {
    const double ur = reference.positions[i] - rest.positions[i], uo = other.positions[i] - rest.positions[i];
    d.max_difference = std::max(d.max_difference, std::abs(uo - ur));
    d.max_displacement = std::max(d.max_displacement, std::abs(ur));
  }
  return d;
}

}  // namespace dipc
