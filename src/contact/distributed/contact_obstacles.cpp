#include "contact/distributed/contact_obstacles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "contact/broad_phase/aabb.hpp"
#include "math/vector3.hpp"

namespace dipc {

ObstacleSurface::ObstacleSurface(const std::vector<ContactParameters::Obstacle>& obstacles) {
  std::int32_t vertex_base = 0;
  for (std::size_t o = 0; o < obstacles.size(); ++o) {
    const auto& ob = obstacles[o];
    first_vertex.push_back(vertex_base);
    first_face.push_back(static_cast<std::int32_t>(faces.size()));
    const auto nv = static_cast<std::int32_t>(ob.rest.size());
    vertex_obstacle.insert(vertex_obstacle.end(), nv, static_cast<int>(o));
    vertex_area.insert(vertex_area.end(), nv, 0.0);
    // Each undirected edge once (open surfaces have boundary edges used by one triangle).
    std::map<std::pair<std::int32_t, std::int32_t>, int> seen;
    for (const auto& t : ob.triangles) {
      const auto& a = ob.rest[t[0]];
      const auto& b = ob.rest[t[1]];
      const auto& c = ob.rest[t[2]];
      double u[3], v[3], n[3];
      subtract3(b.data(), a.data(), u);
      subtract3(c.data(), a.data(), v);
      cross3(u, v, n);
      const double area = 0.5 * std::sqrt(squared_norm3(n));
      for (int k = 0; k < 3; ++k) vertex_area[vertex_base + t[k]] += area / 3.0;
      faces.push_back({vertex_base + t[0], vertex_base + t[1], vertex_base + t[2]});
      face_obstacle.push_back(static_cast<int>(o));
      for (int k = 0; k < 3; ++k) {
        const std::int32_t p = t[k], q = t[(k + 1) % 3];
        if (!seen.emplace(std::make_pair(std::min(p, q), std::max(p, q)), 0).second) continue;
        edges.push_back({vertex_base + std::min(p, q), vertex_base + std::max(p, q)});
        edge_obstacle.push_back(static_cast<int>(o));
        double l2 = 0;
        for (int c = 0; c < 3; ++c) l2 += (ob.rest[p][c] - ob.rest[q][c]) * (ob.rest[p][c] - ob.rest[q][c]);
        edge_rest_length2.push_back(l2);
      }
    }
    vertex_base += nv;
  }
  move(obstacles, 0.0, 0.0);
  mark_step_start();
}

void ObstacleSurface::move(const std::vector<ContactParameters::Obstacle>& obstacles, double t0, double t1) {
  start_.resize(3 * vertex_obstacle.size());
  end_.resize(3 * vertex_obstacle.size());
  std::size_t v = 0;
  for (const auto& ob : obstacles)
    for (const auto& X : ob.rest) {
      const auto a = ob.motion.position(X, t0);
      const auto b = ob.motion.position(X, t1);
      for (int c = 0; c < 3; ++c) start_[3 * v + c] = a[c], end_[3 * v + c] = b[c];
      ++v;
    }
  moving_ = start_ != end_;
}

ObstacleSurface::Near ObstacleSurface::near(const Aabb& box) const {
  Near out;
  auto reaches = [&](const std::int32_t* ids, int count) {
    return aabbs_overlap(contact::primitive_box(start_.data(), end_.data(), ids, count, 0.0), box);
  };
  std::vector<char> used(vertex_obstacle.size(), 0);
  for (std::int32_t v = 0; v < num_vertices(); ++v)
    if (reaches(&v, 1)) used[v] = 1;
  for (std::size_t e = 0; e < edges.size(); ++e)
    if (reaches(edges[e].data(), 2)) {
      out.edges.push_back(static_cast<std::int32_t>(e));
      used[edges[e][0]] = used[edges[e][1]] = 1;
    }
  for (std::size_t f = 0; f < faces.size(); ++f)
    if (reaches(faces[f].data(), 3)) {
      out.faces.push_back(static_cast<std::int32_t>(f));
      for (std::int32_t v : faces[f]) used[v] = 1;
    }
  for (std::int32_t v = 0; v < num_vertices(); ++v)
    if (used[v]) out.vertices.push_back(v);
  return out;
}

}  // namespace dipc
