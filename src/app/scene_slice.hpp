// The input mesh of a scene as per-rank slices (partition/mesh_slice.hpp), so that no rank
// builds the whole mesh: generated boxes are generated row by row where the rows live, dipc
// HDF5 mesh files (io/mesh_file.hpp, "mesh": "x.h5") are read in slices with MPI-IO, and
// Gmsh MSH files are read on rank 0 (the format has to be scanned from the start) and then
// sliced; convert big MSH meshes with dipc-mesh-convert. Bodies are appended in scene order with
// their body ids; a body's node sets are prefixed with its name ("part.top") and "<name>"
// selects all its nodes, as in build_scene_mesh.
#pragma once
#include <mpi.h>

#include "io/scene.hpp"
#include "partition/distributed_mesh.hpp"
#include "partition/mesh_slice.hpp"

namespace dipc {

// Collective. Throws on every rank (MeshError / std::runtime_error) for unreadable files; with
// contact, for a body nested inside another (boxes compared exactly; meshes from files by
// check_no_nested_bodies on the whole mesh gathered on rank 0, see the README's size notes).
MeshSlice build_scene_slice(const Scene& scene, MPI_Comm comm);

// Collective. check_mesh's element rules (finite coordinates, distinct nodes, det J) on every
// rank's part of a mesh read from dipc HDF5 files, whose rows nobody checked before; the
// message names the element by its input id and the file of its body. No-op for scenes
// without such bodies (generated boxes are valid by construction, MSH files are checked by
// their reader).
void check_file_elements(const Scene& scene, const DistributedMesh& mesh);

}  // namespace dipc
