// Gmsh MSH -> dipc HDF5 mesh file (io/mesh_file.hpp): the core of dipc-mesh-convert, also used by
// tests. The mesh is read and checked by read_gmsh (mesh/gmsh_reader.hpp); its physical groups
// become /mesh/sets/<name> (a scene selects them as "<body>.<name>", as for the MSH file).
#pragma once
#include <mpi.h>

#include <string>

#include "mesh/hex_mesh.hpp"

namespace dipc {

// Collective over `comm`: rank 0 writes all rows of `mesh` (significant on rank 0 only), the
// other ranks take part in the collective HDF5 calls with none. Throws std::runtime_error on
// every rank on failure.
void write_hex_mesh_file(MPI_Comm comm, const std::string& path, const HexMesh& mesh);

// Collective: read_gmsh(input) on rank 0, then write_hex_mesh_file(output). Throws on every rank.
void convert_gmsh_to_mesh_file(MPI_Comm comm, const std::string& input, const std::string& output);

}  // namespace dipc
