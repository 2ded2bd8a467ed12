// A small contact-rich scene for the app tests: two rubber blocks (0.2 x 0.2 x 0.1 m, n x n x n/2
// hexes) falling at 0.5 m/s, the upper offset sideways, onto each other and the plane z = 0, with
// friction; they touch within the first steps and their active set keeps changing.
#pragma once
#include <string>

#include "io/scene.hpp"

namespace dipc {

inline Scene colliding_blocks_scene(int n, int steps) {
  const std::string resolution =
      "[" + std::to_string(n) + ", " + std::to_string(n) + ", " + std::to_string(n / 2) + "]";
  const std::string text =
      R"({"materials": [{"name": "rubber", "E": 1e6, "nu": 0.4, "rho": 1000}],
          "geometry": [{"name": "lower", "box": {"size": [0.2, 0.2, 0.1], "resolution": )" +
      resolution + R"(, "origin": [0, 0, 0.0005]},
                        "material": "rubber", "initial_velocity": [0, 0, -0.5]},
                       {"name": "upper", "box": {"size": [0.2, 0.2, 0.1], "resolution": )" +
      resolution + R"(, "origin": [0.03, 0.02, 0.1012]},
                        "material": "rubber", "initial_velocity": [0, 0, -0.5]}],
          "boundary_conditions": {"gravity": [0, 0, -9.81]},
          "contact": {"enabled": true, "dhat": 1e-3, "friction": 0.3, "epsv": 1e-3,
                      "planes": [{"point": [0, 0, 0], "normal": [0, 0, 1]}]},
          "time": {"dt": 0.002, "steps": )" +
      std::to_string(steps) + "}}";
  return parse_scene_text(text, "colliding_blocks.json", ".");
}

}  // namespace dipc
