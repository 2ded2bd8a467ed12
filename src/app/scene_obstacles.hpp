// The triangle-mesh obstacles of a scene (contact.obstacles), read and placed for the contact
// form.
#pragma once
#include <mpi.h>

#include <vector>

#include "contact/distributed/contact_parameters.hpp"
#include "io/scene.hpp"

namespace dipc {

// Collective over comm. Rank 0 reads each obstacle's OBJ/STL file (mesh/triangle_surface_reader:
// finite coordinates, no degenerate triangle, open surfaces allowed), places it at
// scale·X + translation and every rank receives the result. A bad file throws SceneError on
// every rank alike, naming the scene key and the reader's file, line (or facet) and face.
std::vector<ContactParameters::Obstacle> load_scene_obstacles(const Scene& scene, MPI_Comm comm);

}  // namespace dipc
