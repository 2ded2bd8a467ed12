// Builds the whole input mesh of a scene on the calling rank alone (tests, tools): every body generated or read from
// its Gmsh file, placed, and appended with its body id. Node sets of a body are prefixed
// with its name ("part.top"); "<name>" selects all of a body's nodes. Throws MeshError for a
// mesh that fails check_mesh, and with contact for a body inside another (nested_bodies.hpp).
#pragma once
#include "io/scene.hpp"
#include "mesh/hex_mesh.hpp"

namespace dipc {

HexMesh build_scene_mesh(const Scene& scene);

}  // namespace dipc
