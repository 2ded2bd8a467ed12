// XdmfWriter: collective output of a distributed hexahedral mesh and its time steps into one
// HDF5 file written by all ranks (MPI-IO, collective hyperslab writes) plus an XDMF file that
// ParaView/VisIt open. HDF5 layout (README, "Output", lists the same):
//   /mesh/coordinates        N x 3 double   reference coordinates
//   /mesh/topology           E x 8 int64    global node ids (Gmsh/XDMF hexahedron order)
//   /mesh/rank, /mesh/body   E int32        owning rank, body id
//   /mesh/body_names         B strings      body id -> the scene's body name
//   /mesh/kinematic          E int32        1 in kinematic bodies (only when the scene has one)
//   /mesh/grids/<g>/rank, body, kinematic   the rows of bodies' grid g (scenes with kinematic
//                            bodies: each kinematic body is a grid, the other bodies runs of
//                            consecutive rows; grid g's name is in the .xmf), for readers that
//                            cannot select rows (ParaView's XDMF 3 reader)
//   /obstacles/<j>           contact obstacles (planes, then triangle meshes), attributes
//                            "name" and "kind" ("plane" | "triangle_mesh"):
//     coordinates  V x 3 double, topology  C x 4 (plane patch) or C x 3 int64,
//     displacement V x 3 zeros when the obstacle does not move
//   /steps/<k>               attribute "time"; with contact also "contact_pairs_<kind>" (int64,
//                            active pairs over all ranks)
//   /steps/<k>/displacement  N x 3 double
//   /steps/<k>/velocity      N x 3 double
//   /steps/<k>/volume_ratio  E double       min det F over the element's quadrature points
//   /steps/<k>/grids/<g>/volume_ratio      its rows of bodies' grid g, as /mesh/grids
//   /steps/<k>/contact_force, friction_force  N x 3 double (contact / friction scenes only)
//   /steps/<k>/obstacles/<j>/displacement     V x 3 double (moving obstacles)
// Rows follow the numbering the caller gives: rank r writes its block of nodes and of elements
// as one contiguous block each (dipc's driver passes blocks of the input mesh's numbering, so
// that a file does not depend on the rank count and a restart on other ranks can continue it).
// Obstacle rows and names are the same on every rank; rank 0 writes them.
#pragma once
#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

#include "io/hdf5_handle.hpp"
#include "io/xdmf_text.hpp"

namespace dipc {

// A contact obstacle, drawn as its own grid: a half-space plane as a finite quad patch, a
// triangle-mesh obstacle as its triangles. Positions at time t are rest + displacement.
struct OutputObstacle {
  std::string name;
  std::string kind;                 // "plane" or "triangle_mesh"
  int nodes_per_cell = 3;           // 3 (triangles) or 4 (quadrilaterals)
  std::vector<double> rest;         // 3 per vertex
  std::vector<std::int64_t> cells;  // nodes_per_cell vertex ids per cell
  bool moving = false;              // a displacement per written step
};

struct OutputMesh {  // this rank's part, partition-ordered global numbering
  MPI_Comm comm = MPI_COMM_NULL;
  std::int64_t num_global_nodes = 0, node_offset = 0;
  int num_owned_nodes = 0;
  const double* owned_coordinates = nullptr;  // 3*num_owned_nodes reference coordinates
  std::int64_t num_global_elements = 0, element_offset = 0;
  int num_elements = 0;
  const std::int64_t* element_nodes = nullptr;  // 8*num_elements global node ids
  const int* element_body = nullptr;            // num_elements
  const int* element_rank = nullptr;            // num_elements owning ranks; null: this rank
  const int* element_kinematic = nullptr;       // num_elements flags; null: no kinematic body
  // The rest is the same on every rank.
  std::vector<std::string> body_names;                 // per body id (none: no /mesh/body_names)
  bool contact_force = false, friction_force = false;  // node fields every step carries
  std::vector<std::string> contact_pair_kinds;         // step attributes "contact_pairs_<kind>"
  std::vector<OutputObstacle> obstacles;
  // Named node selections, written to /mesh/sets/<name> (io/mesh_file.hpp) so that the file can
  // be a later run's mesh: this rank writes rows [offset, offset + count) of `size` ids. The
  // same names in the same order on every rank.
  struct Selection {
    std::string name;
    std::int64_t size = 0, offset = 0, count = 0;
    const std::int64_t* ids = nullptr;
  };
  std::vector<Selection> selections;
};

// What write_step stores; arrays are this rank's owned nodes (3 per node) and elements.
struct StepFields {
  double time = 0;  // equal on all ranks
  const double* displacement = nullptr;
  const double* velocity = nullptr;
  const double* volume_ratio = nullptr;
  const double* contact_force = nullptr;   // when OutputMesh::contact_force
  const double* friction_force = nullptr;  // when OutputMesh::friction_force
  std::vector<long long> contact_pairs;    // one per OutputMesh::contact_pair_kinds
  // Per moving obstacle (in OutputMesh::obstacles' order), 3 per vertex; rank 0's are written.
  std::vector<std::vector<double>> obstacle_displacement;
};

class XdmfWriter {
 public:
  // Collective. Creates `directory` ("" = the working directory; mkdir -p, on rank 0),
  // <directory>/<name>.h5 with the /mesh datasets, and <directory>/<name>.xmf with no time
  // steps yet. Throws std::runtime_error naming the path on every rank if any rank fails,
  // or if the ranks' parts do not tile the global numbering.
  // keep_steps >= 0 continues an existing <name>.h5 instead (a restart): its first keep_steps
  // steps stay, later ones are removed, the mesh datasets must have this mesh's row counts;
  // where no such file exists a new one is created.
  XdmfWriter(const std::string& directory, const std::string& name, const OutputMesh& mesh,
             std::int64_t keep_steps = -1);
  ~XdmfWriter();  // collective: closes the HDF5 file
  XdmfWriter(const XdmfWriter&) = delete;
  XdmfWriter& operator=(const XdmfWriter&) = delete;

  // Collective. Writes /steps/<k> (k = steps written so far), flushes the HDF5 file, then
  // rank 0 writes the .xmf listing all steps to a temporary file and renames it over the old
  // one: a run killed at any moment leaves a .xmf that refers to complete steps only. Throws
  // std::runtime_error on every rank on failure (a field the mesh announced is missing, too).
  void write_step(const StepFields& fields);

  std::string xdmf_path() const;
  std::string h5_path() const;
  std::size_t num_steps_written() const { return step_times_.size(); }

 private:
  void write_xdmf_on_rank0() const;
  void create_file(const OutputMesh& mesh);
  void continue_file(std::int64_t keep_steps);
  std::string write_strings(hid_t parent, const std::string& path, const std::vector<std::string>& texts,
                            const std::string& h5) const;
  std::string write_obstacle(std::size_t j) const;
  struct CellField {
    const char* name;
    hid_t file_type, memory_type;
    const void* data;   // this rank's element block
    std::size_t bytes;  // per row
  };
  void write_grid_cells(hid_t parent, const std::string& parent_path, const std::vector<CellField>& fields) const;

  MPI_Comm comm_;
  int rank_ = 0;
  std::string directory_, name_;
  std::int64_t num_global_nodes_, node_offset_, num_global_elements_, element_offset_;
  int num_owned_nodes_, num_elements_;
  bool kinematic_, contact_force_, friction_force_;
  std::vector<std::string> body_names_, contact_pair_kinds_;
  std::vector<OutputObstacle> obstacles_;
  std::vector<XdmfCellRange> body_grids_;  // empty: one grid of all bodies
  Hdf5Handle file_;
  std::vector<double> step_times_;
};

}  // namespace dipc
