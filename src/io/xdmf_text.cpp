// XDMF 3 text generation (see xdmf_text.hpp). Format reference: xdmf.org "XDMF Model and
// Format" (Grid, Topology, Geometry, Attribute, DataItem with Format="HDF").
#include "io/xdmf_text.hpp"

#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace dipc {
namespace {

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

struct DataItem {
  std::string dimensions;
  const char* number_type;  // "Float" or "Int"
  int precision;            // bytes
  std::string dataset;      // path inside the .h5
};

void write_data_item(std::ostream& out, const std::string& h5_file, const DataItem& item) {
  out << "          <DataItem Dimensions=\"" << item.dimensions << "\" NumberType=\"" << item.number_type
      << "\" Precision=\"" << item.precision << "\" Format=\"HDF\">" << h5_file << ":" << item.dataset
      << "</DataItem>\n";
}

void write_attribute(std::ostream& out, const std::string& h5_file, const char* name, const char* type,
                     const char* center, const DataItem& item) {
  out << "        <Attribute Name=\"" << name << "\" AttributeType=\"" << type << "\" Center=\"" << center
      << "\">\n";
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

// The bodies' grid of step /steps/<k> without its <Grid> element: hexahedra and their fields.
std::string body_grid_content(const XdmfLayout& layout, const std::string& h5, const std::string& step) {
  const std::string nodes = std::to_string(layout.num_nodes);
  const std::string cells = std::to_string(layout.num_elements);
  std::ostringstream out;
  out << "        <Topology TopologyType=\"Hexahedron\" NumberOfElements=\"" << cells << "\">\n";
  write_data_item(out, h5, {cells + " 8", "Int", 8, "/mesh/topology"});
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
  write_attribute(out, h5, "volume_ratio", "Scalar", "Cell", {cells, "Float", 8, step + "/volume_ratio"});
  write_attribute(out, h5, "rank", "Scalar", "Cell", {cells, "Int", 4, "/mesh/rank"});
  write_attribute(out, h5, "body", "Scalar", "Cell", {cells, "Int", 4, "/mesh/body"});
  if (layout.kinematic) write_attribute(out, h5, "kinematic", "Scalar", "Cell", {cells, "Int", 4, "/mesh/kinematic"});
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
  const bool collection = !layout.obstacles.empty();
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
          << time << body_grid_content(layout, h5, step) << "      </Grid>\n";
      continue;
    }
    out << "      <Grid Name=\"step_" << k << "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n" << time;
    out << indented("      <Grid Name=\"bodies\" GridType=\"Uniform\">\n" + body_grid_content(layout, h5, step) +
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
