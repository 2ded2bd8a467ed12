// ObstacleSurface: the triangle-mesh obstacles of a scene as one contact surface whose positions
// are prescribed functions of time (ContactParameters::Obstacle), for ContactForm.
//
// Distribution. Every rank holds every obstacle whole (read once on rank 0 and broadcast), and a
// pair of an obstacle primitive with a body primitive is evaluated by the rank that owns the body
// primitive: body vertex–obstacle triangle by the vertex's owner, body edge–obstacle edge by the
// edge's owner, obstacle vertex–body triangle by the triangle's owner. Each body primitive is
// owned once (partition/contact_surface.hpp), so each pair is counted once and no obstacle data
// travels between ranks. A rank's pair work is that of its own surface: its broad phase takes
// only the obstacle primitives near the rank's swept surface box (near()), found by one linear
// pass over the obstacle per search. The costs that grow with the obstacle rather than with the
// rank's share are that pass and the obstacle's memory on every rank (about 150 bytes per
// triangle): fine for floors, funnels and rollers of up to a few 10⁵ triangles; an obstacle far
// larger would want its own BVH (or a partition by space) instead. A ContactForm on the device
// keeps the positions there too and gives its broad phase every obstacle primitive (no
// culling pass; the BVH over them is rebuilt per search with the body's).
//
// Node ids. ContactForm's pairs name body nodes by ext-local id (>= 0); obstacle vertex k is
// named -2 - k (obstacle_node, obstacle_nodes.hpp), so -1 keeps meaning "unused slot". Obstacle
// nodes have no unknowns: forms skip them in gradients and take only the body nodes' blocks of
// pair Hessians (the potential is a function of the body positions, the obstacle's being
// constants).
//
// Time. Evaluations see the obstacles at one time (end()); a segment x + αp of the body may come
// with an obstacle segment from start() to end() (linear in between, as IPC's CCD assumes for
// every trajectory), which the broad phase and CCD follow; step_start() keeps the positions at
// the start of the time step for friction's relative sliding.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "contact/distributed/contact_parameters.hpp"
#include "contact/obstacle_nodes.hpp"
#include "math/aabb.hpp"

namespace dipc {

class ObstacleSurface {
 public:
  ObstacleSurface() = default;
  explicit ObstacleSurface(const std::vector<ContactParameters::Obstacle>& obstacles);
  bool empty() const { return faces.empty(); }
  int num_vertices() const { return static_cast<int>(vertex_obstacle.size()); }

  // Connectivity (obstacle vertex ids, all obstacles numbered one after the other).
  std::vector<std::array<std::int32_t, 2>> edges;  // each undirected edge once
  std::vector<std::array<std::int32_t, 3>> faces;
  std::vector<int> vertex_obstacle, edge_obstacle, face_obstacle;  // which obstacle
  std::vector<std::int32_t> first_vertex, first_face;              // per obstacle: its first ids (messages)
  std::vector<double> vertex_area;        // ⅓ of the incident rest triangle areas (barrier weight)
  std::vector<double> edge_rest_length2;  // squared rest length (edge–edge mollifier)

  // Places the obstacles: the segment from time t0 to t1 (start() and end()).
  void move(const std::vector<ContactParameters::Obstacle>& obstacles, double t0, double t1);
  // The positions at the segment's end become those of the step's start (friction).
  void mark_step_start() { step_start_ = end_; }
  const double* start(std::int32_t v) const { return &start_[3 * static_cast<std::size_t>(v)]; }
  const double* end(std::int32_t v) const { return &end_[3 * static_cast<std::size_t>(v)]; }
  const double* step_start(std::int32_t v) const { return &step_start_[3 * static_cast<std::size_t>(v)]; }
  bool moving() const { return moving_; }

  // The primitives whose boxes over the segment reach `box` (min xyz, max xyz): vertices, edges
  // and faces (sorted ids), and every vertex that those edges and faces use.
  struct Near {
    std::vector<std::int32_t> vertices, edges, faces;
  };
  Near near(const Aabb& box) const;

 private:
  std::vector<double> start_, end_, step_start_;
  bool moving_ = false;
};

}  // namespace dipc
