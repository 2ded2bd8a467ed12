// XDMF 3 text for dipc's output: a temporal collection with one entry per written step, all
// heavy data in the companion HDF5 file (layout in xdmf_writer.hpp). Without obstacles a step
// is one uniform hexahedral grid ("bodies"); with obstacles it is a spatial collection of that
// grid and one grid per obstacle (named by the obstacle), which ParaView shows as blocks.
// Kept apart from the writer so the text can be checked without MPI or HDF5.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace dipc {

struct XdmfObstacle {
  std::string name;
  int nodes_per_cell = 3;  // 3 Triangle, 4 Quadrilateral
  std::int64_t num_vertices = 0, num_cells = 0;
  bool moving = false;     // displacement per step (else /obstacles/<j>/displacement)
};

struct XdmfLayout {
  std::string h5_file_name;  // relative to the .xmf (same directory), e.g. "dipc.h5"
  std::int64_t num_nodes = 0;
  std::int64_t num_elements = 0;
  bool kinematic = false;                         // /mesh/kinematic exists
  bool contact_force = false, friction_force = false;
  std::vector<std::string> body_names;            // listed in an Information element
  std::vector<XdmfObstacle> obstacles;            // /obstacles/<j>, j in this order
};

// Step k of `step_times` refers to the HDF5 group /steps/k.
std::string xdmf_document(const XdmfLayout& layout, const std::vector<double>& step_times);

}  // namespace dipc
