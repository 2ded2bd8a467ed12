// The scene embedded in the program (used when no scene file is given), as JSON text so that
// it doubles as an example of the scene format. default_scene() (scene.hpp) parses it.
#pragma once
#include <string>

namespace dipc {

const std::string& default_scene_json();

}  // namespace dipc
