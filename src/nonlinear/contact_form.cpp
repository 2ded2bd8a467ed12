// ContactForm (contact_form.hpp): construction, the ghost-surface exchange step, κ bounds and
// the Form evaluations (value, gradient, Hessian and its pattern, CCD step bound) on the host
// and the device. The candidate search is in contact_candidates.cpp, the queries and messages
// in contact_diagnostics.cpp.
#include "nonlinear/contact_form.hpp"

#include <petscvec.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "contact/contact_pair_terms.hpp"
#include "contact/geometry/barrier.hpp"
#include "math/aabb.hpp"
#include "math/vector3.hpp"
#include "partition/ghost_exchange.hpp"
#include "partition/ghost_surface_exchange.hpp"

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

ContactForm::ContactForm(const DistributedMesh& mesh, ContactParameters parameters, MemorySpace space)
    : comm_(mesh.comm), mesh_(mesh), parameters_(std::move(parameters)), space_(space),
      obstacles_(parameters_.obstacles) {
  if (space_ == MemorySpace::device) {
    if (device::device_count() == 0)
      throw device::DeviceError(device::built_with_cuda()
                                    ? "contact barrier on the device: no CUDA device is visible to this process"
                                    : "contact barrier on the device: dipc was built without CUDA "
                                      "(configure with -DDIPC_WITH_CUDA=ON)");
    std::vector<double> plane_points, plane_normals;  // flat, for the device
    for (const auto& plane : parameters_.planes) {
      plane_points.insert(plane_points.end(), plane.point.begin(), plane.point.end());
      plane_normals.insert(plane_normals.end(), plane.normal.begin(), plane.normal.end());
    }
    device_obstacles_.upload_planes(plane_points, plane_normals);
    upload_obstacle_positions();
  }
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  surface_ = build_contact_surface(mesh);
  for (int n = 0; n < mesh.num_local_nodes(); ++n) global_to_local_[mesh.local_to_global[n]] = n;

  // Rest vertex areas: each owned triangle gives ⅓ of its area to its three nodes; the sums of
  // all ranks meet at the owners and are copied back to every rank holding the node.
  GhostExchange scalar;
  scalar.setup(mesh, 1);
  Vec local, global;
  scalar.create_local_vec(&local);
  scalar.create_global_vec(&global);
  VecZeroEntries(local);
  VecZeroEntries(global);
  PetscScalar* a;
  VecGetArray(local, &a);
  for (const auto& f : surface_.faces) {
    const double area = triangle_area(mesh.coordinates[f[0]].data(), mesh.coordinates[f[1]].data(),
                                      mesh.coordinates[f[2]].data());
    for (std::int32_t n : f) a[n] += area / 3.0;
  }
  VecRestoreArray(local, &a);
  scalar.add_to_global(local, global);
  scalar.to_local(global, local);
  const PetscScalar* ac;
  VecGetArrayRead(local, &ac);
  for (std::int32_t v : surface_.vertices) node_area_[v] = ac[v];
  for (const auto& e : surface_.edges) node_area_[e[0]] = ac[e[0]], node_area_[e[1]] = ac[e[1]];
  VecRestoreArrayRead(local, &ac);
  VecDestroy(&local);
  VecDestroy(&global);
  collect_owned();
  // Half-space obstacles: every owned surface vertex against every plane, for the whole run
  // (see the header: such pairs never change the matrix pattern).
  for (std::int32_t v : surface_.vertices)
    for (std::size_t k = 0; k < parameters_.planes.size(); ++k)
      vertex_plane_.push_back({v, static_cast<std::int32_t>(k)});
  // They are in the pattern from the first matrix on.
  for (std::size_t i = 0; i < vertex_plane_.size(); ++i)
    pattern_pairs_.push_back({CandidateKind::vertex_plane, static_cast<std::int32_t>(i)});
  pattern_key_ = pattern_keys(pattern_pairs_);
  if (space_ == MemorySpace::device) upload_surface();
}

void ContactForm::collect_owned() {
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

std::int32_t ContactForm::ext_local(std::int64_t global_node) {
  auto it = global_to_local_.find(global_node);
  if (it != global_to_local_.end()) return it->second;
  const auto id = static_cast<std::int32_t>(mesh_.num_local_nodes() + extra_nodes_.size());
  extra_nodes_.push_back(global_node);
  global_to_local_[global_node] = id;
  return id;
}

std::int64_t ContactForm::global_node(std::int32_t ext) const {
  if (is_obstacle_node(ext)) return ext;
  return ext < mesh_.num_local_nodes() ? mesh_.local_to_global[ext] : extra_nodes_[ext - mesh_.num_local_nodes()];
}

void ContactForm::set_kappa_bounds(double average_mass, double bbox_diagonal) {
  // IPC supplement (adaptive barrier stiffness): κ_min makes the barrier's stiffness at a
  // tiny distance d₀ = (1e-8 L)² comparable to the inertia of an average node,
  // κ_min = 1e11 · m̄ / (4 d₀ b''(d₀)), and κ_max = 100 κ_min. dipc's barrier is weighted by
  // rest vertex areas, so a node's barrier stiffness is κ Ā b'': the mass is taken per unit
  // area, m̄ / Ā (Ā the average vertex area), which keeps κ_min independent of the mesh size.
  double local[2] = {0, static_cast<double>(surface_.vertices.size())}, total[2];
  for (std::int32_t v : surface_.vertices) local[0] += node_area_.at(v);
  MPI_Allreduce(local, total, 2, MPI_DOUBLE, MPI_SUM, comm_);
  const double average_area = total[1] > 0 ? total[0] / total[1] : 1.0;
  const double dhat2 = parameters_.dhat * parameters_.dhat;
  double d0 = 1e-8 * bbox_diagonal;
  d0 *= d0;
  if (d0 >= dhat2) d0 = 0.5 * dhat2;
  kappa_min_ = 1e11 * (average_mass / average_area) / (4.0 * d0 * contact::barrier_second_derivative(d0, dhat2));
  kappa_max_ = 100.0 * kappa_min_;
  min_distance_eps2_ = (1e-9 * bbox_diagonal) * (1e-9 * bbox_diagonal);
  if (parameters_.kappa_adaptive && parameters_.kappa < kappa_min_) parameters_.kappa = kappa_min_;
}

bool ContactForm::update_extra_nodes(const double* x, const double* p) {
  const double start = MPI_Wtime();
  // The owned edges, then the owned triangles, with their boxes swept along p and inflated by
  // d̂ (partition/ghost_surface_exchange.hpp sends them where they may meet a rank's surface).
  auto swept_box = [&](const Primitive& prim, int nodes) {
    Aabb b = aabb_empty();
    for (int k = 0; k < nodes; ++k) {
      const double* xi = x + 3 * prim.node[k];
      const double xe[3] = {xi[0] + p[3 * prim.node[k]], xi[1] + p[3 * prim.node[k] + 1], xi[2] + p[3 * prim.node[k] + 2]};
      aabb_add_point(&b, xi);
      aabb_add_point(&b, xe);
    }
    aabb_inflate(&b, parameters_.dhat);
    return b;
  };
  std::vector<SurfacePrimitiveRecord> owned;
  std::vector<Aabb> boxes;
  for (std::size_t i = 0; i < owned_edges_; ++i) {
    const Primitive& e = edges_[i];
    owned.push_back({0, e.gid, e.body, {global_node(e.node[0]), global_node(e.node[1]), -1}, e.rest_length2});
    boxes.push_back(swept_box(e, 2));
  }
  for (std::size_t i = 0; i < owned_faces_; ++i) {
    const Primitive& f = faces_[i];
    owned.push_back({1, f.gid, f.body, {global_node(f.node[0]), global_node(f.node[1]), global_node(f.node[2])}, 0.0});
    boxes.push_back(swept_box(f, 3));
  }
  const std::vector<SurfacePrimitiveRecord> received = exchange_ghost_surface(comm_, owned, boxes);

  // Rebuild the ghost primitives in the exchange's order and the extra nodes in order of first
  // use. Device space keeps the previous ghosts to upload the surface only when they change.
  const std::vector<std::int64_t> previous = extra_nodes_;
  std::vector<Primitive> previous_edges, previous_faces;
  if (space_ == MemorySpace::device) {
    previous_edges.assign(edges_.begin() + owned_edges_, edges_.end());
    previous_faces.assign(faces_.begin() + owned_faces_, faces_.end());
  }
  for (std::int64_t g : extra_nodes_) global_to_local_.erase(g);
  extra_nodes_.clear();
  edges_.resize(owned_edges_);
  faces_.resize(owned_faces_);
  for (const SurfacePrimitiveRecord& m : received) {
    Primitive prim{m.gid, static_cast<int>(m.body), false, {ext_local(m.node[0]), ext_local(m.node[1]), -1},
                   m.rest_length2};
    if (m.is_face == 0) {
      edges_.push_back(prim);
    } else {
      prim.node[2] = ext_local(m.node[2]);
      faces_.push_back(prim);
    }
  }
  for (std::int64_t g : pinned_) ext_local(g);
  stats_.exchange_seconds += MPI_Wtime() - start;
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
  return extra_nodes_ != previous;
}

void ContactForm::prepare_segment(const double* x, const double* p) {
  if (space_ != MemorySpace::device) {
    find_candidates(x, p);
    return;
  }
  find_candidates_on_device(x, p);
  const double start = MPI_Wtime();
  device::ContactPairList list;
  for_each_pair([&](CandidateKind kind, std::size_t i) {
    append(&list, describe(kind, i));
    return true;
  });
  device_candidates_.upload(list);
  stats_.transfer_seconds += MPI_Wtime() - start;
}

bool ContactForm::terms(const PairInfo& info, const double* x, bool want_g, bool want_H, bool* active,
                        ContactPairTerms* t) const {
  double X[12];
  gather(x, info, X);
  return contact_pair_terms(info.kind, X, info.plane_point(), info.plane_normal(), parameters_.dhat * parameters_.dhat,
                            parameters_.kappa, info.weight, info.eps_x, want_g, want_H, parameters_.project_hessian,
                            active, t);
}

void ContactForm::append(device::ContactPairList* list, const PairInfo& info) const {
  list->add(info.kind, info.nodes.data(), info.weight, info.eps_x,
            info.plane ? static_cast<int>(info.plane - parameters_.planes.data()) : -1);
}

device::BarrierConstants ContactForm::barrier_constants() const {
  device::BarrierConstants c;
  c.dhat2 = parameters_.dhat * parameters_.dhat;
  c.kappa = parameters_.kappa;
  c.project = parameters_.project_hessian;
  return c;
}

bool ContactForm::value(const double* x, double* energy) {
  const double start = MPI_Wtime();
  if (space_ == MemorySpace::device) {
    const bool ok =
        device::contact_barrier_energy(device_candidates_, device_obstacles_, barrier_constants(), x, reducer_, energy);
    stats_.barrier_seconds += MPI_Wtime() - start;
    return ok;
  }
  double e = 0;
  const bool ok = for_each_pair([&](CandidateKind kind, std::size_t i) {
    bool active;
    ContactPairTerms t;
    if (!terms(describe(kind, i), x, false, false, &active, &t)) return false;
    e += t.energy;
    return true;
  });
  *energy = e;
  stats_.barrier_seconds += MPI_Wtime() - start;
  return ok;
}

bool ContactForm::gradient(const double* x, double* g) {
  const double start = MPI_Wtime();
  if (space_ == MemorySpace::device) {
    const bool ok =
        device::add_contact_barrier_gradient(device_candidates_, device_obstacles_, barrier_constants(), x, g, reducer_);
    stats_.barrier_seconds += MPI_Wtime() - start;
    return ok;
  }
  const bool ok = for_each_pair([&](CandidateKind kind, std::size_t i) {
    const PairInfo info = describe(kind, i);
    bool active;
    ContactPairTerms t;
    if (!terms(info, x, true, false, &active, &t)) return false;
    if (!active) return true;
    for (int k = 0; k < info.count; ++k)
      if (!is_obstacle_node(info.nodes[k]))
        for (int c = 0; c < 3; ++c) g[3 * info.nodes[k] + c] += t.g[3 * k + c];
    return true;
  });
  stats_.barrier_seconds += MPI_Wtime() - start;
  return ok;
}

void ContactForm::update_pattern(const double* x) {
  std::vector<PatternEntry> active_now;
  for_each_pair([&](CandidateKind kind, std::size_t i) {
    bool active = kind == CandidateKind::vertex_plane;  // always in the pattern (header)
    if (!active) {
      ContactPairTerms t;
      terms(describe(kind, i), x, false, false, &active, &t);
    }
    if (active) active_now.push_back({kind, static_cast<std::int32_t>(i)});
    return true;
  });
  std::vector<std::array<std::int64_t, 5>> key = pattern_keys(active_now);
  pattern_pairs_ = std::move(active_now);
  if (key != pattern_key_) {
    pattern_key_ = std::move(key);
    ++pattern_version_;
  }
  if (space_ != MemorySpace::device) return;
  // The pattern's device list also changes when exchanges renumber its nodes, so compare the
  // list itself, not only the key.
  const double start = MPI_Wtime();
  device::ContactPairList list;
  for (const auto& pe : pattern_pairs_) append(&list, describe(pe.kind, pe.index));
  if (list != uploaded_pattern_) {
    device_pattern_.upload(list);
    uploaded_pattern_ = std::move(list);
  }
  stats_.transfer_seconds += MPI_Wtime() - start;
}

// Compare by the pairs' global node ids: candidate indices are renumbered by every exchange.
std::vector<std::array<std::int64_t, 5>> ContactForm::pattern_keys(const std::vector<PatternEntry>& pairs) const {
  std::vector<std::array<std::int64_t, 5>> key;
  for (const auto& pe : pairs) {
    const PairInfo info = describe(pe.kind, pe.index);
    std::array<std::int64_t, 5> k{static_cast<std::int64_t>(pe.kind), -1, -1, -1, -1};
    for (int n = 0; n < info.count; ++n) k[1 + n] = global_node(info.nodes[n]);
    if (info.plane) k[2] = info.plane - parameters_.planes.data();
    key.push_back(k);
  }
  return key;
}

void ContactForm::coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) {
  rows->clear(), cols->clear();
  // Only the body nodes' blocks: obstacle nodes (negative ids) have no unknowns.
  for (const auto& k : pattern_key_) {
    int slots[4];
    const int n = body_slots(k.data() + 1, k[0] == static_cast<std::int64_t>(CandidateKind::vertex_plane) ? 1 : 4, slots);
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < 3; ++i)
        for (int b = 0; b < n; ++b)
          for (int j = 0; j < 3; ++j) {
            rows->push_back(static_cast<PetscInt>(3 * k[1 + slots[a]] + i));
            cols->push_back(static_cast<PetscInt>(3 * k[1 + slots[b]] + j));
          }
  }
}

bool ContactForm::hessian(const double* x, double* values) {
  const double start = MPI_Wtime();
  if (space_ == MemorySpace::device) {
    const bool ok =
        device::contact_barrier_hessian(device_pattern_, device_obstacles_, barrier_constants(), x, values, reducer_);
    stats_.barrier_seconds += MPI_Wtime() - start;
    return ok;
  }
  std::size_t offset = 0;
  bool ok = true;
  for (const auto& pe : pattern_pairs_) {
    const PairInfo info = describe(pe.kind, pe.index);
    int slots[4];
    const int n = 3 * body_slots(info.nodes.data(), info.count, slots);
    bool active;
    ContactPairTerms t;
    ok = terms(info, x, true, true, &active, &t) && ok;
    if (active)
      body_block(t.H, info.count, slots, n / 3, values + offset);
    else
      std::fill(values + offset, values + offset + n * n, 0.0);
    offset += static_cast<std::size_t>(n) * n;
  }
  stats_.barrier_seconds += MPI_Wtime() - start;
  return ok;
}

double ContactForm::max_step(const double* x, const double* p) {
  const double start = MPI_Wtime();
  double t = 1.0;
  if (space_ == MemorySpace::device) {
    t = device::contact_min_time_of_impact(device_candidates_, device_obstacles_, x, p, 1.0, reducer_);
  } else {
    // Every pair on [0, 1], as on the device (see the header).
    for_each_pair([&](CandidateKind kind, std::size_t i) {
      const PairInfo info = describe(kind, i);
      double X0[12], X1[12];
      gather_segment(x, p, info, X0, X1);
      t = std::min(t, contact_pair_time_of_impact(info.kind, X0, X1, info.plane_point(), info.plane_normal(), 1.0));
      return true;
    });
  }
  stats_.ccd_seconds += MPI_Wtime() - start;
  // IPC starts the line search at a fraction of the time of impact, so that the new state
  // keeps a positive distance even before the barrier pushes back.
  return t < 1.0 ? parameters_.ccd_fraction * t : 1.0;
}

}  // namespace dipc
