// Gmsh MSH 4.1 and 2.2 reader, ASCII and binary (see gmsh_reader.hpp). Section layouts
// follow the Gmsh reference manual, "MSH file format" (version 4.1) and "Legacy formats"
// (MSH file format version 2). MSH 4.1:
//   $MeshFormat     version file-type data-size
//   $PhysicalNames  n, then n x { dim tag "name" }
//   $Entities       #points #curves #surfaces #volumes, then per entity its tag, position or
//                   bounding box, physical tags and (except points) bounding entities
//   $Nodes          #blocks #nodes minTag maxTag, then per block
//                   { dim entityTag parametric #n, n tags, n x { x y z [u v w up to dim] } }
//   $Elements       #blocks #elements minTag maxTag, then per block
//                   { dim entityTag type #n, n x { tag node-tags... } }
// In binary 4.1 files $Entities, $Nodes and $Elements hold the same values as raw data:
// counts and node/element tags as size_t (the data size of $MeshFormat, 4 or 8 bytes),
// dimensions, entity tags, types and physical tags as int (4 bytes), coordinates as double.
// MSH 2.2 ($MeshFormat and $PhysicalNames as in 4.1, no $Entities):
//   $Nodes          n, then n x { tag x y z }  (binary: int tag, 3 doubles)
//   $Elements       n, then n x { tag type #tags tags... node-tags... }, the tags being the
//                   physical group, the elementary entity and optional partition data
//                   (binary: blocks of { int type, int #elements, int #tags } then per
//                   element { int tag, int tags[#tags], int node-tags[] })
// Binary files write the int 1 after the $MeshFormat line so that readers can check the
// byte order; every binary value is read as little-endian.
#include "mesh/gmsh_reader.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <unordered_map>
#include <utility>

#include "mesh/mesh_checks.hpp"
#include "mesh/mesh_error.hpp"
#include "mesh/msh_scanner.hpp"

namespace dipc {

namespace {

using EntityKey = std::pair<int, std::int64_t>;  // (dimension, tag) of a model entity
using GroupKey = std::pair<int, std::int64_t>;   // (dimension, tag) of a physical group

constexpr int kHexahedron = 5;

struct ElementType {
  int type;
  int nodes;
  int dim;
  const char* name;
};

// Gmsh element types (reference manual, "MSH file format", element types table). dipc reads
// linear hexahedra; points, lines, triangles and quadrangles only feed physical groups.
constexpr ElementType kElementTypes[] = {
    {1, 2, 1, "2-node line"},
    {2, 3, 2, "3-node triangle"},
    {3, 4, 2, "4-node quadrangle"},
    {4, 4, 3, "4-node tetrahedron"},
    {5, 8, 3, "8-node hexahedron"},
    {6, 6, 3, "6-node prism"},
    {7, 5, 3, "5-node pyramid"},
    {8, 3, 1, "3-node second-order line"},
    {9, 6, 2, "6-node second-order triangle"},
    {10, 9, 2, "9-node second-order quadrangle"},
    {11, 10, 3, "10-node second-order tetrahedron"},
    {12, 27, 3, "27-node second-order hexahedron"},
    {13, 18, 3, "18-node second-order prism"},
    {14, 14, 3, "14-node second-order pyramid"},
    {15, 1, 0, "1-node point"},
    {16, 8, 2, "8-node second-order quadrangle"},
    {17, 20, 3, "20-node second-order hexahedron"},
    {18, 15, 3, "15-node second-order prism"},
    {19, 13, 3, "13-node second-order pyramid"},
    {92, 64, 3, "64-node third-order hexahedron"},
    {93, 125, 3, "125-node fourth-order hexahedron"},
};

const ElementType* find_element_type(std::int64_t type) {
  for (const auto& t : kElementTypes)
    if (t.type == type) return &t;
  return nullptr;
}

bool feeds_node_sets(int type) { return type == 15 || type == 1 || type == 2 || type == 3; }
bool is_higher_order_hexahedron(int type) { return type == 12 || type == 17 || type == 92 || type == 93; }

// Node tag -> 0-based index. Gmsh tags are usually dense (1..n), so a vector indexed by
// tag - minTag is used when the header's range is not much larger than the node count;
// tags outside that range (sparse numbering, a header that lies) go to a hash map.
class NodeTagIndex {
 public:
  void reserve(std::int64_t min_tag, std::int64_t max_tag, std::int64_t count) {
    if (min_tag >= 0 && max_tag >= min_tag && max_tag - min_tag <= 4 * count + 1024) {
      lo_ = min_tag;
      dense_.assign(static_cast<std::size_t>(max_tag - min_tag + 1), -1);
    }
  }
  // False when the tag is already present.
  bool insert(std::int64_t tag, std::int64_t index) {
    if (tag >= lo_ && tag - lo_ < static_cast<std::int64_t>(dense_.size())) {
      auto& slot = dense_[static_cast<std::size_t>(tag - lo_)];
      if (slot >= 0) return false;
      slot = index;
      return true;
    }
    return sparse_.emplace(tag, index).second;
  }
  // -1 when absent.
  std::int64_t find(std::int64_t tag) const {
    if (tag >= lo_ && tag - lo_ < static_cast<std::int64_t>(dense_.size()))
      return dense_[static_cast<std::size_t>(tag - lo_)];
    const auto it = sparse_.find(tag);
    return it == sparse_.end() ? -1 : it->second;
  }

 private:
  std::int64_t lo_ = 0;
  std::vector<std::int64_t> dense_;
  std::unordered_map<std::int64_t, std::int64_t> sparse_;
};

struct PhysicalGroup {
  std::string name;       // empty: unnamed
  std::int64_t line = 0;  // where it was first named or referenced
};

class GmshReader {
 public:
  GmshReader(std::string text, const std::string& path) : in_(std::move(text), path) {}

  HexMesh read(int body);

 private:
  void read_mesh_format();
  void read_physical_names();
  void read_entities();
  void read_nodes();
  void read_elements();
  void read_nodes_v2();
  void read_elements_v2();
  // Adds one MSH 2 element: `tags` are its integer tags, `node_tags` its nodes.
  void add_element_v2(std::int64_t element_tag, std::int64_t location, const ElementType& type,
                      const std::int64_t* tags, std::int64_t num_tags, const std::int64_t* node_tags);
  // The element type `type_id`, or a located error when dipc cannot use it.
  const ElementType& usable_type(std::int64_t type_id, std::int64_t location) const;

  // Values that are text in ASCII files and raw data in binary ones.
  std::int64_t int_value(const char* what) { return binary_ ? in_.binary_int(what) : in_.integer(what); }
  // A count (size_t in binary 4.1 files).
  std::int64_t count_value(const char* what) { return binary_ ? in_.binary_size(size_bytes_, what) : in_.count(what); }
  // A node or element tag (size_t in binary 4.1 files, int in binary 2.2 files).
  std::int64_t tag_value(const char* what) {
    if (!binary_) return in_.integer(what);
    return version_ == 2 ? in_.binary_int(what) : in_.binary_size(size_bytes_, what);
  }
  double real_value(const char* what) { return binary_ ? in_.binary_double(what) : in_.real(what); }
  void build_node_sets(HexMesh& mesh) const;
  std::int64_t node_index(std::int64_t tag, std::int64_t element_tag) const;
  std::size_t capped(std::int64_t count) const {
    return static_cast<std::size_t>(std::min<std::int64_t>(count, in_.remaining() / 2));
  }

  MshScanner in_;
  int version_ = 4;  // 4 (MSH 4.1) or 2 (MSH 2.2)
  bool binary_ = false;
  int size_bytes_ = 8;  // sizeof(size_t) of the writer, binary MSH 4.1
  std::set<std::string> seen_sections_;

  std::map<GroupKey, PhysicalGroup> groups_;
  std::map<EntityKey, std::vector<std::int64_t>> entity_groups_;  // physical tags per entity
  bool have_entities_ = false;

  std::vector<Vec3> nodes_;
  NodeTagIndex node_index_;
  MeshSourceMap source_;
  std::vector<Hex> hexes_;
  std::int64_t elements_line_ = 0;  // line of the $Elements header
  // Nodes of the elements of each entity that carries physical groups (with repeats).
  std::map<EntityKey, std::vector<std::int64_t>> entity_nodes_;
  // MSH 2: hexahedron index by its sorted node ids. Gmsh (4.8) writes an element once per
  // physical group of its entity, under a new tag each time, so a hexahedron with the nodes
  // of an earlier one is that element in another group.
  std::map<Hex, std::size_t> hex_of_nodes_;
};

HexMesh GmshReader::read(int body) {
  read_mesh_format();
  while (in_.has_token()) {
    const std::string header(in_.token("a section header"));
    if (header.size() < 2 || header.front() != '$' || header.compare(0, 4, "$End") == 0)
      in_.fail("expected a section header ($Name), found '" + header.substr(0, 40) + "'");
    const std::string name = header.substr(1);
    const bool known = name == "PhysicalNames" || name == "Entities" || name == "Nodes" || name == "Elements" ||
                       name == "PartitionedEntities";
    if (known && !seen_sections_.insert(name).second) in_.fail("second " + header + " section");
    in_.enter_section(header);
    if (name == "PhysicalNames") {
      read_physical_names();  // ASCII in binary files too
    } else if (name == "Entities" && version_ == 4) {
      if (seen_sections_.count("Elements")) in_.fail("$Entities must come before $Elements");
      if (binary_) in_.begin_binary("the binary $Entities data");
      read_entities();
    } else if (name == "Nodes") {
      if (version_ == 4) {
        if (binary_) in_.begin_binary("the binary $Nodes data");
        read_nodes();
      } else {
        read_nodes_v2();
      }
    } else if (name == "Elements") {
      elements_line_ = in_.location();
      if (!seen_sections_.count("Nodes")) in_.fail("$Elements must come after $Nodes");
      if (version_ == 4) {
        if (binary_) in_.begin_binary("the binary $Elements data");
        read_elements();
      } else {
        read_elements_v2();
      }
    } else if (name == "PartitionedEntities") {
      in_.fail("partitioned meshes are not supported: save the mesh unpartitioned "
               "(dipc partitions it itself)");
    } else {
      in_.skip_section(name);
    }
    in_.enter_section("");
  }
  if (!seen_sections_.count("Nodes")) in_.fail("no $Nodes section");
  if (!seen_sections_.count("Elements")) in_.fail("no $Elements section");
  if (hexes_.empty())
    in_.fail_at(elements_line_, "no hexahedra (element type 5) in $Elements; if the file has physical groups, "
                                "add the volume to one or save with Mesh.SaveAll = 1");

  HexMesh mesh;
  mesh.nodes = std::move(nodes_);
  mesh.hexes = std::move(hexes_);
  mesh.body.assign(mesh.hexes.size(), body);
  build_node_sets(mesh);
  source_.byte_offsets = in_.byte_offsets();
  check_mesh(mesh, in_.path(), &source_);
  return mesh;
}

void GmshReader::read_mesh_format() {
  const std::string_view first = in_.token("$MeshFormat");
  if (first != "$MeshFormat")
    in_.fail("not a Gmsh MSH file: expected $MeshFormat first, found '" + std::string(first.substr(0, 40)) + "'");
  in_.enter_section("$MeshFormat");
  const std::string version(in_.token("the MSH version"));
  if (version == "4.1") {
    version_ = 4;
  } else if (version == "2.2") {
    version_ = 2;
  } else {
    in_.fail("MSH version " + version +
             " is not supported (dipc reads 4.1 and 2.2): re-export it as MSH 4.1 (gmsh -format "
             "msh41, or Mesh.MshFileVersion = 4.1)");
  }
  in_.declare_version(version);
  const std::int64_t file_type = in_.integer("the file type (0 = ASCII, 1 = binary)");
  if (file_type != 0 && file_type != 1)
    in_.fail("$MeshFormat section is malformed: file type " + std::to_string(file_type) +
             " (expected 0 for ASCII or 1 for binary)");
  binary_ = file_type == 1;
  const std::int64_t data_size = in_.integer("the data size");
  // MSH 4.1 gives sizeof(size_t) of the writer, MSH 2.2 sizeof(double); both must be
  // usable by the binary readers (an ASCII file does not depend on it).
  if (binary_ && version_ == 4 && data_size != 4 && data_size != 8)
    in_.fail("$MeshFormat section: data size " + std::to_string(data_size) +
             " is not supported for binary MSH 4.1 (size_t of 4 or 8 bytes)");
  if (binary_ && version_ == 2 && data_size != 8)
    in_.fail("$MeshFormat section: data size " + std::to_string(data_size) +
             " is not supported for binary MSH 2.2 (8-byte doubles)");
  size_bytes_ = static_cast<int>(data_size);
  if (binary_) {
    // The int 1, as the writer stored it: 01 00 00 00 little-endian, 00 00 00 01 big-endian.
    in_.begin_binary("the binary byte-order check (the int 1)");
    unsigned char one[4];
    if (in_.peek_bytes(one) && one[0] == 0 && one[1] == 0 && one[2] == 0 && one[3] == 1)
      in_.fail("binary MSH written with big-endian byte order is not supported: re-save it "
               "as ASCII (gmsh -format msh41 without -bin) or on a little-endian machine");
    in_.use_byte_offsets();
    const std::int64_t check = in_.binary_int("the binary byte-order check (the int 1)");
    if (check != 1)
      in_.fail("$MeshFormat section is malformed: the binary byte-order check is " + std::to_string(check) + ", not 1");
  }
  in_.expect("$EndMeshFormat", "$MeshFormat holds 3 values");
  in_.enter_section("");
}

void GmshReader::read_physical_names() {
  const std::int64_t n = in_.count("the number of physical names");
  for (std::int64_t i = 0; i < n; ++i) {
    const std::int64_t dim = in_.integer("a physical group dimension");
    const std::int64_t line = in_.location();
    if (dim < 0 || dim > 3)
      in_.fail("$PhysicalNames section is malformed: dimension " + std::to_string(dim) + " is not 0..3");
    const std::int64_t tag = in_.integer("a physical group tag");
    std::string name = in_.quoted("a physical group name");
    auto& group = groups_[{static_cast<int>(dim), tag}];
    if (!group.name.empty())
      in_.fail("physical group (dimension " + std::to_string(dim) + ", tag " + std::to_string(tag) +
               ") is named twice");
    group.name = std::move(name);
    group.line = line;
  }
  in_.expect("$EndPhysicalNames", "more names than the count announces?");
}

void GmshReader::read_entities() {
  have_entities_ = true;
  std::int64_t counts[4];
  counts[0] = count_value("the number of points");
  counts[1] = count_value("the number of curves");
  counts[2] = count_value("the number of surfaces");
  counts[3] = count_value("the number of volumes");
  for (int dim = 0; dim < 4; ++dim)
    for (std::int64_t i = 0; i < counts[dim]; ++i) {
      const std::int64_t tag = int_value("an entity tag");
      const std::int64_t line = in_.location();
      // A point has its position (3 values), higher entities their bounding box (6).
      for (int k = 0; k < (dim == 0 ? 3 : 6); ++k)
        real_value(dim == 0 ? "a point coordinate" : "a bounding box coordinate");
      const std::int64_t num_physicals = count_value("the number of physical tags");
      auto& tags = entity_groups_[{dim, tag}];
      for (std::int64_t p = 0; p < num_physicals; ++p) {
        // A negative physical tag only records an orientation; the group is the same.
        const std::int64_t physical = std::abs(int_value("a physical tag"));
        tags.push_back(physical);
        auto& group = groups_[{dim, physical}];
        if (group.line == 0) group.line = line;
      }
      if (dim > 0) {
        const std::int64_t num_bounding = count_value("the number of bounding entities");
        for (std::int64_t b = 0; b < num_bounding; ++b) int_value("a bounding entity tag");
      }
    }
  in_.expect("$EndEntities", "more entities than the counts announce?");
}

void GmshReader::read_nodes() {
  const std::int64_t num_blocks = count_value("the number of node blocks");
  const std::int64_t num_nodes = count_value("the number of nodes");
  const std::int64_t min_tag = tag_value("the smallest node tag");
  const std::int64_t max_tag = tag_value("the largest node tag");
  nodes_.reserve(capped(num_nodes));
  source_.node_tags.reserve(capped(num_nodes));
  source_.node_lines.reserve(capped(num_nodes));
  node_index_.reserve(min_tag, max_tag, static_cast<std::int64_t>(capped(num_nodes)));

  std::vector<std::int64_t> block_tags;
  for (std::int64_t b = 0; b < num_blocks; ++b) {
    const std::int64_t dim = int_value("a node block's entity dimension");
    if (dim < 0 || dim > 3)
      in_.fail("$Nodes section is malformed: entity dimension " + std::to_string(dim) + " is not 0..3");
    int_value("a node block's entity tag");
    const std::int64_t parametric = binary_ ? in_.binary_int("a node block's parametric flag")
                                            : in_.count("a node block's parametric flag");
    if (parametric < 0 || parametric > 1)
      in_.fail("$Nodes section is malformed: parametric flag " + std::to_string(parametric) + " is not 0 or 1");
    const std::int64_t n = count_value("a node block's node count");
    // Parametric blocks append the entity-dimension local coordinates (u, v, w) to x y z.
    const int values_per_node = 3 + (parametric ? static_cast<int>(dim) : 0);

    block_tags.clear();
    block_tags.reserve(capped(n));
    for (std::int64_t i = 0; i < n; ++i) {
      const std::int64_t tag = tag_value("a node tag");
      if (tag <= 0) in_.fail("node tag " + std::to_string(tag) + " is not positive");
      const auto index = static_cast<std::int64_t>(source_.node_tags.size());
      if (!node_index_.insert(tag, index)) in_.fail("node " + std::to_string(tag) + " is defined twice");
      block_tags.push_back(tag);
      source_.node_tags.push_back(tag);
      source_.node_lines.push_back(in_.location());
    }
    for (std::int64_t i = 0; i < n; ++i) {
      Vec3 x;
      for (int k = 0; k < values_per_node; ++k) {
        const double v = real_value(k < 3 ? "a node coordinate" : "a parametric coordinate");
        if (k >= 3) continue;
        if (!std::isfinite(v))
          in_.fail("node " + std::to_string(block_tags[i]) + " has a non-finite " + "xyz"[k] + " coordinate");
        x[k] = v;
      }
      nodes_.push_back(x);
    }
  }
  if (static_cast<std::int64_t>(nodes_.size()) != num_nodes)
    in_.fail("$Nodes section is malformed: the header announces " + std::to_string(num_nodes) +
             " nodes but its blocks hold " + std::to_string(nodes_.size()));
  in_.expect("$EndNodes", "more node blocks than the header announces?");
}

std::int64_t GmshReader::node_index(std::int64_t tag, std::int64_t element_tag) const {
  const std::int64_t index = node_index_.find(tag);
  if (index < 0)
    in_.fail("element " + std::to_string(element_tag) + " refers to node " + std::to_string(tag) +
             ", which is not in $Nodes");
  return index;
}

void GmshReader::read_elements() {
  const std::int64_t num_blocks = count_value("the number of element blocks");
  const std::int64_t num_elements = count_value("the number of elements");
  tag_value("the smallest element tag");
  tag_value("the largest element tag");

  std::int64_t total = 0;
  std::int64_t tags[8];  // node tags of one element: only types of at most 8 nodes get here
  for (std::int64_t b = 0; b < num_blocks; ++b) {
    const std::int64_t dim = int_value("an element block's entity dimension");
    const std::int64_t entity = int_value("an element block's entity tag");
    const std::int64_t type_id = int_value("an element type");
    const std::int64_t block_line = in_.location();
    const std::int64_t n = count_value("an element block's element count");
    const ElementType* type = &usable_type(type_id, block_line);
    if (dim != type->dim)
      in_.fail_at(block_line, "$Elements section is malformed: a block of " + std::string(type->name) +
                                  " elements on an entity of dimension " + std::to_string(dim));
    const EntityKey key{static_cast<int>(dim), entity};
    const auto groups = entity_groups_.find(key);
    if (have_entities_ && groups == entity_groups_.end())
      in_.fail_at(block_line, "element block on entity (dimension " + std::to_string(dim) + ", tag " +
                                  std::to_string(entity) + "), which is not in $Entities");
    std::vector<std::int64_t>* set_nodes = (groups != entity_groups_.end() && !groups->second.empty())
                                               ? &entity_nodes_[key]
                                               : nullptr;

    for (std::int64_t i = 0; i < n; ++i) {
      const std::int64_t element_tag = tag_value("an element tag");
      const std::int64_t element_line = in_.location();
      if (element_tag <= 0) in_.fail("element tag " + std::to_string(element_tag) + " is not positive");
      for (int a = 0; a < type->nodes; ++a) tags[a] = tag_value("an element node tag");
      if (type->type == kHexahedron) {
        Hex h;
        for (int a = 0; a < 8; ++a) h[a] = node_index(tags[a], element_tag);
        hexes_.push_back(h);
        source_.element_tags.push_back(element_tag);
        source_.element_lines.push_back(element_line);
        if (set_nodes) set_nodes->insert(set_nodes->end(), h.begin(), h.end());
      } else {
        for (int a = 0; a < type->nodes; ++a) {
          const std::int64_t index = node_index(tags[a], element_tag);
          if (set_nodes) set_nodes->push_back(index);
        }
      }
    }
    total += n;
  }
  if (total != num_elements)
    in_.fail("$Elements section is malformed: the header announces " + std::to_string(num_elements) +
             " elements but its blocks hold " + std::to_string(total));
  in_.expect("$EndElements", "more element blocks than the header announces?");
}

const ElementType& GmshReader::usable_type(std::int64_t type_id, std::int64_t location) const {
  const ElementType* type = find_element_type(type_id);
  if (!type)
    in_.fail_at(location, "element type " + std::to_string(type_id) +
                              " is not supported (dipc reads linear hexahedra, type 5, and "
                              "points, lines, triangles, quadrangles for physical groups)");
  if (type->type != kHexahedron && !feeds_node_sets(type->type)) {
    std::string why = is_higher_order_hexahedron(type->type)
                          ? "dipc reads linear hexahedra only (type 5, Mesh.ElementOrder = 1)"
                      : type->dim == 3 ? "dipc needs an all-hexahedral mesh (e.g. transfinite volumes with "
                                         "Mesh.RecombineAll = 1)"
                                       : "use a first-order mesh (Mesh.ElementOrder = 1)";
    in_.fail_at(location, "element type " + std::to_string(type_id) + " (" + type->name + ") is not supported: " + why);
  }
  return *type;
}

void GmshReader::read_nodes_v2() {
  const std::int64_t n = in_.count("the number of nodes");
  if (binary_) in_.begin_binary("the binary $Nodes data");
  nodes_.reserve(capped(n));
  source_.node_tags.reserve(capped(n));
  source_.node_lines.reserve(capped(n));
  // MSH 2 has no tag range in the header; Gmsh numbers nodes 1..n.
  node_index_.reserve(1, n, static_cast<std::int64_t>(capped(n)));
  for (std::int64_t i = 0; i < n; ++i) {
    const std::int64_t tag = tag_value("a node tag");
    if (tag <= 0) in_.fail("node tag " + std::to_string(tag) + " is not positive");
    if (!node_index_.insert(tag, static_cast<std::int64_t>(nodes_.size())))
      in_.fail("node " + std::to_string(tag) + " is defined twice");
    source_.node_tags.push_back(tag);
    source_.node_lines.push_back(in_.location());
    Vec3 x;
    for (int k = 0; k < 3; ++k) {
      x[k] = real_value("a node coordinate");
      if (!std::isfinite(x[k]))
        in_.fail("node " + std::to_string(tag) + " has a non-finite " + "xyz"[k] + " coordinate");
    }
    nodes_.push_back(x);
  }
  in_.expect("$EndNodes", "more nodes than the count announces?");
}

void GmshReader::read_elements_v2() {
  const std::int64_t n = in_.count("the number of elements");
  std::vector<std::int64_t> tags;
  std::int64_t node_tags[8];  // only types of at most 8 nodes get past usable_type
  if (!binary_) {
    for (std::int64_t i = 0; i < n; ++i) {
      const std::int64_t element_tag = in_.integer("an element tag");
      const std::int64_t location = in_.location();
      const ElementType& type = usable_type(in_.integer("an element type"), location);
      const std::int64_t num_tags = in_.count("the number of element tags");
      tags.resize(static_cast<std::size_t>(std::min<std::int64_t>(num_tags, 64)));
      for (std::int64_t t = 0; t < num_tags; ++t) {
        const std::int64_t v = in_.integer("an element tag (physical, entity, partitions)");
        if (t < 64) tags[static_cast<std::size_t>(t)] = v;
      }
      for (int a = 0; a < type.nodes; ++a) node_tags[a] = in_.integer("an element node tag");
      add_element_v2(element_tag, location, type, tags.data(), static_cast<std::int64_t>(tags.size()), node_tags);
    }
  } else {
    in_.begin_binary("the binary $Elements data");
    std::int64_t read = 0;
    while (read < n) {
      const std::int64_t type_id = in_.binary_int("an element block's element type");
      const ElementType& type = usable_type(type_id, in_.location());
      const std::int64_t count = in_.binary_int("an element block's element count");
      const std::int64_t num_tags = in_.binary_int("an element block's number of tags");
      if (count <= 0 || count > n - read)
        in_.fail("$Elements section is malformed: a block of " + std::to_string(count) + " elements where " +
                 std::to_string(n - read) + " remain");
      if (num_tags < 0 || num_tags > 64)
        in_.fail("$Elements section is malformed: " + std::to_string(num_tags) + " tags per element");
      tags.resize(static_cast<std::size_t>(num_tags));
      for (std::int64_t i = 0; i < count; ++i) {
        const std::int64_t element_tag = in_.binary_int("an element tag");
        const std::int64_t location = in_.location();
        for (auto& t : tags) t = in_.binary_int("an element tag (physical, entity, partitions)");
        for (int a = 0; a < type.nodes; ++a) node_tags[a] = in_.binary_int("an element node tag");
        add_element_v2(element_tag, location, type, tags.data(), num_tags, node_tags);
      }
      read += count;
    }
  }
  in_.expect("$EndElements", "more elements than the count announces?");
}

void GmshReader::add_element_v2(std::int64_t element_tag, std::int64_t location, const ElementType& type,
                                const std::int64_t* tags, std::int64_t num_tags, const std::int64_t* node_tags) {
  if (element_tag <= 0) in_.fail_at(location, "element tag " + std::to_string(element_tag) + " is not positive");
  // MSH 2 has no entities: the physical group (first tag, 0 for none) stands in as the
  // entity whose elements feed the group's node set. Partition tags are not needed: dipc
  // partitions the whole mesh itself.
  const std::int64_t physical = num_tags > 0 ? tags[0] : 0;
  if (physical < 0)
    in_.fail_at(location, "element " + std::to_string(element_tag) + " has physical tag " + std::to_string(physical));
  std::vector<std::int64_t>* set_nodes = nullptr;
  if (physical > 0) {
    const EntityKey key{type.dim, physical};
    auto& group = groups_[key];
    if (group.line == 0) group.line = location;
    auto& groups = entity_groups_[key];
    if (groups.empty()) groups.push_back(physical);
    set_nodes = &entity_nodes_[key];
  }
  std::int64_t ids[8];
  for (int a = 0; a < type.nodes; ++a) {
    ids[a] = node_index_.find(node_tags[a]);
    if (ids[a] < 0)
      in_.fail_at(location, "element " + std::to_string(element_tag) + " refers to node " +
                                std::to_string(node_tags[a]) + ", which is not in $Nodes");
  }
  if (set_nodes) set_nodes->insert(set_nodes->end(), ids, ids + type.nodes);
  if (type.type != kHexahedron) return;
  Hex h;
  std::copy(ids, ids + 8, h.begin());
  Hex sorted = h;
  std::sort(sorted.begin(), sorted.end());
  const auto [it, inserted] = hex_of_nodes_.emplace(sorted, hexes_.size());
  if (!inserted) {
    if (hexes_[it->second] != h)
      in_.fail_at(location, "element " + std::to_string(element_tag) + " has the nodes of element " +
                                std::to_string(source_.element_tags[it->second]) + " in another order");
    return;  // the same element, written again for another physical group
  }
  hexes_.push_back(h);
  source_.element_tags.push_back(element_tag);
  source_.element_lines.push_back(location);
}

void GmshReader::build_node_sets(HexMesh& mesh) const {
  // Set name of each physical group; detect names that two groups would share.
  std::map<std::string, std::vector<GroupKey>> by_name;
  for (const auto& [key, group] : groups_) {
    const std::string name = group.name.empty() ? "physical_" + std::to_string(key.second) : group.name;
    by_name[name].push_back(key);
  }
  for (const auto& [name, keys] : by_name) {
    if (keys.size() < 2) continue;
    for (const GroupKey& key : keys) {
      const PhysicalGroup& group = groups_.at(key);
      if (!group.name.empty()) continue;
      const GroupKey& other = keys[0] == key ? keys[1] : keys[0];
      in_.fail_at(group.line, "physical groups (dimension " + std::to_string(key.first) + ", tag " +
                                  std::to_string(key.second) + ") and (dimension " + std::to_string(other.first) +
                                  ", tag " + std::to_string(other.second) + ") would both be node set '" + name +
                                  "': name them in $PhysicalNames");
    }
  }

  std::map<GroupKey, const std::string*> name_of;
  for (const auto& [name, keys] : by_name)
    for (const GroupKey& key : keys) name_of[key] = &name;
  for (const auto& [name, keys] : by_name) mesh.node_sets[name];  // empty groups stay visible
  for (const auto& [entity, nodes] : entity_nodes_)
    for (std::int64_t physical : entity_groups_.at(entity)) {
      auto& set = mesh.node_sets[*name_of.at({entity.first, physical})];
      set.insert(set.end(), nodes.begin(), nodes.end());
    }
  for (auto& [name, ids] : mesh.node_sets) {
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  }
}

}  // namespace

HexMesh read_gmsh(const std::string& path, int body) {
  // No line to point at for these two: the message names only the path.
  if (body < 0) throw MeshError(path + ": body id " + std::to_string(body) + " is negative");
  std::ifstream file(path, std::ios::binary | std::ios::ate);
  if (!file) throw MeshError(path + ": cannot open the file");
  // One read into a string of the file's size: meshes run to hundreds of MB.
  std::string text(static_cast<std::size_t>(file.tellg()), '\0');
  file.seekg(0);
  if (!file.read(text.data(), static_cast<std::streamsize>(text.size())))
    throw MeshError(path + ": cannot read the file");
  return GmshReader(std::move(text), path).read(body);
}

}  // namespace dipc
