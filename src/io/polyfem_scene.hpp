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

// The key path that marks the document as PolyFEM's (dipc's own format would reject it as
// unknown), or "" for dipc's format: a root key `space`, `initial_conditions`, `units`,
// `common`, `root_path`, `tests`, `preset_problem` or `input`; `geometry` or `materials` as one
// object; an entry of either with `transformation`, `volume_selection`, `surface_selection`,
// `is_obstacle`, `type`, `id`, `enabled` or `n_refs`; `time` with `time_steps`, `tend`, `t0` or
// `quasistatic`; `boundary_conditions` with `rhs`, `dirichlet_boundary`, `neumann_boundary`,
// `obstacle_displacements` or `pressure_boundary`; `contact` with `friction_coefficient` or
// `dhat_percentage`.
std::string polyfem_marker(const nlohmann::json& document);
inline bool is_polyfem_scene(const nlohmann::json& document) { return !polyfem_marker(document).empty(); }

// Throws SceneError "<source>: <key path>: <what>" for a key dipc cannot model.
Scene translate_polyfem_scene(const nlohmann::json& document, const std::string& source,
                              const std::string& base_directory);

}  // namespace dipc
