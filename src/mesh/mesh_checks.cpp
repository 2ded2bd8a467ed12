// check_mesh and bounding_box_diagonal (see mesh_checks.hpp for the rules).
#include "mesh/mesh_checks.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "math/small_matrix.hpp"
#include "mesh/hex8_reference.hpp"
#include "mesh/mesh_error.hpp"

namespace dipc {

namespace {

// Names nodes and elements in messages: by file tag and line when a source map has them.
class Labels {
 public:
  Labels(const std::string& source, const MeshSourceMap* map) : source_(source), map_(map) {}

  std::string node(std::int64_t n) const {
    if (map_ && in(map_->node_tags, n)) return "node " + std::to_string(map_->node_tags[n]);
    return "node " + std::to_string(n);
  }
  std::string element(std::int64_t e) const {
    if (map_ && in(map_->element_tags, e)) return "element " + std::to_string(map_->element_tags[e]) + " (hexahedron)";
    return "element " + std::to_string(e);
  }
  [[noreturn]] void fail(const std::string& what) const { throw MeshError(source_ + ": " + what); }
  [[noreturn]] void fail_at_node(std::int64_t n, const std::string& what) const {
    fail_at(map_ ? &map_->node_lines : nullptr, n, node(n) + " " + what);
  }
  [[noreturn]] void fail_at_element(std::int64_t e, const std::string& what) const {
    fail_at(map_ ? &map_->element_lines : nullptr, e, element(e) + " " + what);
  }

 private:
  static bool in(const std::vector<std::int64_t>& v, std::int64_t i) {
    return i >= 0 && static_cast<std::size_t>(i) < v.size();
  }
  [[noreturn]] void fail_at(const std::vector<std::int64_t>* lines, std::int64_t i, const std::string& what) const {
    if (lines && in(*lines, i)) {
      const std::string at = map_->byte_offsets ? ": byte " + std::to_string((*lines)[i]) + ": "
                                                : ":" + std::to_string((*lines)[i]) + ": ";
      throw MeshError(source_ + at + what);
    }
    fail(what);
  }
  const std::string& source_;
  const MeshSourceMap* map_;
};

std::string format_double(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

double longest_edge(const double X[24]) {
  // The 12 edges of a hex8 in Gmsh ordering: bottom ring, top ring, verticals.
  static const int edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                   {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  double longest = 0;
  for (const auto& e : edges) {
    double d2 = 0;
    for (int i = 0; i < 3; ++i) {
      const double d = X[3 * e[1] + i] - X[3 * e[0] + i];
      d2 += d * d;
    }
    longest = std::max(longest, std::sqrt(d2));
  }
  return longest;
}

// Where det J is smallest among the points hex8::min_jacobian_determinant visits (the 8
// corners, then the 8 Gauss points), so the message can point at it.
std::string worst_jacobian_point(const double X[24]) {
  double dN[24], J[9];
  double smallest = 1e300;
  int worst = 0;
  for (int p = 0; p < 16; ++p) {
    double xi, eta, zeta;
    if (p < 8) {
      xi = hex8::corner_xi(p), eta = hex8::corner_eta(p), zeta = hex8::corner_zeta(p);
    } else {
      hex8::gauss_point(p - 8, xi, eta, zeta);
    }
    hex8::shape_gradient(xi, eta, zeta, dN);
    hex8::jacobian(X, dN, J);
    const double d = det3x3(J);
    if (d < smallest) smallest = d, worst = p;
  }
  return worst < 8 ? "corner " + std::to_string(worst) : "Gauss point " + std::to_string(worst - 8);
}

void check_element_jacobian(const HexMesh& mesh, std::size_t e, const Labels& labels) {
  double X[24];
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i) X[3 * a + i] = mesh.nodes[mesh.hexes[e][a]][i];
  const double det = hex8::min_jacobian_determinant(X);
  const double edge = longest_edge(X);
  const double tolerance = kDegenerateJacobianRatio * edge * edge * edge;
  if (det > tolerance) return;
  const auto id = static_cast<std::int64_t>(e);
  const std::string at = "det J = " + format_double(det) + " at " + worst_jacobian_point(X);
  if (det < -tolerance) labels.fail_at_element(id, "is inverted: " + at + " (check the node ordering)");
  labels.fail_at_element(id, "is degenerate: " + at + " (longest edge " + format_double(edge) + ")");
}

}  // namespace

void check_mesh(const HexMesh& mesh, const std::string& source, const MeshSourceMap* map) {
  const Labels labels(source, map);
  const auto num_nodes = static_cast<std::int64_t>(mesh.nodes.size());

  if (mesh.hexes.empty()) labels.fail("mesh has no elements");
  if (mesh.body.size() != mesh.hexes.size())
    labels.fail("mesh has " + std::to_string(mesh.body.size()) + " body ids for " + std::to_string(mesh.hexes.size()) +
                " elements");
  for (std::size_t e = 0; e < mesh.body.size(); ++e)
    if (mesh.body[e] < 0)
      labels.fail_at_element(static_cast<std::int64_t>(e), "has negative body id " + std::to_string(mesh.body[e]));

  for (std::int64_t n = 0; n < num_nodes; ++n)
    for (int i = 0; i < 3; ++i)
      if (!std::isfinite(mesh.nodes[n][i]))
        labels.fail_at_node(n, std::string("has a non-finite ") + "xyz"[i] + " coordinate");

  std::vector<char> used(mesh.nodes.size(), 0);
  for (std::size_t e = 0; e < mesh.hexes.size(); ++e) {
    const Hex& h = mesh.hexes[e];
    const auto id = static_cast<std::int64_t>(e);
    for (int a = 0; a < 8; ++a) {
      if (h[a] < 0 || h[a] >= num_nodes)
        labels.fail_at_element(id, "refers to node id " + std::to_string(h[a]) + " out of range [0, " +
                                       std::to_string(num_nodes) + ")");
      for (int b = 0; b < a; ++b)
        if (h[a] == h[b])
          labels.fail_at_element(id, "uses " + labels.node(h[a]) + " twice (corners " + std::to_string(b) + " and " +
                                         std::to_string(a) + ")");
      used[h[a]] = 1;
    }
    check_element_jacobian(mesh, e, labels);
  }

  for (std::int64_t n = 0; n < num_nodes; ++n)
    if (!used[n]) labels.fail_at_node(n, "is not used by any element");

  for (const auto& [name, ids] : mesh.node_sets)
    for (std::size_t i = 0; i < ids.size(); ++i) {
      if (ids[i] < 0 || ids[i] >= num_nodes)
        labels.fail("node set '" + name + "' holds node id " + std::to_string(ids[i]) + " out of range [0, " +
                    std::to_string(num_nodes) + ")");
      if (i > 0 && ids[i] <= ids[i - 1])
        labels.fail("node set '" + name + "' is not sorted and unique (at position " + std::to_string(i) + ")");
    }
}

double bounding_box_diagonal(const HexMesh& mesh) {
  if (mesh.nodes.empty()) return 0;
  Vec3 lo = mesh.nodes.front(), hi = mesh.nodes.front();
  for (const Vec3& x : mesh.nodes)
    for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], x[i]), hi[i] = std::max(hi[i], x[i]);
  return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

}  // namespace dipc
