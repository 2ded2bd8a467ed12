// The scenes embedded in the program, as JSON text so that they double as examples of the
// scene format:
// - the default scene (used when no scene file is given): a soft 0.2 m cube (6 x 6 x 6 hexes)
//   dropped from 0.05 m onto a wider box (0.4 x 0.4 x 0.1, 8 x 8 x 2 hexes) that rests on the
//   ground plane z = 0, with IPC contact and friction μ = 0.2; 40 steps of 0.01 s cover the
//   fall (about 0.1 s), the impact and the settling. The lower box starts 1 mm above the
//   plane because IPC needs a strictly positive initial distance (the barrier is infinite at
//   0); that gap is larger than d̂ (1e-3 × the 0.67 m diagonal), so no contact is active at
//   t = 0. The cube is 13 mm / 7 mm off the base's centre so that no vertex lands exactly on
//   a vertex: that symmetric landing has two mirror-image solutions and round-off would pick
//   one. tests/io/data/default_scene.json holds the same JSON (a test checks it);
// - the beam scene (the default before contact): a rubber cantilever clamped at x = 0 sagging
//   under gravity, 24 x 3 x 3 hexes; tests/io/data/beam_scene.json and
//   scenes/default_beam.json hold the same JSON.
#include "io/default_scene.hpp"

#include "io/scene.hpp"

namespace dipc {

const std::string& default_scene_json() {
  static const std::string text = R"json({
  "materials": [
    {"name": "soft", "E": 1e5, "nu": 0.4, "rho": 1000}
  ],
  "geometry": [
    {"name": "base",
     "box": {"size": [0.4, 0.4, 0.1], "resolution": [8, 8, 2], "origin": [-0.2, -0.2, 0.001]},
     "material": "soft"},
    {"name": "cube",
     "box": {"size": [0.2, 0.2, 0.2], "resolution": [6, 6, 6], "origin": [-0.087, -0.093, 0.151]},
     "material": "soft"}
  ],
  "boundary_conditions": {
    "gravity": [0, 0, -9.81]
  },
  "time": {"integrator": "implicit_euler", "dt": 0.01, "steps": 40},
  "solver": {"mass": "lumped"},
  "output": {"directory": "output", "name": "dipc", "every": 1},
  "contact": {
    "enabled": true,
    "dhat": 1e-3, "dhat_relative": true,
    "barrier_stiffness": "adaptive",
    "friction": 0.2, "epsv": 1e-3, "friction_iterations": 1,
    "planes": [
      {"point": [0, 0, 0], "normal": [0, 0, 1]}
    ]
  }
}
)json";
  return text;
}

const std::string& beam_scene_json() {
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

Scene beam_scene() { return parse_scene_text(beam_scene_json(), "<beam scene>", ""); }

}  // namespace dipc
