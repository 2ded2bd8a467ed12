// ContactSet (contact_set.hpp): construction (owned surface, rest vertex areas, vertex–plane
// pairs), extra nodes, the ghost-surface exchange step, obstacle motion and the active set's
// matrix pattern. The candidate search is in contact_candidates.cpp, the diagnostics in
// contact_diagnostics.cpp.
#include "contact/distributed/contact_set.hpp"

#include <petscvec.h>

#include <cmath>

#include "contact/distributed/ghost_surface_exchange.hpp"
#include "math/aabb.hpp"
#include "math/vector3.hpp"
#include "partition/ghost_exchange.hpp"
#include "threads/host_threads.hpp"

namespace dipc {

namespace {

double triangle_area(const double* a, const double* b, const double* c) {
  double u[3], v[3], n[3];
  subtract3(b, a, u);
  subtract3(c, a, v);
  cross3(u, v, n);
  return 0.5 * std::sqrt(squared_norm3(n));
}

}  // namespace

ContactSet::ContactSet(const DistributedMesh& mesh, const ContactParameters& parameters, MemorySpace space,
                       ContactStats* stats, const GhostExchange* nodal)
    : comm_(mesh.comm),
      mesh_(mesh),
      parameters_(parameters),
      space_(space),
      stats_(stats),
      obstacles_(parameters.obstacles) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  surface_ = build_contact_surface(mesh);

  // Rest vertex areas: each owned triangle gives ⅓ of its area to its three nodes; the sums of
  // all ranks meet at the owners and are copied back to every rank holding the node (as the
  // first component of the caller's nodal exchange where there is one).
  GhostExchange scalar;
  if (!nodal) {
    scalar.setup(mesh, 1);
    nodal = &scalar;
  }
  const PetscInt bs = nodal->block_size();
  Vec local, global;
  nodal->create_local_vec(&local);
  nodal->create_global_vec(&global);
  VecZeroEntries(local);
  VecZeroEntries(global);
  PetscScalar* a;
  VecGetArray(local, &a);
  for (const auto& f : surface_.faces) {
    const double area = triangle_area(mesh.coordinates[f[0]].data(), mesh.coordinates[f[1]].data(),
                                      mesh.coordinates[f[2]].data());
    for (std::int32_t n : f) a[bs * n] += area / 3.0;
  }
  VecRestoreArray(local, &a);
  nodal->add_to_global(local, global);
  nodal->to_local(global, local);
  const PetscScalar* ac;
  VecGetArrayRead(local, &ac);
  for (std::int32_t v : surface_.vertices) node_area_[v] = ac[bs * v];
  for (const auto& e : surface_.edges) node_area_[e[0]] = ac[bs * e[0]], node_area_[e[1]] = ac[bs * e[1]];
  VecRestoreArrayRead(local, &ac);
  VecDestroy(&local);
  VecDestroy(&global);
  collect_owned();
  // Half-space obstacles: every owned surface vertex against every plane, for the whole run
  // (contact_form.hpp: such pairs never change the matrix pattern).
  for (std::int32_t v : surface_.vertices)
    for (std::size_t k = 0; k < parameters_.planes.size(); ++k)
      vertex_plane_.push_back({v, static_cast<std::int32_t>(k)});
  // They are in the pattern from the first matrix on.
  for (std::size_t i = 0; i < vertex_plane_.size(); ++i)
    pattern_pairs_.push_back({CandidateKind::vertex_plane, static_cast<std::int32_t>(i)});
  pattern_key_ = pattern_keys(pattern_pairs_);
  if (space_ == MemorySpace::device) {
    std::vector<double> plane_points, plane_normals;  // flat, for the device
    for (const auto& plane : parameters_.planes) {
      plane_points.insert(plane_points.end(), plane.point.begin(), plane.point.end());
      plane_normals.insert(plane_normals.end(), plane.normal.begin(), plane.normal.end());
    }
    device_obstacles_.upload_planes(plane_points, plane_normals);
    upload_obstacle_positions();
    upload_pair_sources_fixed();
    upload_surface();
  }
}

void ContactSet::collect_owned() {
  edges_.clear(), faces_.clear();
  for (std::size_t i = 0; i < surface_.edges.size(); ++i) {
    const auto& e = surface_.edges[i];
    Primitive p{surface_.edge_gid[i], surface_.edge_body[i], true, {e[0], e[1], -1}, 0.0};
    const auto& a = mesh_.coordinates[e[0]];
    const auto& b = mesh_.coordinates[e[1]];
    for (int c = 0; c < 3; ++c) p.rest_length2 += (a[c] - b[c]) * (a[c] - b[c]);
    edges_.push_back(p);
  }
  for (std::size_t i = 0; i < surface_.faces.size(); ++i) {
    const auto& f = surface_.faces[i];
    faces_.push_back(Primitive{surface_.face_gid[i], surface_.face_body[i], true, {f[0], f[1], f[2]}, 0.0});
  }
  owned_edges_ = edges_.size();
  owned_faces_ = faces_.size();
}

std::int32_t ContactSet::ext_local(std::int64_t global_node) {
  const std::int32_t m = mesh_local(global_node);
  if (m >= 0) return m;
  auto it = extra_local_.find(global_node);
  if (it != extra_local_.end()) return it->second;
  const auto id = static_cast<std::int32_t>(mesh_.num_local_nodes() + extra_nodes_.size());
  extra_nodes_.push_back(global_node);
  extra_local_[global_node] = id;
  return id;
}

std::int64_t ContactSet::global_node(std::int32_t ext) const {
  if (is_obstacle_node(ext)) return ext;
  return ext < mesh_.num_local_nodes() ? mesh_.local_to_global[ext] : extra_nodes_[ext - mesh_.num_local_nodes()];
}

double ContactSet::average_vertex_area() const {
  double local[2] = {0, static_cast<double>(surface_.vertices.size())}, total[2];
  for (std::int32_t v : surface_.vertices) local[0] += node_area_.at(v);
  MPI_Allreduce(local, total, 2, MPI_DOUBLE, MPI_SUM, comm_);
  return total[1] > 0 ? total[0] / total[1] : 1.0;
}

bool ContactSet::exchange_ghosts(const double* x, const double* p) {
  const double start = MPI_Wtime();
  // The owned edges, then the owned triangles, with their boxes swept along p and inflated by
  // d̂ (partition/ghost_surface_exchange.hpp sends them where they may meet a rank's surface).
  auto swept_box = [&](const Primitive& prim, int nodes) {
    Aabb b = aabb_empty();
    for (int k = 0; k < nodes; ++k) {
      const double* xi = x + 3 * prim.node[k];
      const double xe[3] = {xi[0] + p[3 * prim.node[k]], xi[1] + p[3 * prim.node[k] + 1],
                            xi[2] + p[3 * prim.node[k] + 2]};
      aabb_add_point(&b, xi);
      aabb_add_point(&b, xe);
    }
    aabb_inflate(&b, parameters_.dhat);
    return b;
  };
  // Each primitive's record and box in its own slot, on the host threads (a pass over the whole
  // owned surface at every exchange).
  std::vector<SurfacePrimitiveRecord> owned(owned_edges_ + owned_faces_);
  std::vector<Aabb> boxes(owned.size());
  parallel_for(owned.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      if (i < owned_edges_) {
        const Primitive& e = edges_[i];
        owned[i] = {0, e.gid, e.body, {global_node(e.node[0]), global_node(e.node[1]), -1}, e.rest_length2};
        boxes[i] = swept_box(e, 2);
      } else {
        const Primitive& f = faces_[i - owned_edges_];
        owned[i] = {1, f.gid, f.body, {global_node(f.node[0]), global_node(f.node[1]), global_node(f.node[2])}, 0.0};
        boxes[i] = swept_box(f, 3);
      }
    }
  });
  const std::vector<SurfacePrimitiveRecord> received = exchange_ghost_surface(comm_, owned, boxes);

  // Rebuild the ghost primitives in the exchange's order and the extra nodes in order of first
  // use. Device space keeps the previous ghosts to upload the surface only when they change.
  const std::vector<std::int64_t> previous = extra_nodes_;
  std::vector<Primitive> previous_edges, previous_faces;
  if (space_ == MemorySpace::device) {
    previous_edges.assign(edges_.begin() + owned_edges_, edges_.end());
    previous_faces.assign(faces_.begin() + owned_faces_, faces_.end());
  }
  extra_local_.clear();
  extra_nodes_.clear();
  edges_.resize(owned_edges_);
  faces_.resize(owned_faces_);
  for (const SurfacePrimitiveRecord& m : received) {
    Primitive prim{
        m.gid, static_cast<int>(m.body), false, {ext_local(m.node[0]), ext_local(m.node[1]), -1}, m.rest_length2};
    if (m.is_face == 0) {
      edges_.push_back(prim);
    } else {
      prim.node[2] = ext_local(m.node[2]);
      faces_.push_back(prim);
    }
  }
  for (std::int64_t g : pinned_) ext_local(g);
  stats_->exchange_seconds += MPI_Wtime() - start;
  auto same = [](const std::vector<Primitive>& before, const std::vector<Primitive>& now, std::size_t owned) {
    if (owned + before.size() != now.size()) return false;
    for (std::size_t i = 0; i < before.size(); ++i) {
      const Primitive& a = before[i];
      const Primitive& b = now[owned + i];
      if (a.gid != b.gid || a.body != b.body || a.node != b.node) return false;
    }
    return true;
  };
  if (space_ == MemorySpace::device &&
      !(same(previous_edges, edges_, owned_edges_) && same(previous_faces, faces_, owned_faces_)))
    upload_surface();
  const bool renumbered = extra_nodes_ != previous;
  if (renumbered) ++numbering_version_;
  return renumbered;
}

// Compare by the pairs' global node ids: candidate indices are renumbered by every exchange.
std::vector<std::array<std::int64_t, 5>> ContactSet::pattern_keys(const std::vector<PatternEntry>& pairs) const {
  // On the host threads: the pattern has hundreds of thousands of pairs on a contact-rich scene
  // at 1M hexes, and its keys are made at every Newton iteration.
  std::vector<std::array<std::int64_t, 5>> key(pairs.size());
  parallel_for(pairs.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t p = begin; p < end; ++p) {
      const PairInfo info = describe(pairs[p].kind, pairs[p].index);
      std::array<std::int64_t, 5> k{static_cast<std::int64_t>(pairs[p].kind), -1, -1, -1, -1};
      for (int n = 0; n < info.count; ++n) k[1 + n] = global_node(info.nodes[n]);
      if (info.plane) k[2] = info.plane - parameters_.planes.data();
      key[p] = k;
    }
  });
  return key;
}

void ContactSet::reserved_blocks(std::vector<std::array<std::int64_t, 2>>* blocks) const {
  using Block = std::array<std::int64_t, 2>;
  const std::vector<Block> found = collect_pairs<Block>([&](CandidateKind kind, std::size_t i, std::vector<Block>& out) {
    if (kind == CandidateKind::vertex_plane) return;
    const PairInfo info = describe(kind, i);
    std::int64_t node[4];
    int n = 0;
    for (int k = 0; k < info.count; ++k) {
      const std::int64_t g = global_node(info.nodes[k]);
      if (!is_obstacle_node(g)) node[n++] = g;  // obstacle nodes have no unknowns
    }
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) out.push_back({node[a], node[b]});
  });
  blocks->insert(blocks->end(), found.begin(), found.end());
}

}  // namespace dipc
