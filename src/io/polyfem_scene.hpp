// Scenes in PolyFEM's JSON format (https://polyfem.github.io/json_spec/, json-specs/
// input-spec.json in the PolyFEM repository), translated into dipc's Scene for what dipc models:
// hexahedral MSH meshes placed by `transformation`, NeoHookean materials chosen by volume id,
// `initial_conditions.velocity`, the body force `rhs`, Dirichlet conditions on surface
// selections, OBJ/STL and plane obstacles with their displacements, `ImplicitEuler` (or
// quasistatic) time, and IPC contact. A key that changes only how PolyFEM solves (linear and
// nonlinear solver, output, CCD settings) is ignored and named in Scene::notes; a key whose
// meaning dipc cannot reproduce is refused with a SceneError naming its key path.
#pragma once
#include <nlohmann/json.hpp>

#include <string>

#include "io/scene.hpp"

namespace dipc {

// True when the document uses keys only PolyFEM's format has (dipc's own format would reject
// them as unknown): `materials` entries with a `type`, `geometry` entries with `transformation`,
// `volume_selection`, `surface_selection` or `is_obstacle`, `time` with `time_steps` or `tend`,
// `boundary_conditions` with `rhs` or `dirichlet_boundary`, `contact.friction_coefficient`, or
// the root keys `space`, `initial_conditions`, `units`, `common`.
bool is_polyfem_scene(const nlohmann::json& document);

// Throws SceneError "<source>: <key path>: <what>" for a key dipc cannot model.
Scene translate_polyfem_scene(const nlohmann::json& document, const std::string& source,
                              const std::string& base_directory);

}  // namespace dipc
