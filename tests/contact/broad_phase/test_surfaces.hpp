// Surfaces the broad-phase tests search: the triangulated boundary of a subdivided cube and
// random triangle soups with shared vertices, isolated vertices and mixed triangle sizes.
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "contact/broad_phase/surface_view.hpp"

namespace dipc::contact::testing {

struct TestSurface {
  std::vector<double> x0;
  std::vector<double> x1;  // empty: static
  std::vector<std::int32_t> edges;
  std::vector<std::int32_t> faces;
  std::vector<std::int32_t> groups;  // empty: none

  int num_vertices() const { return static_cast<int>(x0.size() / 3); }
  SurfaceView view() const {
    SurfaceView s;
    s.num_vertices = num_vertices();
    s.x0 = x0.data();
    s.x1 = x1.empty() ? nullptr : x1.data();
    s.num_edges = static_cast<int>(edges.size() / 2);
    s.edges = edges.data();
    s.num_faces = static_cast<int>(faces.size() / 3);
    s.faces = faces.data();
    s.vertex_group = groups.empty() ? nullptr : groups.data();
    return s;
  }
};

// The unique edges of a triangle list, each as (smaller id, larger id), sorted.
inline std::vector<std::int32_t> edges_of_faces(const std::vector<std::int32_t>& faces) {
  std::vector<std::array<std::int32_t, 2>> e;
  for (std::size_t f = 0; f + 2 < faces.size(); f += 3) {
    for (int j = 0; j < 3; ++j) {
      const std::int32_t a = faces[f + j];
      const std::int32_t b = faces[f + (j + 1) % 3];
      e.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  std::sort(e.begin(), e.end());
  e.erase(std::unique(e.begin(), e.end()), e.end());
  std::vector<std::int32_t> flat;
  for (const auto& p : e) {
    flat.push_back(p[0]);
    flat.push_back(p[1]);
  }
  return flat;
}

// Boundary of the cube [origin, origin + size]^3 cut into n^3 cells: the lattice points with
// an index 0 or n, two triangles per boundary quad. Lattice coordinates repeat exactly, so
// many boxes touch without overlapping: the closed-box rule is exercised.
inline TestSurface cube_boundary(int n, double size, const std::array<double, 3>& origin, std::int32_t group = 0) {
  TestSurface s;
  std::vector<std::int32_t> id((n + 1) * (n + 1) * (n + 1), -1);
  auto lattice = [n](int i, int j, int k) { return i + (n + 1) * (j + (n + 1) * k); };
  for (int k = 0; k <= n; ++k) {
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        if (i != 0 && i != n && j != 0 && j != n && k != 0 && k != n) continue;
        id[lattice(i, j, k)] = s.num_vertices();
        s.x0.push_back(origin[0] + size * i / n);
        s.x0.push_back(origin[1] + size * j / n);
        s.x0.push_back(origin[2] + size * k / n);
      }
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    for (int side : {0, n}) {
      for (int v = 0; v < n; ++v) {
        for (int u = 0; u < n; ++u) {
          std::array<std::int32_t, 4> q;
          const int du[4] = {0, 1, 1, 0};
          const int dv[4] = {0, 0, 1, 1};
          for (int c = 0; c < 4; ++c) {
            int ijk[3];
            ijk[axis] = side;
            ijk[(axis + 1) % 3] = u + du[c];
            ijk[(axis + 2) % 3] = v + dv[c];
            q[c] = id[lattice(ijk[0], ijk[1], ijk[2])];
          }
          s.faces.insert(s.faces.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
        }
      }
    }
  }
  s.edges = edges_of_faces(s.faces);
  s.groups.assign(s.num_vertices(), group);
  return s;
}

// A soup on the unit cube: a jittered m^3 lattice of vertices (some never used), triangles
// made of 3 distinct corners of a random lattice cell (so neighbouring triangles share
// vertices and edges), and a few larger free-standing triangles with vertices of their own.
inline TestSurface random_soup(unsigned seed, int m, int num_local, int num_free) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double h = 1.0 / m;
  TestSurface s;
  for (int k = 0; k <= m; ++k) {
    for (int j = 0; j <= m; ++j) {
      for (int i = 0; i <= m; ++i) {
        s.x0.push_back((i + 0.6 * (unit(rng) - 0.5)) * h);
        s.x0.push_back((j + 0.6 * (unit(rng) - 0.5)) * h);
        s.x0.push_back((k + 0.6 * (unit(rng) - 0.5)) * h);
      }
    }
  }
  std::uniform_int_distribution<int> cell(0, m - 1);
  std::uniform_int_distribution<int> corner(0, 7);
  for (int t = 0; t < num_local; ++t) {
    const int ci = cell(rng), cj = cell(rng), ck = cell(rng);
    std::array<int, 3> c = {corner(rng), corner(rng), corner(rng)};
    while (c[1] == c[0]) c[1] = corner(rng);
    while (c[2] == c[0] || c[2] == c[1]) c[2] = corner(rng);
    for (int corner_id : c) {
      const int i = ci + (corner_id & 1), j = cj + ((corner_id >> 1) & 1), k = ck + (corner_id >> 2);
      s.faces.push_back(i + (m + 1) * (j + (m + 1) * k));
    }
  }
  for (int t = 0; t < num_free; ++t) {
    const double cx = unit(rng), cy = unit(rng), cz = unit(rng);
    const double r = 3.0 * h * unit(rng);
    for (int c = 0; c < 3; ++c) {
      s.faces.push_back(s.num_vertices());
      s.x0.push_back(cx + r * (unit(rng) - 0.5));
      s.x0.push_back(cy + r * (unit(rng) - 0.5));
      s.x0.push_back(cz + r * (unit(rng) - 0.5));
    }
  }
  s.edges = edges_of_faces(s.faces);
  return s;
}

// End positions x0 + a random displacement of at most `amplitude` per coordinate.
inline std::vector<double> randomly_moved(const std::vector<double>& x0, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-amplitude, amplitude);
  std::vector<double> x1 = x0;
  for (double& c : x1) c += d(rng);
  return x1;
}

}  // namespace dipc::contact::testing
