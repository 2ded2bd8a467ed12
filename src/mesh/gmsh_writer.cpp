// write_gmsh (see gmsh_writer.hpp). Layout: Gmsh reference manual, "MSH file format" (4.1):
// one model entity per group (surfaces 1..n) and one volume (tag 1) that holds every node.
#include "mesh/gmsh_writer.hpp"

#include <algorithm>
#include <charconv>
#include <fstream>

#include "mesh/mesh_error.hpp"

namespace dipc {

void write_gmsh(const std::string& path, const HexMesh& mesh, const std::string& volume_name,
                const std::vector<QuadGroup>& groups) {
  std::vector<std::string> names{volume_name};
  for (const QuadGroup& g : groups) names.push_back(g.name);
  for (const std::string& name : names)
    if (name.empty() || name.find('"') != std::string::npos)
      throw MeshError(path + ": physical group name '" + name + "' is empty or contains '\"'");
  std::ofstream out(path);
  if (!out) throw MeshError(path + ": cannot open the file for writing");
  out.precision(17);

  Vec3 lo{0, 0, 0}, hi{0, 0, 0};
  if (!mesh.nodes.empty()) {
    lo = hi = mesh.nodes[0];
    for (const Vec3& p : mesh.nodes)
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], p[d]);
        hi[d] = std::max(hi[d], p[d]);
      }
  }
  const std::size_t n = groups.size();
  out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  // Physical tags: the volume 1, surface group g has g + 1 (dimensions keep them apart).
  out << "$PhysicalNames\n" << n + 1 << "\n3 1 \"" << volume_name << "\"\n";
  for (std::size_t g = 0; g < n; ++g) out << "2 " << g + 1 << " \"" << groups[g].name << "\"\n";
  out << "$EndPhysicalNames\n";
  out << "$Entities\n0 0 " << n << " 1\n";
  for (std::size_t g = 0; g < n; ++g)
    out << g + 1 << " " << lo[0] << " " << lo[1] << " " << lo[2] << " " << hi[0] << " " << hi[1] << " " << hi[2]
        << " 1 " << g + 1 << " 0\n";
  out << "1 " << lo[0] << " " << lo[1] << " " << lo[2] << " " << hi[0] << " " << hi[1] << " " << hi[2] << " 1 1 " << n;
  for (std::size_t g = 0; g < n; ++g) out << " " << g + 1;
  out << "\n$EndEntities\n";

  const std::size_t nn = mesh.nodes.size();
  out << "$Nodes\n1 " << nn << " 1 " << nn << "\n3 1 0 " << nn << "\n";
  for (std::size_t i = 0; i < nn; ++i) out << i + 1 << "\n";
  // Shortest text that reads back as the same double (std::to_chars), and much faster than
  // an ostream at 17 digits on meshes of a million nodes.
  char line[3 * 32];
  for (const Vec3& p : mesh.nodes) {
    char* end = line;
    for (int d = 0; d < 3; ++d) {
      end = std::to_chars(end, line + sizeof line, p[d]).ptr;
      *end++ = d < 2 ? ' ' : '\n';
    }
    out.write(line, end - line);
  }
  out << "$EndNodes\n";

  std::size_t total = mesh.hexes.size();
  for (const QuadGroup& g : groups) total += g.quads.size();
  out << "$Elements\n" << n + 1 << " " << total << " 1 " << total << "\n";
  std::size_t tag = 1;
  for (std::size_t g = 0; g < n; ++g) {
    out << "2 " << g + 1 << " 3 " << groups[g].quads.size() << "\n";
    for (const auto& q : groups[g].quads)
      out << tag++ << " " << q[0] + 1 << " " << q[1] + 1 << " " << q[2] + 1 << " " << q[3] + 1 << "\n";
  }
  out << "3 1 5 " << mesh.hexes.size() << "\n";
  for (const Hex& h : mesh.hexes) {
    out << tag++;
    for (std::int64_t v : h) out << " " << v + 1;
    out << "\n";
  }
  out << "$EndElements\n";
  if (!out) throw MeshError(path + ": write error");
}

}  // namespace dipc
