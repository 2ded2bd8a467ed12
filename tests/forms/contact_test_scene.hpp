// The two-body contact scene the ContactForm tests share (contact_form_test.cpp on the CPU,
// contact_form_gpu_test.cpp host against device): a 3×3×1 slab above the ground plane and a
// 2×2×2 box above the slab, offset so vertices, edges and faces all face each other
// (point–triangle and edge–edge pairs, not only aligned vertices).
#pragma once
#include "contact/distributed/contact_parameters.hpp"
#include "mesh/box_generator.hpp"

namespace dipc {

// The box's lowest face at height box_z (the slab's top is at 0.26).
inline HexMesh slab_and_box(double box_z) {
  HexMesh whole = generate_box({1, 1, 0.25}, {3, 3, 1}, {0, 0, 0.01}, 0, "slab");
  whole.append(generate_box({0.5, 0.5, 0.5}, {2, 2, 2}, {0.21, 0.17, box_z}, 1, "box"));
  return whole;
}

// d̂ = 0.02, fixed κ = 1, self-contact on for both bodies, the ground plane z = 0.
inline ContactParameters slab_and_box_parameters() {
  ContactParameters params;
  params.dhat = 0.02;
  params.kappa = 1.0;
  params.kappa_adaptive = false;
  params.self_contact = {1, 1};
  params.planes.push_back({{0, 0, 0}, {0, 0, 1}});
  return params;
}

}  // namespace dipc
