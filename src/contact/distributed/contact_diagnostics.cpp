// ContactSet's diagnostics (contact_set.hpp): the closest pair and the edge–triangle crossings
// with the names of what they involve (the initial-state check, -dipc_check_invariants and
// error messages).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "contact/broad_phase/bvh.hpp"
#include "contact/contact_pair_terms.hpp"
#include "contact/distributed/contact_set.hpp"
#include "contact/segment_triangle.hpp"
#include "math/aabb.hpp"
#include "threads/host_threads.hpp"

namespace dipc {

std::string ContactSet::body_label(int b) const {
  return b >= 0 && b < static_cast<int>(parameters_.body_names.size()) ? "\"" + parameters_.body_names[b] + "\""
                                                                       : std::to_string(b);
}

std::string ContactSet::node_label(std::int32_t n) const {
  return n < mesh_.num_local_nodes() ? "node " + std::to_string(mesh_.node_input_id[n])
                                     : "node (global " + std::to_string(global_node(n)) + ")";
}

// Obstacle primitives by their index in their obstacle (triangles in the file's order, after
// polygons are split into triangles; vertices after equal ones are merged).
std::string ContactSet::obstacle_vertex_label(std::int32_t v) const {
  const int o = obstacles_.vertex_obstacle[v];
  return "vertex " + std::to_string(v - obstacles_.first_vertex[o]) + " of obstacle \"" +
         parameters_.obstacles[o].name + "\"";
}

std::string ContactSet::obstacle_face_label(std::int32_t f) const {
  const int o = obstacles_.face_obstacle[f];
  const auto& ob = parameters_.obstacles[o];
  const std::size_t t = static_cast<std::size_t>(f - obstacles_.first_face[o]);
  std::string where = ob.source;
  if (t < ob.triangle_origin.size())
    where += (ob.binary_origin ? ": facet " : ":") + std::to_string(ob.triangle_origin[t]);
  return "triangle " + std::to_string(t) + " of obstacle \"" + ob.name + "\" (" + where + ")";
}

std::string ContactSet::obstacle_edge_label(std::int32_t e) const {
  const int o = obstacles_.edge_obstacle[e];
  const std::int32_t base = obstacles_.first_vertex[o];
  return "edge (vertex " + std::to_string(obstacles_.edges[e][0] - base) + ", vertex " +
         std::to_string(obstacles_.edges[e][1] - base) + ") of obstacle \"" + parameters_.obstacles[o].name + "\"";
}

std::string ContactSet::closest_pair(const double* x) const {
  struct {
    double distance;
    int rank;
  } mine{std::numeric_limits<double>::infinity(), rank_}, closest;
  CandidateKind closest_kind = CandidateKind::vertex_face;
  std::size_t closest_index = 0;
  for_each_pair([&](CandidateKind kind, std::size_t i) {
    const PairInfo info = describe(kind, i);
    double X[12];
    gather(x, info, X);
    const double d = std::sqrt(contact_pair_squared_distance(info.kind, X, info.plane_point(), info.plane_normal()));
    if (d < mine.distance) mine.distance = d, closest_kind = kind, closest_index = i;
    return true;
  });
  MPI_Allreduce(&mine, &closest, 1, MPI_DOUBLE_INT, MPI_MINLOC, comm_);
  if (closest.distance == std::numeric_limits<double>::infinity()) return "";
  std::string text;
  if (closest.rank == rank_) {
    const std::size_t i = closest_index;
    auto vertex_body = [&](std::int32_t node) {
      const auto it = std::find(surface_.vertices.begin(), surface_.vertices.end(), node);
      return it == surface_.vertices.end() ? -1 : surface_.vertex_body[it - surface_.vertices.begin()];
    };
    auto primitive = [&](const char* what, const Primitive& p, int nodes) {
      std::string s = std::string(what) + " (";
      for (int k = 0; k < nodes; ++k) s += (k ? ", " : "") + node_label(p.node[k]);
      return s + ") of body " + body_label(p.body);
    };
    switch (closest_kind) {
      case CandidateKind::vertex_face: {
        const std::int32_t v = vertex_face_[i][0];
        text = node_label(v) + " of body " + body_label(vertex_body(v)) + " and " +
               primitive("triangle", faces_[vertex_face_[i][1]], 3);
        break;
      }
      case CandidateKind::edge_edge:
        text = primitive("edge", edges_[edge_edge_[i][0]], 2) + " and " +
               primitive("edge", edges_[edge_edge_[i][1]], 2);
        break;
      case CandidateKind::vertex_plane: {
        const std::int32_t v = vertex_plane_[i][0];
        const auto& point = parameters_.planes[vertex_plane_[i][1]].point;
        text = node_label(v) + " of body " + body_label(vertex_body(v)) + " and the plane through (" +
               std::to_string(point[0]) + ", " + std::to_string(point[1]) + ", " + std::to_string(point[2]) + ")";
        break;
      }
      case CandidateKind::vertex_obstacle_face: {
        const std::int32_t v = vertex_obstacle_face_[i][0];
        text = node_label(v) + " of body " + body_label(vertex_body(v)) + " and " +
               obstacle_face_label(vertex_obstacle_face_[i][1]);
        break;
      }
      case CandidateKind::edge_obstacle_edge:
        text = primitive("edge", edges_[edge_obstacle_edge_[i][0]], 2) + " and " +
               obstacle_edge_label(edge_obstacle_edge_[i][1]);
        break;
      case CandidateKind::obstacle_vertex_face:
        text = obstacle_vertex_label(obstacle_vertex_face_[i][0]) + " and " +
               primitive("triangle", faces_[obstacle_vertex_face_[i][1]], 3);
        break;
    }
    char distance[32];
    std::snprintf(distance, sizeof distance, ", %g apart", closest.distance);
    text += distance;
  }
  int length = static_cast<int>(text.size());
  MPI_Bcast(&length, 1, MPI_INT, closest.rank, comm_);
  text.resize(length);
  MPI_Bcast(text.data(), length, MPI_CHAR, closest.rank, comm_);
  return text;
}

long ContactSet::count_intersections(const double* x, std::string* first) const {
  // Each edge meets only the triangles whose boxes overlap its own, found in a BVH of the
  // triangle boxes (a sweep along x alone visits whole faces of a box-shaped surface per edge,
  // quadratic in the surface). The crossing reported is that of the first edge with one, and of
  // its triangles the one with the lowest (box's lower x, index), so that it does not depend on
  // the tree; it is picked as the edges are visited (sorting every edge's overlaps by that key
  // took most of the 0.2 s this check cost at setup for a 1M-hex cube's 180K surface edges).
  std::vector<Aabb> face_box(faces_.size());
  parallel_for(faces_.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      face_box[f] = aabb_empty();
      for (int k = 0; k < 3; ++k) aabb_add_point(&face_box[f], x + 3 * faces_[f].node[k]);
    }
  });
  const contact::Bvh tree(face_box);
  const auto before = [&face_box](std::size_t f, std::size_t g) {
    return face_box[f].lo[0] != face_box[g].lo[0] ? face_box[f].lo[0] < face_box[g].lo[0] : f < g;
  };
  // The edges in chunks on the host threads; a chunk's first crossing is that of its first edge
  // with one, so the lowest chunk with a crossing holds the first overall.
  struct Found {
    long count = 0;
    std::size_t edge = 0, face = 0;
  };
  std::vector<Found> found(static_cast<std::size_t>(host_threads()));
  parallel_chunks(
      owned_edges_,
      [&](int chunk, std::size_t begin, std::size_t end) {
        Found& mine = found[static_cast<std::size_t>(chunk)];
        for (std::size_t e = begin; e < end; ++e) {
          const Primitive& edge = edges_[e];
          Aabb eb = aabb_empty();
          aabb_add_point(&eb, x + 3 * edge.node[0]);
          aabb_add_point(&eb, x + 3 * edge.node[1]);
          tree.for_each_overlap(eb, [&](std::int32_t fi) {
            const std::size_t f = static_cast<std::size_t>(fi);
            const Primitive& face = faces_[f];
            for (int a = 0; a < 2; ++a)
              for (int b = 0; b < 3; ++b)
                if (edge.node[a] == face.node[b]) return;
            if (!segment_crosses_triangle(x + 3 * edge.node[0], x + 3 * edge.node[1], x + 3 * face.node[0],
                                          x + 3 * face.node[1], x + 3 * face.node[2]))
              return;
            if (mine.count++ == 0)
              mine.edge = e, mine.face = f;
            else if (e == mine.edge && before(f, mine.face))
              mine.face = f;
          });
        }
      },
      256);
  long count = 0;
  std::size_t first_edge = 0, first_face = 0;
  for (const Found& chunk : found) {
    if (count == 0 && chunk.count > 0) first_edge = chunk.edge, first_face = chunk.face;
    count += chunk.count;
  }
  if (count > 0 && first) {
    const Primitive &edge = edges_[first_edge], &face = faces_[first_face];
    *first = "edge (" + node_label(edge.node[0]) + ", " + node_label(edge.node[1]) + ") of body " +
             body_label(edge.body) + " crosses triangle (" + node_label(face.node[0]) + ", " +
             node_label(face.node[1]) + ", " + node_label(face.node[2]) + ") of body " + body_label(face.body);
  }
  count += count_obstacle_intersections(x, count == 0 ? first : nullptr);
  for (std::size_t i = 0; i < surface_.vertices.size(); ++i)
    for (const auto& plane : parameters_.planes) {
      const std::int32_t v = surface_.vertices[i];
      if (contact_plane_offset(x + 3 * v, plane.point.data(), plane.normal.data()) > 0) continue;
      if (count++ == 0 && first)
        *first = node_label(v) + " of body " + body_label(surface_.vertex_body[i]) +
                 " is on or behind the plane through (" + std::to_string(plane.point[0]) + ", " +
                 std::to_string(plane.point[1]) + ", " + std::to_string(plane.point[2]) + ")";
    }
  return count;
}

// Owned body edges against obstacle triangles, and obstacle edges against owned body triangles
// (each crossing counted by the owner of its body primitive), by sweep and prune on x.
long ContactSet::count_obstacle_intersections(const double* x, std::string* first) const {
  if (obstacles_.empty()) return 0;
  auto box_of = [&](const std::int32_t* nodes, int count) {
    Aabb b = aabb_empty();
    for (int k = 0; k < count; ++k) aabb_add_point(&b, position(x, nodes[k]));
    return b;
  };
  auto sorted_by_x = [](const std::vector<Aabb>& boxes) {
    std::vector<std::pair<double, std::size_t>> by_x;
    for (std::size_t i = 0; i < boxes.size(); ++i) by_x.emplace_back(boxes[i].lo[0], i);
    std::sort(by_x.begin(), by_x.end());
    return by_x;
  };
  long count = 0;
  auto crossing = [&](const std::int32_t* e, const std::int32_t* t) {
    return segment_crosses_triangle(position(x, e[0]), position(x, e[1]), position(x, t[0]), position(x, t[1]),
                                    position(x, t[2]));
  };
  // Body edges against obstacle triangles.
  std::vector<std::array<std::int32_t, 3>> tri(obstacles_.faces.size());
  std::vector<Aabb> tri_box(tri.size());
  for (std::size_t f = 0; f < tri.size(); ++f) {
    for (int k = 0; k < 3; ++k) tri[f][k] = obstacle_node(obstacles_.faces[f][k]);
    tri_box[f] = box_of(tri[f].data(), 3);
  }
  const auto tri_by_x = sorted_by_x(tri_box);
  for (std::size_t e = 0; e < owned_edges_; ++e) {
    const std::int32_t edge[2] = {edges_[e].node[0], edges_[e].node[1]};
    const Aabb eb = box_of(edge, 2);
    for (const auto& [fx, f] : tri_by_x) {
      if (fx > eb.hi[0]) break;
      if (!aabbs_overlap(eb, tri_box[f]) || !crossing(edge, tri[f].data())) continue;
      if (count++ == 0 && first)
        *first = "edge (" + node_label(edge[0]) + ", " + node_label(edge[1]) + ") of body " +
                 body_label(edges_[e].body) + " crosses " + obstacle_face_label(static_cast<std::int32_t>(f));
    }
  }
  // Obstacle edges against owned body triangles.
  std::vector<Aabb> face_box(owned_faces_);
  for (std::size_t f = 0; f < owned_faces_; ++f) face_box[f] = box_of(faces_[f].node.data(), 3);
  const auto face_by_x = sorted_by_x(face_box);
  for (std::size_t e = 0; e < obstacles_.edges.size(); ++e) {
    const std::int32_t edge[2] = {obstacle_node(obstacles_.edges[e][0]), obstacle_node(obstacles_.edges[e][1])};
    const Aabb eb = box_of(edge, 2);
    for (const auto& [fx, f] : face_by_x) {
      if (fx > eb.hi[0]) break;
      if (!aabbs_overlap(eb, face_box[f]) || !crossing(edge, faces_[f].node.data())) continue;
      if (count++ == 0 && first)
        *first = obstacle_edge_label(static_cast<std::int32_t>(e)) + " crosses triangle (" +
                 node_label(faces_[f].node[0]) + ", " + node_label(faces_[f].node[1]) + ", " +
                 node_label(faces_[f].node[2]) + ") of body " + body_label(faces_[f].body);
    }
  }
  return count;
}

}  // namespace dipc
