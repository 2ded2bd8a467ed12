// write_hex_mesh_file and convert_gmsh_to_mesh_file (see mesh_convert.hpp).
#include "tools/mesh_convert.hpp"

#include <vector>

#include "io/collective_error.hpp"
#include "io/mesh_file.hpp"
#include "mesh/gmsh_reader.hpp"

namespace dipc {

void write_hex_mesh_file(MPI_Comm comm, const std::string& path, const HexMesh& mesh) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const bool root = rank == 0;
  // Totals and set names are known on rank 0 only: broadcast them so every rank describes the
  // same datasets.
  std::int64_t totals[2] = {std::int64_t(mesh.num_nodes()), std::int64_t(mesh.num_elements())};
  MPI_Bcast(totals, 2, MPI_INT64_T, 0, comm);
  std::string names;
  std::vector<std::int64_t> sizes;
  if (root)
    for (const auto& [name, ids] : mesh.node_sets) names += name + '\0', sizes.push_back(std::int64_t(ids.size()));
  int length = static_cast<int>(names.size()), count = static_cast<int>(sizes.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, comm);
  MPI_Bcast(&count, 1, MPI_INT, 0, comm);
  names.resize(static_cast<std::size_t>(length));
  sizes.resize(static_cast<std::size_t>(count));
  MPI_Bcast(names.data(), length, MPI_CHAR, 0, comm);
  MPI_Bcast(sizes.data(), count, MPI_INT64_T, 0, comm);

  std::vector<double> x;
  std::vector<std::int64_t> topology;
  std::vector<std::int32_t> body;
  if (root) {
    for (const Vec3& p : mesh.nodes) x.insert(x.end(), p.begin(), p.end());
    for (const Hex& h : mesh.hexes) topology.insert(topology.end(), h.begin(), h.end());
    body.assign(mesh.body.begin(), mesh.body.end());
  }
  MeshFileRows rows;
  rows.num_nodes = totals[0];
  rows.node_count = root ? totals[0] : 0;
  rows.coordinates = x.data();
  rows.num_elements = totals[1];
  rows.element_count = root ? totals[1] : 0;
  rows.topology = topology.data();
  rows.body = body.data();
  auto set = mesh.node_sets.begin();
  for (std::size_t begin = 0, s = 0; begin < names.size(); ++s) {
    const std::size_t end = names.find('\0', begin);
    MeshFileRows::Set entry;
    entry.name = names.substr(begin, end - begin);
    entry.size = sizes[s];
    entry.count = root ? sizes[s] : 0;
    if (root) entry.ids = (set++)->second.data();
    rows.sets.push_back(entry);
    begin = end + 1;
  }
  write_mesh_file(comm, path, rows);
}

void convert_gmsh_to_mesh_file(MPI_Comm comm, const std::string& input, const std::string& output) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  HexMesh mesh;
  std::string error;
  if (rank == 0) try {
      mesh = read_gmsh(input, 0);
    } catch (const std::exception& e) {
      error = e.what();
    }
  throw_if_failed_anywhere(comm, error);
  write_hex_mesh_file(comm, output, mesh);
}

}  // namespace dipc
