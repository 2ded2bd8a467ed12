// snap_to_surface (see surface_snapping.hpp).
#include "mesh/surface_snapping.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "math/vector3.hpp"
#include "mesh/boundary_faces.hpp"
#include "mesh/hex8_reference.hpp"
#include "mesh/mesh_error.hpp"

namespace dipc {

namespace {

Vec3 sub(const Vec3& a, const Vec3& b) {
  Vec3 c;
  subtract3(a.data(), b.data(), c.data());
  return c;
}
double dot(const Vec3& a, const Vec3& b) { return dot3(a.data(), b.data()); }
Vec3 axpy(const Vec3& p, double s, const Vec3& d) { return {p[0] + s * d[0], p[1] + s * d[1], p[2] + s * d[2]}; }

// Closest point to p on triangle (a, b, c), by the Voronoi regions of its vertices, edges and
// face (Ericson, "Real-Time Collision Detection", 2005, section 5.1.5).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return axpy(a, d1 / (d1 - d3), ab);
  const Vec3 cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return axpy(a, d2 / (d2 - d6), ac);
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return axpy(b, (d4 - d3) / ((d4 - d3) + (d5 - d6)), sub(c, b));
  const double denom = 1 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return {a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w};
}

// Triangles bucketed on a grid of cells of edge `size`: a triangle is listed in every bucket
// its bounding box overlaps, so every triangle within `size` of a point is in the 27 buckets
// around the point's own.
class TriangleBuckets {
 public:
  TriangleBuckets(const TriangleSurface& s, double size) : size_(size) {
    for (std::size_t t = 0; t < s.triangles.size(); ++t) {
      std::int64_t lo[3], hi[3];
      for (int d = 0; d < 3; ++d) {
        double mn = 1e300, mx = -1e300;
        for (int k = 0; k < 3; ++k) {
          mn = std::min(mn, s.vertices[s.triangles[t][k]][d]);
          mx = std::max(mx, s.vertices[s.triangles[t][k]][d]);
        }
        lo[d] = cell(mn), hi[d] = cell(mx);
      }
      for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
        for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
          for (std::int64_t k = lo[2]; k <= hi[2]; ++k) buckets_[key(i, j, k)].push_back(static_cast<std::int64_t>(t));
    }
  }
  // Calls f(t) for each triangle in the buckets around p (a triangle may come more than once).
  template <class F>
  void around(const Vec3& p, F&& f) const {
    const std::int64_t c[3] = {cell(p[0]), cell(p[1]), cell(p[2])};
    for (std::int64_t i = c[0] - 1; i <= c[0] + 1; ++i)
      for (std::int64_t j = c[1] - 1; j <= c[1] + 1; ++j)
        for (std::int64_t k = c[2] - 1; k <= c[2] + 1; ++k) {
          const auto it = buckets_.find(key(i, j, k));
          if (it == buckets_.end()) continue;
          for (std::int64_t t : it->second) f(t);
        }
  }

 private:
  std::int64_t cell(double x) const { return static_cast<std::int64_t>(std::floor(x / size_)); }
  // 21 bits per axis: bucket indices within ±2^20 of the origin, plenty for models whose
  // extent is a few hundred cells.
  static std::uint64_t key(std::int64_t i, std::int64_t j, std::int64_t k) {
    const auto bits = [](std::int64_t v) { return static_cast<std::uint64_t>(v + (1 << 20)) & 0x1FFFFF; };
    return bits(i) | bits(j) << 21 | bits(k) << 42;
  }
  double size_;
  std::unordered_map<std::uint64_t, std::vector<std::int64_t>> buckets_;
};

double min_det(const HexMesh& mesh, const std::vector<Vec3>& x, std::size_t e) {
  double X[24];
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i) X[3 * a + i] = x[mesh.hexes[e][a]][i];
  return hex8::min_jacobian_determinant(X);
}

}  // namespace

SnapStatistics snap_to_surface(HexMesh& mesh, const TriangleSurface& surface, double h, double min_det_ratio) {
  if (!(min_det_ratio > 0 && min_det_ratio < 1) || !(h > 0))
    throw MeshError(surface.source + ": snapping needs h > 0 and a det J ratio in (0, 1)");
  const double reach = std::sqrt(3.0) * h;
  const double floor_det = min_det_ratio * h * h * h / 8;

  std::vector<std::int64_t> boundary;
  for (const BoundaryFace& f : extract_boundary_faces(mesh))
    for (int c : hex_face_nodes(f.face)) boundary.push_back(mesh.hexes[f.element][c]);
  std::sort(boundary.begin(), boundary.end());
  boundary.erase(std::unique(boundary.begin(), boundary.end()), boundary.end());

  // The closest surface point of each boundary node, if one is within reach.
  const TriangleBuckets buckets(surface, reach);
  std::vector<Vec3> move(mesh.nodes.size(), Vec3{0, 0, 0});
  std::vector<double> fraction(mesh.nodes.size(), 0.0);
  SnapStatistics stats;
  stats.boundary_nodes = static_cast<std::int64_t>(boundary.size());
  for (std::int64_t v : boundary) {
    const Vec3& p = mesh.nodes[v];
    double best = reach * reach;
    Vec3 target = p;
    bool found = false;
    buckets.around(p, [&](std::int64_t t) {
      const Triangle& tri = surface.triangles[t];
      const Vec3 q = closest_point_on_triangle(p, surface.vertices[tri[0]], surface.vertices[tri[1]],
                                               surface.vertices[tri[2]]);
      const Vec3 d = sub(q, p);
      if (dot(d, d) <= best) best = dot(d, d), target = q, found = true;
    });
    if (found) {
      move[v] = sub(target, p);
      fraction[v] = 1;
    }
  }

  // Elements that touch a boundary node: the only ones a move can spoil.
  std::vector<char> is_boundary(mesh.nodes.size(), 0);
  for (std::int64_t v : boundary) is_boundary[v] = 1;
  std::vector<std::size_t> touched;
  for (std::size_t e = 0; e < mesh.hexes.size(); ++e)
    for (std::int64_t v : mesh.hexes[e])
      if (is_boundary[v]) {
        touched.push_back(e);
        break;
      }

  std::vector<Vec3> x = mesh.nodes;
  auto place = [&](std::int64_t v) { x[v] = axpy(mesh.nodes[v], fraction[v], move[v]); };
  for (std::int64_t v : boundary) place(v);
  // Halve moves around every element below the floor until none is: each round either finds
  // no such element or halves some move; a move below 1/64 becomes none, and with no moves
  // left around it an element is an undistorted cell again (det J = h^3/8).
  while (true) {
    std::vector<std::int64_t> shrink;
    for (std::size_t e : touched)
      if (min_det(mesh, x, e) < floor_det) {
        // The node that moved farthest: halving it alone spares the element's other nodes,
        // whose partial moves would in turn distort their other elements.
        std::int64_t far = -1;
        double longest = 0;
        for (std::int64_t v : mesh.hexes[e]) {
          const double d = fraction[v] * std::sqrt(dot(move[v], move[v]));
          if (fraction[v] > 0 && d >= longest) longest = d, far = v;
        }
        if (far >= 0) shrink.push_back(far);
      }
    if (shrink.empty()) break;
    std::sort(shrink.begin(), shrink.end());
    shrink.erase(std::unique(shrink.begin(), shrink.end()), shrink.end());
    for (std::int64_t v : shrink) {
      fraction[v] = fraction[v] > 1.0 / 64 ? 0.5 * fraction[v] : 0.0;
      place(v);
    }
  }

  double worst = 1e300;
  for (std::size_t e : touched) worst = std::min(worst, min_det(mesh, x, e));
  stats.min_det_ratio = touched.empty() ? 1.0 : worst / (h * h * h / 8);
  for (std::int64_t v : boundary) {
    if (fraction[v] == 1)
      ++stats.moved;
    else if (fraction[v] > 0)
      ++stats.backed_off;
    else
      ++stats.not_moved;
  }
  mesh.nodes = std::move(x);
  return stats;
}

}  // namespace dipc
