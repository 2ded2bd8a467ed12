// dipc's HDF5 mesh file: the /mesh group that every dipc output file has, so a run's output
// seeds the next run, plus optional named node selections:
//   /mesh/coordinates   float64, N x 3   node coordinates, row = 0-based node id
//   /mesh/topology      int64,   E x 8   node ids of each hexahedron (Gmsh/VTK order, hex_mesh.hpp)
//   /mesh/body          int32,   E       optional; written by dipc's output, not needed as input
//   /mesh/sets/<name>   int64,   n       optional; sorted, unique node ids of a selection
// Every rank reads its own rows with collective MPI-IO (hdf5_rows.hpp), so no rank reads the
// whole mesh. dipc-mesh-convert (src/tools) writes the file from a Gmsh MSH file.
#pragma once
#include <hdf5.h>
#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

#include "io/hdf5_handle.hpp"

namespace dipc {

// Collective over `comm`; every method is collective too (all ranks call it, each with its own
// rows, possibly none). Errors throw std::runtime_error on every rank, naming the file and
// the dataset.
class MeshFileReader {
 public:
  MeshFileReader(MPI_Comm comm, const std::string& path);

  std::int64_t num_nodes() const { return num_nodes_; }
  std::int64_t num_elements() const { return num_elements_; }
  const std::vector<std::string>& set_names() const { return set_names_; }
  std::int64_t set_size(std::size_t set) const { return set_sizes_[set]; }

  // 3 per node for nodes [begin, begin + count).
  std::vector<double> read_coordinates(std::int64_t begin, std::int64_t count) const;
  // 8 per element for elements [begin, begin + count).
  std::vector<std::int64_t> read_topology(std::int64_t begin, std::int64_t count) const;
  // Entries [begin, begin + count) of selection `set` (an index into set_names()).
  std::vector<std::int64_t> read_set(std::size_t set, std::int64_t begin, std::int64_t count) const;

 private:
  MPI_Comm comm_;
  std::string path_;
  Hdf5Handle file_;
  std::int64_t num_nodes_ = 0, num_elements_ = 0;
  std::vector<std::string> set_names_;
  std::vector<std::int64_t> set_sizes_;
};

// What one rank writes: its rows of each dataset (rows [offset, offset + count) of the total).
// Set names must be the same on every rank and must not contain '/'.
struct MeshFileRows {
  std::int64_t num_nodes = 0, node_offset = 0, node_count = 0;
  const double* coordinates = nullptr;  // 3 per row
  std::int64_t num_elements = 0, element_offset = 0, element_count = 0;
  const std::int64_t* topology = nullptr;  // 8 per row
  const std::int32_t* body = nullptr;      // 1 per row
  struct Set {
    std::string name;
    std::int64_t size = 0, offset = 0, count = 0;
    const std::int64_t* ids = nullptr;
  };
  std::vector<Set> sets;
};

// Collective: creates (truncates) `path` and writes the mesh; throws std::runtime_error on
// every rank on failure.
void write_mesh_file(MPI_Comm comm, const std::string& path, const MeshFileRows& rows);

// True for the names dipc reads as its HDF5 mesh file (".h5", ".hdf5"); others are Gmsh MSH.
bool is_hdf5_mesh_path(const std::string& path);

}  // namespace dipc
