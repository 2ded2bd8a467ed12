#include "nonlinear/contact_form.hpp"

#include <petscvec.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "contact/broad_phase/find_candidates.hpp"
#include "contact/geometry/barrier.hpp"
#include "nonlinear/contact_pair_terms.hpp"
#include "nonlinear/segment_triangle.hpp"
#include "partition/ghost_exchange.hpp"

namespace dipc {

namespace {

using Box = std::array<double, 6>;  // min xyz, max xyz

Box empty_box() {
  const double inf = std::numeric_limits<double>::infinity();
  return {inf, inf, inf, -inf, -inf, -inf};
}
void grow(Box& b, const double* x) {
  for (int c = 0; c < 3; ++c) b[c] = std::min(b[c], x[c]), b[3 + c] = std::max(b[3 + c], x[c]);
}
void inflate(Box& b, double r) {
  for (int c = 0; c < 3; ++c) b[c] -= r, b[3 + c] += r;
}
bool overlap(const Box& a, const Box& b) {
  for (int c = 0; c < 3; ++c)
    if (a[c] > b[3 + c] || b[c] > a[3 + c]) return false;
  return true;
}

double triangle_area(const double* a, const double* b, const double* c) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

// The plane of a vertex–plane pair (nullptr for the other kinds).
const double* plane_point(const ContactForm::PairInfo& info) {
  return info.plane ? info.plane->point.data() : nullptr;
}
const double* plane_normal(const ContactForm::PairInfo& info) {
  return info.plane ? info.plane->normal.data() : nullptr;
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
  for (std::size_t i = 0; i < vertex_plane_.size(); ++i) pattern_pairs_.push_back({2, static_cast<std::int32_t>(i)});
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
  const double r = parameters_.dhat;
  auto swept_box = [&](const Primitive& prim, int nodes) {
    Box b = empty_box();
    for (int k = 0; k < nodes; ++k) {
      const double* xi = x + 3 * prim.node[k];
      const double xe[3] = {xi[0] + p[3 * prim.node[k]], xi[1] + p[3 * prim.node[k] + 1], xi[2] + p[3 * prim.node[k] + 2]};
      grow(b, xi);
      grow(b, xe);
    }
    inflate(b, r);
    return b;
  };
  std::vector<Box> edge_box(owned_edges_), face_box(owned_faces_);
  Box mine = empty_box();
  for (std::size_t i = 0; i < owned_edges_; ++i) {
    edge_box[i] = swept_box(edges_[i], 2);
    grow(mine, edge_box[i].data()), grow(mine, edge_box[i].data() + 3);
  }
  for (std::size_t i = 0; i < owned_faces_; ++i) {
    face_box[i] = swept_box(faces_[i], 3);
    grow(mine, face_box[i].data()), grow(mine, face_box[i].data() + 3);
  }
  std::vector<Box> boxes(size_);
  MPI_Allgather(mine.data(), 6, MPI_DOUBLE, boxes.data(), 6, MPI_DOUBLE, comm_);

  // Send each rank the owned edges and triangles whose boxes reach its surface box. Message
  // per primitive: [kind (0 edge, 1 face), gid, body, 3 global node ids] + [rest length²].
  std::vector<std::vector<std::int64_t>> out_i(size_);
  std::vector<std::vector<double>> out_d(size_);
  for (int s = 0; s < size_; ++s) {
    if (s == rank_ || boxes[s][0] > boxes[s][3]) continue;
    for (std::size_t i = 0; i < owned_edges_; ++i)
      if (overlap(edge_box[i], boxes[s])) {
        const auto& e = edges_[i];
        out_i[s].insert(out_i[s].end(), {0, e.gid, e.body, global_node(e.node[0]), global_node(e.node[1]), -1});
        out_d[s].push_back(e.rest_length2);
      }
    for (std::size_t i = 0; i < owned_faces_; ++i)
      if (overlap(face_box[i], boxes[s])) {
        const auto& f = faces_[i];
        out_i[s].insert(out_i[s].end(),
                        {1, f.gid, f.body, global_node(f.node[0]), global_node(f.node[1]), global_node(f.node[2])});
        out_d[s].push_back(0.0);
      }
  }
  std::vector<int> send_count(size_), recv_count(size_), send_displ(size_), recv_displ(size_);
  for (int s = 0; s < size_; ++s) send_count[s] = static_cast<int>(out_d[s].size());
  MPI_Alltoall(send_count.data(), 1, MPI_INT, recv_count.data(), 1, MPI_INT, comm_);
  std::vector<std::int64_t> send_i, recv_i;
  std::vector<double> send_d, recv_d;
  int total = 0;
  for (int s = 0; s < size_; ++s) {
    send_displ[s] = static_cast<int>(send_d.size());
    send_i.insert(send_i.end(), out_i[s].begin(), out_i[s].end());
    send_d.insert(send_d.end(), out_d[s].begin(), out_d[s].end());
    recv_displ[s] = total;
    total += recv_count[s];
  }
  recv_d.resize(total);
  recv_i.resize(6 * static_cast<std::size_t>(total));
  std::vector<int> send_count6(size_), send_displ6(size_), recv_count6(size_), recv_displ6(size_);
  for (int s = 0; s < size_; ++s)
    send_count6[s] = 6 * send_count[s], send_displ6[s] = 6 * send_displ[s], recv_count6[s] = 6 * recv_count[s],
    recv_displ6[s] = 6 * recv_displ[s];
  MPI_Alltoallv(send_i.data(), send_count6.data(), send_displ6.data(), MPI_INT64_T, recv_i.data(), recv_count6.data(),
                recv_displ6.data(), MPI_INT64_T, comm_);
  MPI_Alltoallv(send_d.data(), send_count.data(), send_displ.data(), MPI_DOUBLE, recv_d.data(), recv_count.data(),
                recv_displ.data(), MPI_DOUBLE, comm_);

  // Rebuild the ghost primitives, sorted by (kind, gid) so the result does not depend on the
  // order of arrival, and the extra nodes in order of first use. Device space keeps the previous
  // ghosts to upload the surface only when they change.
  std::vector<int> order(total);
  for (int k = 0; k < total; ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return std::make_pair(recv_i[6 * a], recv_i[6 * a + 1]) < std::make_pair(recv_i[6 * b], recv_i[6 * b + 1]);
  });
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
  for (int k : order) {
    const std::int64_t* m = &recv_i[6 * static_cast<std::size_t>(k)];
    Primitive prim{m[1], static_cast<int>(m[2]), false, {ext_local(m[3]), ext_local(m[4]), -1}, recv_d[k]};
    if (m[0] == 0) {
      edges_.push_back(prim);
    } else {
      prim.node[2] = ext_local(m[5]);
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
  for_each_pair([&](int kind, std::size_t i) {
    append(&list, describe(kind, i));
    return true;
  });
  device_candidates_.upload(list);
  stats_.transfer_seconds += MPI_Wtime() - start;
}

device::BroadPhaseSurface ContactForm::number_surface() const {
  device::BroadPhaseSurface s;
  std::unordered_map<std::int32_t, std::int32_t> compact;
  auto add = [&](std::int32_t n, int body, bool is_owned_vertex) {
    auto [it, inserted] = compact.emplace(n, static_cast<std::int32_t>(s.vertex_node.size()));
    if (inserted) {
      s.vertex_node.push_back(n);
      s.vertex_group.push_back(body);
      s.owned_vertex.push_back(0);
    }
    if (is_owned_vertex) s.owned_vertex[it->second] = 1;
    return it->second;
  };
  for (std::size_t i = 0; i < surface_.vertices.size(); ++i) add(surface_.vertices[i], surface_.vertex_body[i], true);
  for (const auto& e : edges_) {
    s.edges.insert(s.edges.end(), {add(e.node[0], e.body, false), add(e.node[1], e.body, false)});
    s.edge_gid.push_back(e.gid);
    s.owned_edge.push_back(e.owned ? 1 : 0);
  }
  for (const auto& f : faces_)
    s.faces.insert(s.faces.end(),
                   {add(f.node[0], f.body, false), add(f.node[1], f.body, false), add(f.node[2], f.body, false)});
  s.num_vertices = static_cast<int>(s.vertex_node.size());
  s.self_contact = parameters_.self_contact;
  return s;
}

void ContactForm::upload_surface() {
  const double start = MPI_Wtime();
  device::BroadPhaseSurface s = number_surface();
  device_body_vertices_ = s.num_vertices;
  if (!obstacles_.empty()) append_obstacles(&s);
  device_broad_phase_.upload(s);
  device_surface_nodes_ = std::move(s.vertex_node);
  stats_.broad_phase_seconds += MPI_Wtime() - start;
}

// Every obstacle primitive joins the device search after the body's, in group −1 (never paired
// with itself), with the ownership of find_candidates' filter as data: an obstacle vertex's
// pair belongs to the body face's owner (kFaceDecides), an obstacle edge's to the body edge's
// owner (obstacle edges get the largest global id, so the body edge is the one that decides).
// The host search takes only the obstacle primitives near the rank's swept surface box; the
// device search of all of them finds the same pairs, since two inflated boxes overlap only
// where the obstacle primitive comes within d̂ of that box (up to the rounding of a box bound
// at exactly that distance). The obstacle vertices' rows are their obstacle_node ids, whose
// positions find_candidates_on_device passes.
void ContactForm::append_obstacles(device::BroadPhaseSurface* s) const {
  const auto base = static_cast<std::int32_t>(s->num_vertices);
  for (std::int32_t v = 0; v < obstacles_.num_vertices(); ++v) {
    s->vertex_node.push_back(obstacle_node(v));
    s->vertex_group.push_back(-1);
    s->owned_vertex.push_back(device::kFaceDecides);
  }
  for (const auto& e : obstacles_.edges) {
    s->edges.insert(s->edges.end(), {base + e[0], base + e[1]});
    s->edge_gid.push_back(std::numeric_limits<std::int64_t>::max());
    s->owned_edge.push_back(0);
  }
  s->owned_face.assign(faces_.size(), 0);
  for (std::size_t f = 0; f < owned_faces_; ++f) s->owned_face[f] = 1;
  for (const auto& f : obstacles_.faces) {
    s->faces.insert(s->faces.end(), {base + f[0], base + f[1], base + f[2]});
    s->owned_face.push_back(0);
  }
  s->num_vertices += obstacles_.num_vertices();
}

void ContactForm::move_obstacles(double t0, double t1) {
  obstacles_.move(parameters_.obstacles, t0, t1);
  // The positions are functions of the two times alone: the device keeps them while those stay.
  if (space_ == MemorySpace::device && !(t0 == uploaded_t0_ && t1 == uploaded_t1_)) {
    upload_obstacle_positions();
    uploaded_t0_ = t0, uploaded_t1_ = t1;
  }
}

// Device space: the obstacle vertices' positions to the device, for the broad phase, the
// barrier and the CCD.
void ContactForm::upload_obstacle_positions() {
  if (obstacles_.empty()) return;
  const std::size_t n = 3 * static_cast<std::size_t>(obstacles_.num_vertices());
  const double* start = obstacles_.start(0);
  const double* end = obstacles_.end(0);
  device_obstacles_.upload_vertices(std::vector<double>(start, start + n), std::vector<double>(end, end + n));
}

void ContactForm::find_candidates(const double* x, const double* p) {
  const double start = MPI_Wtime();
  device::BroadPhaseSurface s = number_surface();
  const std::vector<std::int32_t>& node_of = s.vertex_node;
  const std::size_t nv = node_of.size();
  std::vector<double> x0(3 * nv), x1(3 * nv);
  bool moving = false;
  Box reach = empty_box();  // the body surface over the segment
  for (std::size_t v = 0; v < nv; ++v) {
    for (int c = 0; c < 3; ++c) {
      x0[3 * v + c] = x[3 * node_of[v] + c];
      x1[3 * v + c] = x0[3 * v + c] + p[3 * node_of[v] + c];
      moving = moving || p[3 * node_of[v] + c] != 0.0;
    }
    grow(reach, &x0[3 * v]);
    grow(reach, &x1[3 * v]);
  }
  // Obstacle primitives near this rank's surface (within d̂ of its swept box) join the search
  // after the body's, in group −1, so the body's pairs come out as without obstacles.
  const std::size_t body_edges = edges_.size(), body_faces = faces_.size();
  ObstacleSurface::Near near;
  if (!obstacles_.empty() && nv > 0) {
    inflate(reach, parameters_.dhat);
    near = obstacles_.near(reach);
    moving = moving || obstacles_.moving();
    std::unordered_map<std::int32_t, std::int32_t> compact;
    for (std::int32_t v : near.vertices) {
      compact[v] = static_cast<std::int32_t>(x0.size() / 3);
      x0.insert(x0.end(), obstacles_.start(v), obstacles_.start(v) + 3);
      x1.insert(x1.end(), obstacles_.end(v), obstacles_.end(v) + 3);
      s.vertex_group.push_back(-1);
    }
    for (std::int32_t e : near.edges)
      for (std::int32_t v : obstacles_.edges[e]) s.edges.push_back(compact.at(v));
    for (std::int32_t f : near.faces)
      for (std::int32_t v : obstacles_.faces[f]) s.faces.push_back(compact.at(v));
  }
  contact::SurfaceView view;
  view.num_vertices = static_cast<int>(x0.size() / 3);
  view.x0 = x0.data();
  view.x1 = moving ? x1.data() : nullptr;
  view.num_edges = static_cast<int>(s.edges.size() / 2);
  view.edges = s.edges.data();
  view.num_faces = static_cast<int>(s.faces.size() / 3);
  view.faces = s.faces.data();
  view.vertex_group = s.vertex_group.data();
  // The filters the device search reads as data (device_broad_phase.hpp), from the same arrays:
  // a vertex–face pair belongs to the owner of its vertex, an edge–edge pair to the owner of the
  // edge with the smaller global id. With obstacles (group −1, never paired with each other):
  // an obstacle vertex's pair to the owner of the face, an obstacle edge's to the owner of the
  // body edge (which comes first: body edges are numbered before obstacle edges).
  contact::CandidateFilter filter;
  filter.allow_groups = [&s](int a, int b) {
    if (a < 0 || b < 0) return a >= 0 || b >= 0;
    return a != b || (a < static_cast<int>(s.self_contact.size()) && s.self_contact[a]);
  };
  filter.keep_vertex_face = [&](std::int32_t v, std::int32_t f) {
    return static_cast<std::size_t>(v) < nv ? s.owned_vertex[v] != 0 : static_cast<std::size_t>(f) < owned_faces_;
  };
  filter.keep_edge_edge = [&](std::int32_t a, std::int32_t b) {
    if (static_cast<std::size_t>(b) >= body_edges) return static_cast<std::size_t>(a) < owned_edges_;
    return s.owned_edge[s.edge_gid[a] < s.edge_gid[b] ? a : b] != 0;
  };
  contact::Candidates candidates;
  contact::find_candidates(view, 0.5 * parameters_.dhat, &candidates, filter);
  vertex_face_.clear(), vertex_obstacle_face_.clear(), obstacle_vertex_face_.clear();
  edge_edge_.clear(), edge_obstacle_edge_.clear();
  for (const auto& [v, f] : candidates.vertex_face) {
    if (static_cast<std::size_t>(v) >= nv)
      obstacle_vertex_face_.push_back({near.vertices[v - nv], f});
    else if (static_cast<std::size_t>(f) >= body_faces)
      vertex_obstacle_face_.push_back({node_of[v], near.faces[f - body_faces]});
    else
      vertex_face_.push_back({node_of[v], f});
  }
  for (const auto& [a, b] : candidates.edge_edge) {
    if (static_cast<std::size_t>(b) >= body_edges)
      edge_obstacle_edge_.push_back({a, near.edges[b - body_edges]});
    else
      edge_edge_.push_back({a, b});
  }
  stats_.broad_phase_seconds += MPI_Wtime() - start;
}

// The same search as find_candidates on device arrays, over the surface uploaded by the last
// exchange that changed it (device_broad_phase.hpp gives the host search's lists); only the
// candidate lists come back.
void ContactForm::find_candidates_on_device(const double* x, const double* p) {
  const double start = MPI_Wtime();
  contact::Candidates candidates;
  device::PrescribedVertices prescribed;
  if (!obstacles_.empty()) {
    prescribed.start = device_obstacles_.vertex_start.data();
    prescribed.end = device_obstacles_.vertex_end.data();
    prescribed.moving = obstacles_.moving();
  }
  device_broad_phase_.find_candidates_on_segment(x, p, 0.5 * parameters_.dhat, &candidates, prescribed);
  // Split as find_candidates does: obstacle primitives follow the body's (append_obstacles).
  const auto body_vertices = static_cast<std::int32_t>(device_body_vertices_);
  const auto body_edges = static_cast<std::int32_t>(edges_.size());
  const auto body_faces = static_cast<std::int32_t>(faces_.size());
  vertex_face_.clear(), vertex_obstacle_face_.clear(), obstacle_vertex_face_.clear();
  edge_edge_.clear(), edge_obstacle_edge_.clear();
  for (const auto& [v, f] : candidates.vertex_face) {
    if (v >= body_vertices)
      obstacle_vertex_face_.push_back({v - body_vertices, f});
    else if (f >= body_faces)
      vertex_obstacle_face_.push_back({device_surface_nodes_[v], f - body_faces});
    else
      vertex_face_.push_back({device_surface_nodes_[v], f});
  }
  for (const auto& [a, b] : candidates.edge_edge) {
    if (b >= body_edges)
      edge_obstacle_edge_.push_back({a, b - body_edges});
    else
      edge_edge_.push_back({a, b});
  }
  stats_.broad_phase_seconds += MPI_Wtime() - start;
}

// Calls f(kind, index) for every candidate pair this rank evaluates; false if any call was.
template <class F>
bool ContactForm::for_each_pair(F&& f) const {
  const std::size_t count[6] = {vertex_face_.size(),          edge_edge_.size(),          vertex_plane_.size(),
                                vertex_obstacle_face_.size(), edge_obstacle_edge_.size(), obstacle_vertex_face_.size()};
  bool ok = true;
  for (int kind = 0; kind < 6; ++kind)
    for (std::size_t i = 0; i < count[kind]; ++i) ok = f(kind, i) && ok;
  return ok;
}

ContactForm::PairInfo ContactForm::describe(int kind, std::size_t i) const {
  PairInfo info;
  info.kind = kind;
  if (kind == 0) {
    const auto& f = faces_[vertex_face_[i][1]];
    info.nodes = {vertex_face_[i][0], f.node[0], f.node[1], f.node[2]};
    info.count = 4;
    info.weight = node_area_.at(info.nodes[0]);
  } else if (kind == 1) {
    // The edge with the smaller global id first, so that every rank count evaluates (and runs
    // CCD on) the pair in the same order and gets bit-identical results.
    const bool swap = edges_[edge_edge_[i][0]].gid > edges_[edge_edge_[i][1]].gid;
    const auto& a = edges_[edge_edge_[i][swap ? 1 : 0]];
    const auto& b = edges_[edge_edge_[i][swap ? 0 : 1]];
    info.nodes = {a.node[0], a.node[1], b.node[0], b.node[1]};
    info.count = 4;
    const Primitive& own = a.gid < b.gid ? a : b;
    info.weight = 0.5 * (node_area_.at(own.node[0]) + node_area_.at(own.node[1]));
    // Mollifier threshold ε_x = 1e-3 |ea0−ea1|²|eb0−eb1|² at rest (Li et al. 2020, §4.3).
    info.eps_x = 1e-3 * a.rest_length2 * b.rest_length2;
  } else if (kind == 2) {
    info.nodes = {vertex_plane_[i][0], -1, -1, -1};
    info.count = 1;
    info.plane = &parameters_.planes[vertex_plane_[i][1]];
    info.weight = node_area_.at(info.nodes[0]);
  } else if (kind == 3) {  // body vertex – obstacle triangle
    const auto& f = obstacles_.faces[vertex_obstacle_face_[i][1]];
    info.kind = 0;
    info.nodes = {vertex_obstacle_face_[i][0], obstacle_node(f[0]), obstacle_node(f[1]), obstacle_node(f[2])};
    info.count = 4;
    info.weight = node_area_.at(info.nodes[0]);
  } else if (kind == 4) {  // body edge – obstacle edge: the body's edge first, always
    const Primitive& a = edges_[edge_obstacle_edge_[i][0]];
    const std::int32_t b = edge_obstacle_edge_[i][1];
    info.kind = 1;
    info.nodes = {a.node[0], a.node[1], obstacle_node(obstacles_.edges[b][0]), obstacle_node(obstacles_.edges[b][1])};
    info.count = 4;
    info.weight = 0.5 * (node_area_.at(a.node[0]) + node_area_.at(a.node[1]));
    info.eps_x = 1e-3 * a.rest_length2 * obstacles_.edge_rest_length2[b];
  } else {  // obstacle vertex – body triangle
    const std::int32_t v = obstacle_vertex_face_[i][0];
    const auto& f = faces_[obstacle_vertex_face_[i][1]];
    info.kind = 0;
    info.nodes = {obstacle_node(v), f.node[0], f.node[1], f.node[2]};
    info.count = 4;
    info.weight = obstacles_.vertex_area[v];
  }
  return info;
}

void ContactForm::gather(const double* x, const PairInfo& info, double* X) const {
  for (int k = 0; k < info.count; ++k) {
    const double* xk = position(x, info.nodes[k]);
    for (int c = 0; c < 3; ++c) X[3 * k + c] = xk[c];
  }
}

void ContactForm::gather_segment(const double* x, const double* p, const PairInfo& info, double* X0,
                                 double* X1) const {
  for (int k = 0; k < info.count; ++k) {
    const std::int32_t n = info.nodes[k];
    for (int c = 0; c < 3; ++c) {
      if (is_obstacle_node(n)) {
        X0[3 * k + c] = obstacles_.start(obstacle_vertex(n))[c];
        X1[3 * k + c] = obstacles_.end(obstacle_vertex(n))[c];
      } else {
        X0[3 * k + c] = x[3 * n + c];
        X1[3 * k + c] = X0[3 * k + c] + p[3 * n + c];
      }
    }
  }
}

bool ContactForm::terms(const PairInfo& info, const double* x, bool want_g, bool want_H, bool* active,
                        ContactPairTerms* t) const {
  double X[12];
  gather(x, info, X);
  return contact_pair_terms(info.kind, X, plane_point(info), plane_normal(info), parameters_.dhat * parameters_.dhat,
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
  const bool ok = for_each_pair([&](int kind, std::size_t i) {
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
  const bool ok = for_each_pair([&](int kind, std::size_t i) {
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
  for_each_pair([&](int kind, std::size_t i) {
    bool active = kind == 2;  // vertex–plane pairs are always in the pattern (header)
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
    std::array<std::int64_t, 5> k{pe.kind, -1, -1, -1, -1};
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
    const int n = body_slots(k.data() + 1, k[0] == 2 ? 1 : 4, slots);
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
    for_each_pair([&](int kind, std::size_t i) {
      const PairInfo info = describe(kind, i);
      double X0[12], X1[12];
      gather_segment(x, p, info, X0, X1);
      t = std::min(t, contact_pair_time_of_impact(info.kind, X0, X1, plane_point(info), plane_normal(info), 1.0));
      return true;
    });
  }
  stats_.ccd_seconds += MPI_Wtime() - start;
  // IPC starts the line search at a fraction of the time of impact, so that the new state
  // keeps a positive distance even before the barrier pushes back.
  return t < 1.0 ? parameters_.ccd_fraction * t : 1.0;
}

double ContactForm::squared_distance(const PairInfo& info, const double* X) {
  return contact_pair_squared_distance(info.kind, X, plane_point(info), plane_normal(info));
}

double ContactForm::min_distance(const double* x) const {
  double d2 = std::numeric_limits<double>::infinity();
  for_each_pair([&](int kind, std::size_t i) {
    const PairInfo info = describe(kind, i);
    double X[12];
    gather(x, info, X);
    d2 = std::min(d2, squared_distance(info, X));
    return true;
  });
  return std::sqrt(d2);
}

std::vector<ContactForm::ActivePair> ContactForm::active_pairs(const double* x) const {
  std::vector<ActivePair> out;
  for_each_pair([&](int kind, std::size_t i) {
    const PairInfo info = describe(kind, i);
    bool active;
    ContactPairTerms t;
    terms(info, x, false, false, &active, &t);
    if (active) out.push_back({info, global_node(info.nodes[0])});
    return true;
  });
  return out;
}

const char* ContactForm::pair_kind_name(int kind) {
  static const char* const names[num_pair_kinds] = {"point_triangle",          "edge_edge",
                                                    "point_plane",             "point_obstacle_triangle",
                                                    "edge_obstacle_edge",      "obstacle_point_triangle"};
  return kind >= 0 && kind < num_pair_kinds ? names[kind] : "unknown";
}

std::array<long, ContactForm::num_pair_kinds> ContactForm::active_pair_counts(const double* x) const {
  std::array<long, num_pair_kinds> counts{};
  for_each_pair([&](int kind, std::size_t i) {
    bool active;
    ContactPairTerms t;
    terms(describe(kind, i), x, false, false, &active, &t);
    if (active) ++counts[kind];
    return true;
  });
  return counts;
}

std::string ContactForm::body_label(int b) const {
  return b >= 0 && b < static_cast<int>(parameters_.body_names.size()) ? "\"" + parameters_.body_names[b] + "\""
                                                                        : std::to_string(b);
}

std::string ContactForm::node_label(std::int32_t n) const {
  return n < mesh_.num_local_nodes() ? "node " + std::to_string(mesh_.node_input_id[n])
                                     : "node (global " + std::to_string(global_node(n)) + ")";
}

// Obstacle primitives by their index in their obstacle (triangles in the file's order, after
// polygons are split into triangles; vertices after equal ones are merged).
std::string ContactForm::obstacle_vertex_label(std::int32_t v) const {
  const int o = obstacles_.vertex_obstacle[v];
  return "vertex " + std::to_string(v - obstacles_.first_vertex[o]) + " of obstacle \"" +
         parameters_.obstacles[o].name + "\"";
}

std::string ContactForm::obstacle_face_label(std::int32_t f) const {
  const int o = obstacles_.face_obstacle[f];
  const auto& ob = parameters_.obstacles[o];
  const std::size_t t = static_cast<std::size_t>(f - obstacles_.first_face[o]);
  std::string where = ob.source;
  if (t < ob.triangle_origin.size())
    where += (ob.binary_origin ? ": facet " : ":") + std::to_string(ob.triangle_origin[t]);
  return "triangle " + std::to_string(t) + " of obstacle \"" + ob.name + "\" (" + where + ")";
}

std::string ContactForm::obstacle_edge_label(std::int32_t e) const {
  const int o = obstacles_.edge_obstacle[e];
  const std::int32_t base = obstacles_.first_vertex[o];
  return "edge (vertex " + std::to_string(obstacles_.edges[e][0] - base) + ", vertex " +
         std::to_string(obstacles_.edges[e][1] - base) + ") of obstacle \"" + parameters_.obstacles[o].name + "\"";
}

std::string ContactForm::closest_pair(const double* x) const {
  struct {
    double distance;
    int rank;
  } mine{std::numeric_limits<double>::infinity(), rank_}, closest;
  int closest_kind = -1;
  std::size_t closest_index = 0;
  for_each_pair([&](int kind, std::size_t i) {
    const PairInfo info = describe(kind, i);
    double X[12];
    gather(x, info, X);
    const double d = std::sqrt(squared_distance(info, X));
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
    if (closest_kind == 0) {
      const std::int32_t v = vertex_face_[i][0];
      text = node_label(v) + " of body " + body_label(vertex_body(v)) + " and " +
             primitive("triangle", faces_[vertex_face_[i][1]], 3);
    } else if (closest_kind == 1) {
      text = primitive("edge", edges_[edge_edge_[i][0]], 2) + " and " + primitive("edge", edges_[edge_edge_[i][1]], 2);
    } else if (closest_kind == 2) {
      const std::int32_t v = vertex_plane_[i][0];
      const auto& point = parameters_.planes[vertex_plane_[i][1]].point;
      text = node_label(v) + " of body " + body_label(vertex_body(v)) + " and the plane through (" +
             std::to_string(point[0]) + ", " + std::to_string(point[1]) + ", " + std::to_string(point[2]) + ")";
    } else if (closest_kind == 3) {
      const std::int32_t v = vertex_obstacle_face_[i][0];
      text = node_label(v) + " of body " + body_label(vertex_body(v)) + " and " +
             obstacle_face_label(vertex_obstacle_face_[i][1]);
    } else if (closest_kind == 4) {
      text = primitive("edge", edges_[edge_obstacle_edge_[i][0]], 2) + " and " +
             obstacle_edge_label(edge_obstacle_edge_[i][1]);
    } else {
      text = obstacle_vertex_label(obstacle_vertex_face_[i][0]) + " and " +
             primitive("triangle", faces_[obstacle_vertex_face_[i][1]], 3);
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

long ContactForm::count_intersections(const double* x, std::string* first) const {
  // Triangles sorted by the lower x of their boxes, so each edge only looks at the triangles
  // whose x-range can overlap its own (sweep and prune).
  std::vector<std::pair<double, std::size_t>> by_x;
  std::vector<Box> face_box(faces_.size());
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    face_box[f] = empty_box();
    for (int k = 0; k < 3; ++k) grow(face_box[f], x + 3 * faces_[f].node[k]);
    by_x.emplace_back(face_box[f][0], f);
  }
  std::sort(by_x.begin(), by_x.end());
  long count = 0;
  for (std::size_t e = 0; e < owned_edges_; ++e) {
    const Primitive& edge = edges_[e];
    Box eb = empty_box();
    grow(eb, x + 3 * edge.node[0]);
    grow(eb, x + 3 * edge.node[1]);
    for (const auto& [fx, f] : by_x) {
      if (fx > eb[3]) break;
      const Primitive& face = faces_[f];
      if (!overlap(eb, face_box[f])) continue;
      bool shared = false;
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 3; ++b) shared = shared || edge.node[a] == face.node[b];
      if (shared) continue;
      if (!segment_crosses_triangle(x + 3 * edge.node[0], x + 3 * edge.node[1], x + 3 * face.node[0],
                                    x + 3 * face.node[1], x + 3 * face.node[2]))
        continue;
      if (count++ == 0 && first)
        *first = "edge (" + node_label(edge.node[0]) + ", " + node_label(edge.node[1]) + ") of body " +
                 body_label(edge.body) + " crosses triangle (" + node_label(face.node[0]) + ", " +
                 node_label(face.node[1]) + ", " + node_label(face.node[2]) + ") of body " + body_label(face.body);
    }
  }
  count += count_obstacle_intersections(x, count == 0 ? first : nullptr);
  for (std::size_t i = 0; i < surface_.vertices.size(); ++i)
    for (const auto& plane : parameters_.planes) {
      const std::int32_t v = surface_.vertices[i];
      double s = 0;
      for (int c = 0; c < 3; ++c) s += (x[3 * v + c] - plane.point[c]) * plane.normal[c];
      if (s > 0) continue;
      if (count++ == 0 && first)
        *first = node_label(v) + " of body " + body_label(surface_.vertex_body[i]) + " is on or behind the plane through (" +
                 std::to_string(plane.point[0]) + ", " + std::to_string(plane.point[1]) + ", " +
                 std::to_string(plane.point[2]) + ")";
    }
  return count;
}

// Owned body edges against obstacle triangles, and obstacle edges against owned body triangles
// (each crossing counted by the owner of its body primitive), by sweep and prune on x.
long ContactForm::count_obstacle_intersections(const double* x, std::string* first) const {
  if (obstacles_.empty()) return 0;
  auto box_of = [&](const std::int32_t* nodes, int count) {
    Box b = empty_box();
    for (int k = 0; k < count; ++k) grow(b, position(x, nodes[k]));
    return b;
  };
  auto sorted_by_x = [](const std::vector<Box>& boxes) {
    std::vector<std::pair<double, std::size_t>> by_x;
    for (std::size_t i = 0; i < boxes.size(); ++i) by_x.emplace_back(boxes[i][0], i);
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
  std::vector<Box> tri_box(tri.size());
  for (std::size_t f = 0; f < tri.size(); ++f) {
    for (int k = 0; k < 3; ++k) tri[f][k] = obstacle_node(obstacles_.faces[f][k]);
    tri_box[f] = box_of(tri[f].data(), 3);
  }
  const auto tri_by_x = sorted_by_x(tri_box);
  for (std::size_t e = 0; e < owned_edges_; ++e) {
    const std::int32_t edge[2] = {edges_[e].node[0], edges_[e].node[1]};
    const Box eb = box_of(edge, 2);
    for (const auto& [fx, f] : tri_by_x) {
      if (fx > eb[3]) break;
      if (!overlap(eb, tri_box[f]) || !crossing(edge, tri[f].data())) continue;
      if (count++ == 0 && first)
        *first = "edge (" + node_label(edge[0]) + ", " + node_label(edge[1]) + ") of body " +
                 body_label(edges_[e].body) + " crosses " + obstacle_face_label(static_cast<std::int32_t>(f));
    }
  }
  // Obstacle edges against owned body triangles.
  std::vector<Box> face_box(owned_faces_);
  for (std::size_t f = 0; f < owned_faces_; ++f) face_box[f] = box_of(faces_[f].node.data(), 3);
  const auto face_by_x = sorted_by_x(face_box);
  for (std::size_t e = 0; e < obstacles_.edges.size(); ++e) {
    const std::int32_t edge[2] = {obstacle_node(obstacles_.edges[e][0]), obstacle_node(obstacles_.edges[e][1])};
    const Box eb = box_of(edge, 2);
    for (const auto& [fx, f] : face_by_x) {
      if (fx > eb[3]) break;
      if (!overlap(eb, face_box[f]) || !crossing(edge, faces_[f].node.data())) continue;
      if (count++ == 0 && first)
        *first = obstacle_edge_label(static_cast<std::int32_t>(e)) + " crosses triangle (" +
                 node_label(faces_[f].node[0]) + ", " + node_label(faces_[f].node[1]) + ", " +
                 node_label(faces_[f].node[2]) + ") of body " + body_label(faces_[f].body);
    }
  }
  return count;
}

}  // namespace dipc
