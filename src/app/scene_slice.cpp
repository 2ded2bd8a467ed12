// build_scene_slice and check_file_elements (see scene_slice.hpp).
#include "app/scene_slice.hpp"

#include <algorithm>
#include <climits>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>

#include "io/bounding_box_scale.hpp"
#include "io/collective_error.hpp"
#include "io/mesh_file.hpp"
#include "mesh/boundary_faces.hpp"
#include "mesh/box_generator.hpp"
#include "mesh/gmsh_reader.hpp"
#include "mesh/mesh_checks.hpp"
#include "mesh/mesh_error.hpp"
#include "mesh/nested_bodies.hpp"
#include "partition/mpi_exchange.hpp"
#include "threads/host_threads.hpp"

namespace dipc {
namespace {

// PolyFEM's surface selections (Body::face_selections) as node sets of `part` (one body):
// each boundary face takes the id of the first selection holding its centroid (the mean of
// its 4 corners), and "<body>.surface_selection_<id>" collects the nodes of the faces with
// that id. Every id the body declares gets a set, empty when no face took it; the Dirichlet
// check then reports a condition that selects no node.
void add_face_selection_sets(const Body& body, const std::string& source, HexMesh& part) {
  if (body.face_selections.empty()) return;
  std::map<int, std::set<std::int64_t>> nodes_of_id;
  for (const FaceSelection& s : body.face_selections) nodes_of_id[s.id];
  for (const BoundaryFace& f : extract_boundary_faces(part)) {
    const std::array<int, 4> local = hex_face_nodes(f.face);
    Vec3 centroid{0, 0, 0};
    for (int k : local)
      for (int c = 0; c < 3; ++c) centroid[c] += 0.25 * part.nodes[part.hexes[f.element][k]][c];
    for (const FaceSelection& s : body.face_selections) {
      bool inside = true;
      if (s.box)
        for (int c = 0; c < 3; ++c) inside = inside && centroid[c] >= (*s.box)[c] && centroid[c] <= (*s.box)[3 + c];
      if (!inside) continue;
      for (int k : local) nodes_of_id[s.id].insert(part.hexes[f.element][k]);
      break;
    }
  }
  for (const auto& [id, nodes] : nodes_of_id) {
    const std::string name = body.name + ".surface_selection_" + std::to_string(id);
    if (part.node_sets.count(name))
      throw MeshError(source + ": body \"" + body.name + "\": its mesh already has a selection named \"" + name + "\"");
    part.node_sets[name] = std::vector<std::int64_t>(nodes.begin(), nodes.end());
  }
}

// A body built whole on rank 0 (a Gmsh file, or a box with PolyFEM surface selections, which
// need the body's boundary faces): placed (x = scale·(linear·diag(f)·X) + translation for a file,
// f from Body::dimensions and the file's bounding box, known only here), its
// node sets named "<body>.<set>", "<body>" for all its nodes, and the surface selections.
HexMesh whole_body(const Scene& scene, std::size_t b) {
  const Body& body = scene.bodies[b];
  const int id = static_cast<int>(b);
  if (body.box) {
    HexMesh part = generate_box(body.box->size, body.box->resolution, body.box->origin, id, body.name);
    add_face_selection_sets(body, scene.source, part);
    return part;
  }
  HexMesh part = read_gmsh(body.mesh_file, id);
  std::array<double, 3> f;  // PolyFEM's transformation.dimensions; 1 (exact) without
  try {
    f = dimension_factors(body.dimensions, part.nodes);
  } catch (const std::invalid_argument& e) {
    throw MeshError(scene.source + ": body \"" + body.name + "\": transformation.dimensions: " + e.what());
  }
  const std::array<double, 9>& L = body.linear;
  for (Vec3& X : part.nodes) {
    const Vec3 Y{f[0] * X[0], f[1] * X[1], f[2] * X[2]};
    for (int c = 0; c < 3; ++c)
      X[c] = body.scale * (L[3 * c] * Y[0] + L[3 * c + 1] * Y[1] + L[3 * c + 2] * Y[2]) + body.translation[c];
  }
  HexMesh named;
  named.nodes = std::move(part.nodes);
  named.hexes = std::move(part.hexes);
  named.body = std::move(part.body);
  for (auto& [name, nodes] : part.node_sets) named.node_sets[body.name + "." + name] = std::move(nodes);
  std::vector<std::int64_t> every(named.nodes.size());
  for (std::size_t i = 0; i < every.size(); ++i) every[i] = static_cast<std::int64_t>(i);
  named.node_sets[body.name] = std::move(every);
  add_face_selection_sets(body, scene.source, named);
  return named;
}

// One body's rows in the whole mesh: nodes [node_begin, node_begin + num_nodes), elements
// likewise; its source is one of the three kinds.
struct BodyRows {
  std::int64_t node_begin = 0, num_nodes = 0, element_begin = 0, num_elements = 0;
  HexMesh whole;                         // a body built whole (whole_body), on rank 0 only
  std::unique_ptr<MeshFileReader> hdf5;  // a dipc HDF5 body
};

// The overlap of [a, b) with [c, d), as (begin, count); count 0 when they do not meet.
std::pair<std::int64_t, std::int64_t> overlap(std::int64_t a, std::int64_t b, std::int64_t c, std::int64_t d) {
  const std::int64_t lo = std::max(a, c), hi = std::min(b, d);
  return {lo, std::max<std::int64_t>(0, hi - lo)};
}

// Room for `extra` more entries, growing geometrically (a slice gathers many bodies' rows, and an
// exact reserve per body would copy the rows so far for each of them).
template <class T>
void make_room(std::vector<T>& v, std::int64_t extra) {
  const std::size_t need = v.size() + static_cast<std::size_t>(extra);
  if (need > v.capacity()) v.reserve(std::max(need, 2 * v.capacity()));
}

// Box rows by the numbering of generate_box (box_generator.hpp), with the same arithmetic so
// that the coordinates are bit for bit those of generate_box.
void append_box_rows(const BoxGenerator& box, const std::string& name, int id, const BodyRows& rows, MeshSlice& slice,
                     std::pair<std::int64_t, std::int64_t> nodes, std::pair<std::int64_t, std::int64_t> elements) {
  const std::int64_t nx = box.resolution[0], ny = box.resolution[1], nz = box.resolution[2];
  const std::int64_t px = nx + 1, py = ny + 1;
  const auto& origin = box.origin;
  const auto& size = box.size;
  const std::string faces[6] = {name + ".xmin", name + ".xmax", name + ".ymin",
                                name + ".ymax", name + ".zmin", name + ".zmax"};
  std::vector<std::int64_t>* face_sets[6];
  for (int f = 0; f < 6; ++f) face_sets[f] = &slice.node_sets[faces[f]];
  std::vector<std::int64_t>& all = slice.node_sets[name];
  // Grid indices advance with the row instead of being divided out of it (three 64-bit
  // divisions per row were most of the 0.2 s this took for a 1M-hex box on one rank); rows go in
  // chunks on the host threads, each chunk dividing once for its first row.
  const std::size_t first_node = slice.nodes.size(), node_count = static_cast<std::size_t>(nodes.second);
  make_room(slice.nodes, nodes.second);
  make_room(all, nodes.second);
  slice.nodes.resize(first_node + node_count);
  all.resize(all.size() + node_count);
  const std::size_t first_member = all.size() - node_count;
  parallel_for(node_count, [&](std::size_t begin, std::size_t end) {
    const std::int64_t n = nodes.first - rows.node_begin + static_cast<std::int64_t>(begin);
    std::int64_t i = n % px, j = (n / px) % py, k = n / (px * py);
    for (std::size_t r = begin; r < end; ++r) {
      slice.nodes[first_node + r] = {origin[0] + size[0] * static_cast<double>(i) / nx,
                                     origin[1] + size[1] * static_cast<double>(j) / ny,
                                     origin[2] + size[2] * static_cast<double>(k) / nz};
      all[first_member + r] = nodes.first + static_cast<std::int64_t>(r);
      if (++i == px) i = 0, ++j;
      if (j == py) j = 0, ++k;
    }
  });
  {
    // The faces' node sets, in row order (a pass of index arithmetic only).
    const std::int64_t n = nodes.first - rows.node_begin;
    std::int64_t i = n % px, j = (n / px) % py, k = n / (px * py);
    for (std::int64_t g = nodes.first; g < nodes.first + nodes.second; ++g) {
      const bool on[6] = {i == 0, i == nx, j == 0, j == ny, k == 0, k == nz};
      for (int f = 0; f < 6; ++f)
        if (on[f]) face_sets[f]->push_back(g);
      if (++i == px) i = 0, ++j;
      if (j == py) j = 0, ++k;
    }
  }
  auto node_id = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    return rows.node_begin + i + px * (j + py * k);
  };
  const std::size_t first_element = slice.hexes.size(), element_count = static_cast<std::size_t>(elements.second);
  make_room(slice.hexes, elements.second);
  make_room(slice.body, elements.second);
  slice.hexes.resize(first_element + element_count);
  slice.body.resize(first_element + element_count, id);
  parallel_for(element_count, [&](std::size_t begin, std::size_t end) {
    const std::int64_t e = elements.first - rows.element_begin + static_cast<std::int64_t>(begin);
    std::int64_t i = e % nx, j = (e / nx) % ny, k = e / (nx * ny);
    for (std::size_t r = begin; r < end; ++r) {
      slice.hexes[first_element + r] = {
          node_id(i, j, k),     node_id(i + 1, j, k),     node_id(i + 1, j + 1, k),     node_id(i, j + 1, k),
          node_id(i, j, k + 1), node_id(i + 1, j, k + 1), node_id(i + 1, j + 1, k + 1), node_id(i, j + 1, k + 1)};
      if (++i == nx) i = 0, ++j;
      if (j == ny) j = 0, ++k;
    }
  });
}

struct Row3 {
  Vec3 x;
};
struct SetEntry {
  std::int64_t node;
  std::int32_t set;
  std::int32_t pad;
};

// Boxes nest when one closed box contains another (boxes are convex, so containment of the
// corners is containment of the body). Gives the first (inner, outer) pair in body order.
std::pair<int, int> nested_boxes(const Scene& scene) {
  const std::size_t n = scene.bodies.size();
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = 0; b < n; ++b) {
      if (a == b) continue;
      const BoxGenerator &inner = *scene.bodies[a].box, &outer = *scene.bodies[b].box;
      bool inside = true, same = true;
      for (int c = 0; c < 3; ++c) {
        inside = inside && inner.origin[c] >= outer.origin[c] &&
                 inner.origin[c] + inner.size[c] <= outer.origin[c] + outer.size[c];
        same = same && inner.origin[c] == outer.origin[c] && inner.size[c] == outer.size[c];
      }
      if (inside && !same) return {static_cast<int>(a), static_cast<int>(b)};
    }
  return {-1, -1};
}

// Sizes one body's rows (r.num_nodes, r.num_elements) and opens its source: a box generated
// where its rows live, a dipc HDF5 file read in slices, or a body built whole on rank 0.
void size_body_rows(const Scene& scene, std::size_t b, MPI_Comm comm, int rank, BodyRows& r) {
  const Body& body = scene.bodies[b];
  const bool on_root = !body.box ? !is_hdf5_mesh_path(body.mesh_file) : !body.face_selections.empty();
  if (body.box && !on_root) {
    const auto& res = body.box->resolution;
    r.num_nodes = std::int64_t(res[0] + 1) * (res[1] + 1) * (res[2] + 1);
    r.num_elements = std::int64_t(res[0]) * res[1] * res[2];
    // generate_box's own checks (resolution, size, origin) on rank 0 only: the rows need no more.
    std::string error;
    if (rank == 0) try {
        generate_box(body.box->size, {1, 1, 1}, body.box->origin, static_cast<int>(b), body.name);
        for (int c = 0; c < 3; ++c)
          if (res[c] < 1) throw MeshError("generate_box('" + body.name + "'): resolution must be >= 1");
      } catch (const std::exception& e) {
        error = e.what();
      }
    throw_if_failed_anywhere(comm, error);
  } else if (!on_root) {
    std::string error;
    if (!body.face_selections.empty())
      error = scene.source + ": body \"" + body.name +
              "\": PolyFEM surface selections need a Gmsh mesh or a box, not " + body.mesh_file;
    // Each rank places only its own rows of an HDF5 body, so the file's bounding box is not at
    // hand; PolyFEM scenes, the only ones with Body::dimensions, take Gmsh bodies only anyway.
    if (body.dimensions)
      error = scene.source + ": body \"" + body.name + "\": transformation.dimensions needs a Gmsh mesh, not " +
              body.mesh_file;
    throw_if_failed_anywhere(comm, error);
    r.hdf5 = std::make_unique<MeshFileReader>(comm, body.mesh_file);
    r.num_nodes = r.hdf5->num_nodes();
    r.num_elements = r.hdf5->num_elements();
  } else {
    std::string error;
    std::int64_t counts[2] = {0, 0};
    if (rank == 0) try {
        r.whole = whole_body(scene, b);
        counts[0] = static_cast<std::int64_t>(r.whole.num_nodes());
        counts[1] = static_cast<std::int64_t>(r.whole.num_elements());
      } catch (const std::exception& e) {
        error = e.what();
      }
    throw_if_failed_anywhere(comm, error);
    MPI_Bcast(counts, 2, MPI_INT64_T, 0, comm);
    r.num_nodes = counts[0];
    r.num_elements = counts[1];
  }
}

// A dipc HDF5 body's rows in this rank's slice, read from the file, placed (x = scale·(linear·X)
// + translation), and its selections, each read in blocks and sent to the ids' home ranks.
void append_file_rows(const Body& body, int id, const BodyRows& r, MeshSlice& slice,
                      std::pair<std::int64_t, std::int64_t> my_nodes, std::pair<std::int64_t, std::int64_t> my_elements,
                      int rank, int size) {
  std::vector<std::int64_t>& all = slice.node_sets[body.name];
  for (std::int64_t g = my_nodes.first; g < my_nodes.first + my_nodes.second; ++g) all.push_back(g);
  const std::vector<double> x = r.hdf5->read_coordinates(my_nodes.first - r.node_begin, my_nodes.second);
  const std::array<double, 9>& L = body.linear;
  for (std::size_t i = 0; i < x.size(); i += 3) {
    Vec3 X;
    for (int c = 0; c < 3; ++c)
      X[c] = body.scale * (L[3 * c] * x[i] + L[3 * c + 1] * x[i + 1] + L[3 * c + 2] * x[i + 2]) + body.translation[c];
    slice.nodes.push_back(X);
  }
  const std::vector<std::int64_t> t = r.hdf5->read_topology(my_elements.first - r.element_begin, my_elements.second);
  std::string error;
  for (std::size_t e = 0; e < t.size() / 8; ++e) {
    Hex hex;
    for (int k = 0; k < 8; ++k) {
      const std::int64_t n = t[8 * e + k];
      if ((n < 0 || n >= r.num_nodes) && error.empty())
        error = body.mesh_file + ": element " + std::to_string(my_elements.first - r.element_begin + std::int64_t(e)) +
                " node " + std::to_string(k) + " has id " + std::to_string(n) + ", outside [0, " +
                std::to_string(r.num_nodes) + ")";
      hex[k] = n + r.node_begin;
    }
    slice.hexes.push_back(hex);
    slice.body.push_back(id);
  }
  throw_if_failed_anywhere(slice.comm, error);
  // Selections: each rank reads a block of every set and sends the ids to their home ranks.
  std::vector<std::vector<SetEntry>> to_home(size);
  std::vector<std::string> names;
  for (std::size_t s = 0; s < r.hdf5->set_names().size(); ++s) {
    names.push_back(body.name + "." + r.hdf5->set_names()[s]);
    slice.node_sets[names.back()];
    const std::int64_t n = r.hdf5->set_size(s), begin = block_begin(n, size, rank);
    for (std::int64_t node : r.hdf5->read_set(s, begin, block_begin(n, size, rank + 1) - begin)) {
      if ((node < 0 || node >= r.num_nodes) && error.empty())
        error = body.mesh_file + ": selection \"" + r.hdf5->set_names()[s] + "\" has node id " + std::to_string(node) +
                ", outside [0, " + std::to_string(r.num_nodes) + ")";
      else
        to_home[block_of(node + r.node_begin, slice.num_global_nodes, size)].push_back(
            {node + r.node_begin, std::int32_t(s), 0});
    }
  }
  throw_if_failed_anywhere(slice.comm, error);
  for (const SetEntry& m : exchange_records(to_home, slice.comm)) slice.node_sets[names[m.set]].push_back(m.node);
}

// A body built whole: rank 0 holds it and sends every rank its rows.
void append_whole_body_rows(int id, const BodyRows& r, MeshSlice& slice, int rank, int size) {
  const std::int64_t nodes = slice.num_global_nodes, elements = slice.num_global_elements;
  std::vector<std::vector<Row3>> node_rows(size);
  std::vector<std::vector<Hex>> hex_rows(size);
  std::vector<std::vector<SetEntry>> set_rows(size);
  std::string set_names;  // NUL-separated, broadcast
  if (rank == 0) {
    for (int q = 0; q < size; ++q) {
      const auto n = overlap(block_begin(nodes, size, q), block_begin(nodes, size, q + 1), r.node_begin,
                             r.node_begin + r.num_nodes);
      for (std::int64_t g = n.first; g < n.first + n.second; ++g)
        node_rows[q].push_back({r.whole.nodes[g - r.node_begin]});
      const auto e = overlap(block_begin(elements, size, q), block_begin(elements, size, q + 1), r.element_begin,
                             r.element_begin + r.num_elements);
      for (std::int64_t g = e.first; g < e.first + e.second; ++g) {
        Hex hex = r.whole.hexes[g - r.element_begin];
        for (std::int64_t& v : hex) v += r.node_begin;
        hex_rows[q].push_back(hex);
      }
    }
    std::int32_t s = 0;
    for (const auto& [name, ids] : r.whole.node_sets) {
      set_names += name + '\0';
      for (std::int64_t node : ids)
        set_rows[block_of(node + r.node_begin, nodes, size)].push_back({node + r.node_begin, s, 0});
      ++s;
    }
  }
  for (const Row3& x : exchange_records(node_rows, slice.comm)) slice.nodes.push_back(x.x);
  for (const Hex& hex : exchange_records(hex_rows, slice.comm)) {
    slice.hexes.push_back(hex);
    slice.body.push_back(id);
  }
  int length = static_cast<int>(set_names.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, slice.comm);
  set_names.resize(static_cast<std::size_t>(length));
  MPI_Bcast(set_names.data(), length, MPI_CHAR, 0, slice.comm);
  std::vector<std::string> names;
  for (std::size_t begin = 0; begin < set_names.size();) {
    const std::size_t end = set_names.find('\0', begin);
    names.push_back(set_names.substr(begin, end - begin));
    slice.node_sets[names.back()];
    begin = end + 1;
  }
  for (const SetEntry& m : exchange_records(set_rows, slice.comm)) slice.node_sets[names[m.set]].push_back(m.node);
}

// Without contact bodies pass through each other, so one inside another is no error there.
void check_bodies_apart(const Scene& scene, const MeshSlice& slice, int rank) {
  if (!scene.contact.enabled || scene.bodies.size() <= 1) return;
  std::vector<std::string> names;
  for (const Body& body : scene.bodies) names.push_back(body.name);
  const bool all_boxes = std::all_of(scene.bodies.begin(), scene.bodies.end(),
                                     [](const Body& b) { return bool(b.box); });
  std::string error;
  if (all_boxes) {
    const auto [inner, outer] = nested_boxes(scene);
    if (inner >= 0)
      error = scene.source + ": body \"" + names[inner] + "\" lies inside body \"" + names[outer] +
              "\" (bodies must start apart for contact)";
  } else {
    // Meshes from files: the surface test needs the whole mesh, gathered on rank 0.
    const HexMesh whole = gather_whole_mesh(slice);
    if (rank == 0) try {
        check_no_nested_bodies(whole, names, scene.source);
      } catch (const std::exception& e) {
        error = e.what();
      }
  }
  throw_if_failed_anywhere(slice.comm, error);
}

}  // namespace

MeshSlice build_scene_slice(const Scene& scene, MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  // Every body's rows in the whole mesh, in scene order.
  std::vector<BodyRows> rows(scene.bodies.size());
  std::int64_t nodes = 0, elements = 0;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    BodyRows& r = rows[b];
    size_body_rows(scene, b, comm, rank, r);
    r.node_begin = nodes;
    r.element_begin = elements;
    nodes += r.num_nodes;
    elements += r.num_elements;
  }

  MeshSlice slice;
  slice.comm = comm;
  slice.num_global_nodes = nodes;
  slice.num_global_elements = elements;
  slice.node_begin = block_begin(nodes, size, rank);
  slice.element_begin = block_begin(elements, size, rank);
  const std::int64_t node_end = block_begin(nodes, size, rank + 1), element_end = block_begin(elements, size, rank + 1);
  // Every rank knows every set name, in the same order (the map sorts them).
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    const BodyRows& r = rows[b];
    const auto my_nodes = overlap(slice.node_begin, node_end, r.node_begin, r.node_begin + r.num_nodes);
    const auto my_elements = overlap(slice.element_begin, element_end, r.element_begin,
                                     r.element_begin + r.num_elements);
    const int id = static_cast<int>(b);
    if (body.box && body.face_selections.empty())
      append_box_rows(*body.box, body.name, id, r, slice, my_nodes, my_elements);
    else if (r.hdf5)
      append_file_rows(body, id, r, slice, my_nodes, my_elements, rank, size);
    else
      append_whole_body_rows(id, r, slice, rank, size);
  }
  for (auto& entry : slice.node_sets) {
    std::sort(entry.second.begin(), entry.second.end());
    entry.second.erase(std::unique(entry.second.begin(), entry.second.end()), entry.second.end());
  }
  check_bodies_apart(scene, slice, rank);
  return slice;
}

void check_file_elements(const Scene& scene, const DistributedMesh& mesh) {
  const bool any = std::any_of(scene.bodies.begin(), scene.bodies.end(),
                               [](const Body& b) { return !b.box && is_hdf5_mesh_path(b.mesh_file); });
  if (!any) return;
  // Messages name nodes and elements by their row in the body's file: the body's rows are
  // contiguous in the input numbering, so its first row is the smallest input id over the ranks.
  const std::size_t nb = scene.bodies.size();
  std::vector<std::int64_t> first(2 * nb, INT64_MAX);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto b = static_cast<std::size_t>(mesh.element_body[e]);
    first[2 * b] = std::min(first[2 * b], mesh.element_input_id[e]);
    for (std::int32_t l : mesh.elements[e]) first[2 * b + 1] = std::min(first[2 * b + 1], mesh.node_input_id[l]);
  }
  MPI_Allreduce(MPI_IN_PLACE, first.data(), static_cast<int>(first.size()), MPI_INT64_T, MPI_MIN, mesh.comm);
  // The rank's part of each body as a HexMesh whose MeshSourceMap gives the file rows.
  std::string error;
  for (std::size_t b = 0; b < nb && error.empty(); ++b) {
    const Body& body = scene.bodies[b];
    if (body.box || !is_hdf5_mesh_path(body.mesh_file)) continue;
    HexMesh part;
    MeshSourceMap map;
    std::vector<std::int64_t> local_of(mesh.coordinates.size(), -1);
    for (int e = 0; e < mesh.num_elements(); ++e) {
      if (mesh.element_body[e] != static_cast<int>(b)) continue;
      Hex hex;
      for (int k = 0; k < 8; ++k) {
        const std::int32_t l = mesh.elements[e][k];
        if (local_of[l] < 0) {
          local_of[l] = static_cast<std::int64_t>(part.nodes.size());
          part.nodes.push_back(mesh.coordinates[l]);
          map.node_tags.push_back(mesh.node_input_id[l] - first[2 * b + 1]);
        }
        hex[k] = local_of[l];
      }
      part.hexes.push_back(hex);
      part.body.push_back(static_cast<int>(b));
      map.element_tags.push_back(mesh.element_input_id[e] - first[2 * b]);
    }
    if (part.hexes.empty()) continue;
    try {
      check_mesh(part, body.mesh_file, &map);
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  throw_if_failed_anywhere(mesh.comm, error);
}

}  // namespace dipc
