// XDMF 3 text generation (see xdmf_text.hpp). Format reference: xdmf.org "XDMF Model and
// Format" (Grid, Topology, Geometry, Attribute, DataItem with Format="HDF").
#include "io/xdmf_text.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace dipc {

std::string xml_escaped(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {

struct DataItem {
  std::string dimensions;
  const char* number_type;  // "Float" or "Int"
  int precision;            // bytes
  std::string dataset;      // path inside the .h5
};

void write_data_item(std::ostream& out, const std::string& h5_file, const DataItem& item,
                     const std::string& indent = "          ") {
  out << indent << "<DataItem Dimensions=\"" << item.dimensions << "\" NumberType=\"" << item.number_type
      << "\" Precision=\"" << item.precision << "\" Format=\"HDF\">" << h5_file << ":" << item.dataset
      << "</DataItem>\n";
}

// The hexahedra of a grid over `cells` of the mesh's `total` elements. A part of the mesh is an
// XDMF HyperSlab of /mesh/topology: a 3 × 2 XML item of start, stride and count per dimension,
// then the whole dataset it selects from; the HyperSlab states its result's type too.
void write_topology_item(std::ostream& out, const std::string& h5_file, const XdmfCellRange& cells,
                         std::int64_t total) {
  const std::string count = std::to_string(cells.count);
  if (cells.first == 0 && cells.count == total) {
    write_data_item(out, h5_file, {count + " 8", "Int", 8, "/mesh/topology"});
    return;
  }
  out << "          <DataItem ItemType=\"HyperSlab\" Type=\"HyperSlab\" Dimensions=\"" << count
      << " 8\" NumberType=\"Int\" Precision=\"8\">\n"
      << "            <DataItem Dimensions=\"3 2\" Format=\"XML\">" << cells.first << " 0 1 1 " << count
      << " 8</DataItem>\n";
  write_data_item(out, h5_file, {std::to_string(total) + " 8", "Int", 8, "/mesh/topology"}, "            ");
  out << "          </DataItem>\n";
}

void write_attribute(std::ostream& out, const std::string& h5_file, const char* name, const char* type,
                     const char* center, const DataItem& item) {
  out << "        <Attribute Name=\"" << name << "\" AttributeType=\"" << type << "\" Center=\"" << center << "\">\n";
  write_data_item(out, h5_file, item);
  out << "        </Attribute>\n";
}

// The shortest of %.15g..%.17g that reads back as the same double: the time in the .xmf is
// the solver's time exactly, and 0.1 prints as "0.1" rather than "0.10000000000000001".
std::string exact(double v) {
  char buf[32];
  for (int digits = 15; digits < 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) return buf;
  }
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Lines are written for a grid directly in the temporal collection; `indent` shifts them right
// inside a step's spatial collection.
std::string indented(const std::string& text, const std::string& indent) {
  if (indent.empty()) return text;
  std::istringstream lines(text);
  std::string out, line;
  while (std::getline(lines, line)) out += indent + line + "\n";
  return out;
}

// Bodies' grid `grid` (-1: the one grid of all elements) of step /steps/<k> without its <Grid>
// element: hexahedra and their fields. A grid of part of the mesh takes its cell fields from
// its own rows in <group>/grids/<grid>/ (ParaView's XDMF 3 reader drops attributes given as
// HyperSlabs, so they are stored per grid), its nodes and node fields from the whole mesh.
std::string body_grid_content(const XdmfLayout& layout, int grid, const std::string& h5, const std::string& step) {
  const XdmfCellRange cells = grid < 0 ? XdmfCellRange{"bodies", 0, layout.num_elements} : layout.body_grids[grid];
  const std::string nodes = std::to_string(layout.num_nodes), count = std::to_string(cells.count);
  const auto cell_field = [&](const std::string& group, const char* name) {
    return group + (grid < 0 ? "/" : "/grids/" + std::to_string(grid) + "/") + name;
  };
  std::ostringstream out;
  out << "        <Topology TopologyType=\"Hexahedron\" NumberOfElements=\"" << count << "\">\n";
  write_topology_item(out, h5, cells, layout.num_elements);
  out << "        </Topology>\n"
      << "        <Geometry GeometryType=\"XYZ\">\n";
  write_data_item(out, h5, {nodes + " 3", "Float", 8, "/mesh/coordinates"});
  out << "        </Geometry>\n";
  write_attribute(out, h5, "displacement", "Vector", "Node", {nodes + " 3", "Float", 8, step + "/displacement"});
  write_attribute(out, h5, "velocity", "Vector", "Node", {nodes + " 3", "Float", 8, step + "/velocity"});
  if (layout.contact_force)
    write_attribute(out, h5, "contact_force", "Vector", "Node", {nodes + " 3", "Float", 8, step + "/contact_force"});
  if (layout.friction_force)
    write_attribute(out, h5, "friction_force", "Vector", "Node", {nodes + " 3", "Float", 8, step + "/friction_force"});
  write_attribute(out, h5, "volume_ratio", "Scalar", "Cell", {count, "Float", 8, cell_field(step, "volume_ratio")});
  write_attribute(out, h5, "rank", "Scalar", "Cell", {count, "Int", 4, cell_field("/mesh", "rank")});
  write_attribute(out, h5, "body", "Scalar", "Cell", {count, "Int", 4, cell_field("/mesh", "body")});
  if (layout.kinematic)
    write_attribute(out, h5, "kinematic", "Scalar", "Cell", {count, "Int", 4, cell_field("/mesh", "kinematic")});
  return out.str();
}

// Obstacle j's grid at step /steps/<k>: rest geometry and a displacement, like the bodies'.
std::string obstacle_grid(const XdmfLayout& layout, std::size_t j, const std::string& h5, const std::string& step) {
  const XdmfObstacle& o = layout.obstacles[j];
  const std::string group = "/obstacles/" + std::to_string(j);
  const std::string vertices = std::to_string(o.num_vertices), faces = std::to_string(o.num_cells);
  std::ostringstream out;
  out << "      <Grid Name=\"" << xml_escaped(o.name) << "\" GridType=\"Uniform\">\n"
      << "        <Topology TopologyType=\"" << (o.nodes_per_cell == 4 ? "Quadrilateral" : "Triangle")
      << "\" NumberOfElements=\"" << faces << "\">\n";
  write_data_item(out, h5, {faces + " " + std::to_string(o.nodes_per_cell), "Int", 8, group + "/topology"});
  out << "        </Topology>\n"
      << "        <Geometry GeometryType=\"XYZ\">\n";
  write_data_item(out, h5, {vertices + " 3", "Float", 8, group + "/coordinates"});
  out << "        </Geometry>\n";
  write_attribute(out, h5, "displacement", "Vector", "Node",
                  {vertices + " 3", "Float", 8,
                   o.moving ? step + "/obstacles/" + std::to_string(j) + "/displacement" : group + "/displacement"});
  out << "      </Grid>\n";
  return out.str();
}

}  // namespace

std::string xdmf_document(const XdmfLayout& layout, const std::vector<double>& step_times) {
  const std::string h5 = xml_escaped(layout.h5_file_name);
  const int grids = std::max<int>(1, static_cast<int>(layout.body_grids.size()));
  const bool split = !layout.body_grids.empty(), collection = grids > 1 || !layout.obstacles.empty();
  // Body names for readers of the .xmf (ParaView shows the cell field "body" as ids; the names
  // are /mesh/body_names in id order).
  std::string names;
  for (const std::string& n : layout.body_names) names += (names.empty() ? "" : ", ") + n;
  std::ostringstream out;
  out << "<?xml version=\"1.0\" ?>\n"
      << "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
      << "<Xdmf Version=\"3.0\">\n"
      << "  <Domain>\n";
  if (!names.empty()) out << "    <Information Name=\"body_names\" Value=\"" << xml_escaped(names) << "\"/>\n";
  out << "    <Grid Name=\"TimeSeries\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < step_times.size(); ++k) {
    const std::string step = "/steps/" + std::to_string(k);
    const std::string time = "        <Time Value=\"" + exact(step_times[k]) + "\"/>\n";
    if (!collection) {
      out << "      <Grid Name=\"step_" << k << "\" GridType=\"Uniform\">\n"
          << time << body_grid_content(layout, split ? 0 : -1, h5, step) << "      </Grid>\n";
      continue;
    }
    out << "      <Grid Name=\"step_" << k << "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n" << time;
    for (int g = 0; g < grids; ++g)
      out << indented("      <Grid Name=\"" + xml_escaped(split ? layout.body_grids[g].name : "bodies") +
                          "\" GridType=\"Uniform\">\n" + body_grid_content(layout, split ? g : -1, h5, step) +
                          "      </Grid>\n",
                      "  ");
    for (std::size_t j = 0; j < layout.obstacles.size(); ++j) out << indented(obstacle_grid(layout, j, h5, step), "  ");
    out << "      </Grid>\n";
  }
  out << "    </Grid>\n"
      << "  </Domain>\n"
      << "</Xdmf>\n";
  return out.str();
}

}  // namespace dipc
