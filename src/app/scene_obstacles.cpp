#include "app/scene_obstacles.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "app/problem_builder.hpp"
#include "io/bounding_box_scale.hpp"
#include "mesh/triangle_surface_reader.hpp"

namespace dipc {

namespace {

// Reads and places one obstacle (rank 0).
void read_obstacle(const Scene& scene, const Obstacle& o, ContactParameters::Obstacle* out) {
  const std::string where = scene.source + ": " + o.key_path + ".mesh: ";
  TriangleSurface surface;
  try {
    surface = read_triangle_surface(o.mesh_file);
  } catch (const std::exception& e) {
    throw SceneError(where + e.what());
  }
  if (surface.vertices.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max() / 2))
    throw SceneError(where + o.mesh_file + ": too many vertices (" + std::to_string(surface.vertices.size()) + ")");
  std::array<double, 3> f;  // PolyFEM's transformation.dimensions; 1 (exact) without
  try {
    f = dimension_factors(o.dimensions, surface.vertices);
  } catch (const std::invalid_argument& e) {
    throw SceneError(scene.source + ": " + o.key_path + ".transformation.dimensions: " + e.what());
  }
  for (std::size_t v = 0; v < surface.vertices.size(); ++v) {
    const std::array<double, 3> F{f[0] * surface.vertices[v][0], f[1] * surface.vertices[v][1],
                                  f[2] * surface.vertices[v][2]};
    std::array<double, 3> X;
    for (int c = 0; c < 3; ++c)
      X[c] = o.scale * (o.linear[3 * c] * F[0] + o.linear[3 * c + 1] * F[1] + o.linear[3 * c + 2] * F[2]) +
             o.translation[c];
    if (!std::isfinite(X[0]) || !std::isfinite(X[1]) || !std::isfinite(X[2]))
      throw SceneError(where + o.mesh_file + ": vertex " + std::to_string(v) + " is not finite once placed");
    out->rest.push_back(X);
  }
  out->triangle_origin = surface.triangle_origin;
  out->binary_origin = surface.binary;
  for (const Triangle& t : surface.triangles)
    out->triangles.push_back(
        {static_cast<std::int32_t>(t[0]), static_cast<std::int32_t>(t[1]), static_cast<std::int32_t>(t[2])});
}

}  // namespace

std::vector<ContactParameters::Obstacle> load_scene_obstacles(const Scene& scene, MPI_Comm comm) {
  int rank;
  MPI_Comm_rank(comm, &rank);
  std::vector<ContactParameters::Obstacle> obstacles(scene.contact.obstacles.size());
  std::string error;
  if (rank == 0) {
    try {
      for (std::size_t i = 0; i < obstacles.size(); ++i)
        read_obstacle(scene, scene.contact.obstacles[i], &obstacles[i]);
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  int length = static_cast<int>(error.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, comm);
  error.resize(length);
  MPI_Bcast(error.data(), length, MPI_CHAR, 0, comm);
  if (length > 0) throw SceneError(error);
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    const Obstacle& o = scene.contact.obstacles[i];
    ContactParameters::Obstacle& out = obstacles[i];
    out.name = o.name;
    out.source = o.mesh_file;
    out.motion = prescribed_motion(o.motion);
    long long counts[2] = {static_cast<long long>(out.rest.size()), static_cast<long long>(out.triangles.size())};
    MPI_Bcast(counts, 2, MPI_LONG_LONG, 0, comm);
    out.rest.resize(counts[0]);
    out.triangles.resize(counts[1]);
    MPI_Bcast(out.rest.data(), static_cast<int>(3 * counts[0]), MPI_DOUBLE, 0, comm);
    MPI_Bcast(out.triangles.data(), static_cast<int>(3 * counts[1]), MPI_INT32_T, 0, comm);
    out.triangle_origin.resize(counts[1]);
    MPI_Bcast(out.triangle_origin.data(), static_cast<int>(counts[1]), MPI_INT64_T, 0, comm);
    int binary = out.binary_origin ? 1 : 0;
    MPI_Bcast(&binary, 1, MPI_INT, 0, comm);
    out.binary_origin = binary != 0;
  }
  return obstacles;
}

}  // namespace dipc
