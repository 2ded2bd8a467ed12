#include "app/scene_mesh.hpp"

#include "app/scene_slice.hpp"
#include "mesh/mesh_checks.hpp"
#include "partition/mesh_slice.hpp"

namespace dipc {

// The slices of build_scene_slice on a one-rank communicator are the whole mesh: one code path
// builds both.
HexMesh build_scene_mesh(const Scene& scene) {
  HexMesh all = gather_whole_mesh(build_scene_slice(scene, MPI_COMM_SELF));
  check_mesh(all, scene.source);
  return all;
}

}  // namespace dipc
