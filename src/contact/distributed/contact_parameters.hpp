// ContactParameters: what the contact forms need to know about a scene's contact settings.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/prescribed_motion.hpp"

namespace dipc {

struct ContactParameters {
  double dhat = 1e-3;  // activation distance (unsquared, length)
  double kappa = 0;    // barrier stiffness; adaptive when kappa_adaptive
  bool kappa_adaptive = true;
  std::vector<char> self_contact;  // per body: may its surface touch itself?
  struct Plane {
    std::array<double, 3> point, normal;  // solid side behind the unit normal
  };
  std::vector<Plane> planes;
  // A triangle-mesh obstacle: vertices placed at t = 0 (rest), then moved by `motion`; its
  // positions are functions of time, not unknowns. Every rank holds the whole obstacle.
  struct Obstacle {
    std::string name;    // for messages
    std::string source;  // the file it was read from
    std::vector<std::array<double, 3>> rest;
    std::vector<std::array<std::int32_t, 3>> triangles;
    // Where each triangle is in the file, for messages: its face's line (OBJ, ASCII STL) or,
    // with binary_origin, its facet index (binary STL); empty when not read from a file.
    std::vector<std::int64_t> triangle_origin;
    bool binary_origin = false;
    PrescribedMotion motion;
  };
  std::vector<Obstacle> obstacles;
  double ccd_fraction = 0.8;            // the Newton step starts at min(1, ccd_fraction · t_CCD)
  bool project_hessian = true;          // PSD-project each pair's Hessian (tests switch it off)
  std::vector<std::string> body_names;  // for messages (body id when absent)
};

}  // namespace dipc
