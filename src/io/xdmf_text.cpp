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

}  // namespace

std::string xdmf_document(const XdmfLayout& layout, const std::vector<double>& step_times) {
  const std::string h5 = xml_escaped(layout.h5_file_name);
  const std::string nodes = std::to_string(layout.num_nodes);
  const std::string cells = std::to_string(layout.num_elements);
  std::ostringstream out;
  out << "<?xml version=\"1.0\" ?>\n"
      << "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
      << "<Xdmf Version=\"3.0\">\n"
      << "  <Domain>\n"
      << "    <Grid Name=\"TimeSeries\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < step_times.size(); ++k) {
    const std::string step = "/steps/" + std::to_string(k);
    out << "      <Grid Name=\"step_" << k << "\" GridType=\"Uniform\">\n"
        << "        <Time Value=\"" << exact(step_times[k]) << "\"/>\n"
        << "        <Topology TopologyType=\"Hexahedron\" NumberOfElements=\"" << cells << "\">\n";
    write_data_item(out, h5, {cells + " 8", "Int", 8, "/mesh/topology"});
    out << "        </Topology>\n"
        << "        <Geometry GeometryType=\"XYZ\">\n";
    write_data_item(out, h5, {nodes + " 3", "Float", 8, "/mesh/coordinates"});
    out << "        </Geometry>\n";
    write_attribute(out, h5, "displacement", "Vector", "Node", {nodes + " 3", "Float", 8, step + "/displacement"});
    write_attribute(out, h5, "velocity", "Vector", "Node", {nodes + " 3", "Float", 8, step + "/velocity"});
    write_attribute(out, h5, "volume_ratio", "Scalar", "Cell", {cells, "Float", 8, step + "/volume_ratio"});
    write_attribute(out, h5, "rank", "Scalar", "Cell", {cells, "Int", 4, "/mesh/rank"});
    write_attribute(out, h5, "body", "Scalar", "Cell", {cells, "Int", 4, "/mesh/body"});
    out << "      </Grid>\n";
  }
  out << "    </Grid>\n"
      << "  </Domain>\n"
      << "</Xdmf>\n";
  return out.str();
}

}  // namespace dipc
