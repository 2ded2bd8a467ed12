// The scenes embedded in the program (the default contact scene, used when no scene file is
// given, and the beam scene that elastodynamics tests use), as JSON text so that they double
// as examples of the scene format. default_scene() and beam_scene() (scene.hpp) parse them.
#pragma once
#include <string>

namespace dipc {

const std::string& default_scene_json();
const std::string& beam_scene_json();

}  // namespace dipc
