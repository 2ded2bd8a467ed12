// The default scene: a rubber-like cantilever beam, clamped at x = 0, sagging under gravity.
// 24 x 3 x 3 hexahedra (400 nodes) keep 10 implicit steps on 2 ranks within a few seconds.
// tests/io/data/default_scene.json must hold the same JSON (a test checks it).
#include "io/default_scene.hpp"

#include "io/scene.hpp"

namespace dipc {

const std::string& default_scene_json() {
  static const std::string text = R"json({
  "materials": [
    {"name": "rubber", "E": 1e6, "nu": 0.4, "rho": 1000}
  ],
  "geometry": [
    {"name": "beam",
     "box": {"size": [1.0, 0.1, 0.1], "resolution": [24, 3, 3], "origin": [0, 0, 0]},
     "material": "rubber"}
  ],
  "boundary_conditions": {
    "gravity": [0, 0, -9.81],
    "dirichlet": [
      {"selection": "beam.xmin", "type": "fixed"}
    ]
  },
  "time": {"integrator": "implicit_euler", "dt": 0.01, "steps": 50},
  "solver": {"mass": "lumped"},
  "output": {"directory": "output", "name": "dipc", "every": 1}
}
)json";
  return text;
}

Scene default_scene() { return parse_scene_text(default_scene_json(), "<default scene>", ""); }

}  // namespace dipc
