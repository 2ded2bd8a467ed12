// The two-box impact of the step-recovery and checkpoint tests: a 0.2 m rubber box thrown down
// at `speed` m/s onto a 0.3 × 0.3 × 0.15 m box resting above the ground plane z = 0, 4 implicit
// Euler steps of 5 ms, adaptive barrier stiffness, d̂ relative 1e-3; `friction` > 0 adds lagged
// friction (eps_v 1e-3). Output "impact" every step in `output_directory`.
#pragma once
#include <cstdio>
#include <string>

namespace dipc::test {

inline std::string impact_scene(double speed, double friction, const std::string& output_directory) {
  char friction_keys[64] = "";
  if (friction > 0) std::snprintf(friction_keys, sizeof friction_keys, "\"friction\": %g, \"epsv\": 1e-3, ", friction);
  char text[2048];
  std::snprintf(text, sizeof text, R"({
  "materials": [{"name": "rubber", "E": 1e6, "nu": 0.4, "rho": 1000}],
  "geometry": [
    {"name": "lower", "box": {"size": [0.3, 0.3, 0.15], "resolution": [3, 3, 2], "origin": [-0.15, -0.15, 0.05]},
     "material": "rubber"},
    {"name": "upper", "box": {"size": [0.2, 0.2, 0.2], "resolution": [3, 3, 3], "origin": [-0.04, -0.07, 0.3]},
     "material": "rubber", "initial_velocity": [0, 0, %.17g]}
  ],
  "boundary_conditions": {"gravity": [0, 0, -9.81]},
  "time": {"integrator": "implicit_euler", "dt": 0.005, "steps": 4},
  "output": {"directory": "%s", "name": "impact", "every": 1},
  "contact": {"enabled": true, "dhat": 1e-3, "dhat_relative": true, "barrier_stiffness": "adaptive", %s
              "planes": [{"point": [0, 0, 0], "normal": [0, 0, 1]}]}
})",
                -speed, output_directory.c_str(), friction_keys);
  return text;
}

}  // namespace dipc::test
