// dipc-mesh-convert: a Gmsh MSH file (4.1 or 2.2, ASCII or binary) as dipc's HDF5 mesh file, which
// every rank of a run reads in slices instead of rank 0 reading the whole MSH file.
//
//   dipc-mesh-convert INPUT.msh OUTPUT.h5
//
// The hexahedra, the node coordinates and every physical group (as a node selection) are
// written (tools/mesh_convert.hpp, layout in io/mesh_file.hpp). A scene names the result like
// the MSH file: {"name": "part", "mesh": "OUTPUT.h5"}, selections "part.<group>". Exit status
// 1 with "dipc-mesh-convert: error: ..." for bad arguments or input.
#include <mpi.h>

#include <cstdio>
#include <string>

#include "io/mesh_file.hpp"
#include "tools/mesh_convert.hpp"

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  int status = 0;
  try {
    if (argc != 3)
      throw std::runtime_error("expected 2 arguments, got " + std::to_string(argc - 1) +
                               "\nusage: dipc-mesh-convert INPUT.msh OUTPUT.h5");
    if (!dipc::is_hdf5_mesh_path(argv[2]))
      throw std::runtime_error(std::string("the output '") + argv[2] +
                               "' must end in .h5 or .hdf5 (scenes read "
                               "other names as Gmsh files)");
    dipc::convert_gmsh_to_mesh_file(MPI_COMM_WORLD, argv[1], argv[2]);
  } catch (const std::exception& e) {
    if (rank == 0) std::fprintf(stderr, "dipc-mesh-convert: error: %s\n", e.what());
    status = 1;
  }
  MPI_Finalize();
  return status;
}
