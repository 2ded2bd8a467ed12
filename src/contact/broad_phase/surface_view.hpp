// SurfaceView: the non-owning description of a triangulated contact surface (positions,
// edges, triangles, a group per vertex) that the broad phase searches.
#pragma once
#include <cstdint>

namespace dipc::contact {

struct SurfaceView {
  int num_vertices = 0;
  const double* x0 = nullptr;  // 3 coordinates per vertex
  const double* x1 = nullptr;  // end positions for swept boxes; nullptr: static boxes at x0
  int num_edges = 0;
  const std::int32_t* edges = nullptr;  // 2 vertex ids per edge
  int num_faces = 0;
  const std::int32_t* faces = nullptr;         // 3 vertex ids per triangle
  const std::int32_t* vertex_group = nullptr;  // e.g. the body of each vertex; nullable
};

}  // namespace dipc::contact
