// XDMF 3 text for dipc's output: a temporal collection with one entry per written step, all
// heavy data in the companion HDF5 file (layout in xdmf_writer.hpp). Without obstacles and
// kinematic bodies a step is one uniform hexahedral grid ("bodies"); otherwise it is a spatial
// collection, which ParaView shows as named blocks: the bodies' grids (see XdmfLayout::
// body_grids) and one grid per obstacle (named by the obstacle).
// Kept apart from the writer so the text can be checked without MPI or HDF5.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace dipc {

// text with the five XML special characters as entities, for attribute values and content
// (also the VTK files of dipc-surface).
std::string xml_escaped(const std::string& text);

struct XdmfObstacle {
  std::string name;
  int nodes_per_cell = 3;  // 3 Triangle, 4 Quadrilateral
  std::int64_t num_vertices = 0, num_cells = 0;
  bool moving = false;  // displacement per step (else /obstacles/<j>/displacement)
};

// A grid over rows [first, first + count) of the /mesh cell datasets: its cells a HyperSlab of
// /mesh/topology, its cell fields the rows stored for it under grids/<index>/ (xdmf_writer.hpp),
// its geometry and node fields the whole mesh's (nodes no cell of the grid uses are not drawn).
struct XdmfCellRange {
  std::string name;
  std::int64_t first = 0, count = 0;
};

struct XdmfLayout {
  std::string h5_file_name;  // relative to the .xmf (same directory), e.g. "dipc.h5"
  std::int64_t num_nodes = 0;
  std::int64_t num_elements = 0;
  bool kinematic = false;  // /mesh/kinematic exists
  bool contact_force = false, friction_force = false;
  std::vector<std::string> body_names;  // listed in an Information element
  std::vector<XdmfObstacle> obstacles;  // /obstacles/<j>, j in this order
  // The bodies' grids, index = position; empty: one grid "bodies" with every element.
  std::vector<XdmfCellRange> body_grids;
};

// Step k of `step_times` refers to the HDF5 group /steps/k.
std::string xdmf_document(const XdmfLayout& layout, const std::vector<double>& step_times);

}  // namespace dipc
