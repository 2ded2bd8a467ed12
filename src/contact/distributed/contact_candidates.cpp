// ContactSet's candidate pairs (contact_set.hpp): the broad phase on the host
// (contact/broad_phase/find_candidates.hpp) and on the device
// (contact/broad_phase/cuda/device_broad_phase.hpp) with the same filters
// (contact/broad_phase/pair_filter.hpp), the numbering of the surface they search, the
// triangle-mesh obstacles' part in it, and each candidate's description as a pair (nodes,
// weight, mollifier threshold).
#include <limits>
#include <unordered_map>

#include "contact/broad_phase/find_candidates.hpp"
#include "contact/broad_phase/pair_filter.hpp"
#include "contact/distributed/contact_set.hpp"
#include "math/aabb.hpp"

namespace dipc {

device::BroadPhaseSurface ContactSet::number_surface() const {
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

void ContactSet::upload_surface() {
  const double start = MPI_Wtime();
  device::BroadPhaseSurface s = number_surface();
  device_body_vertices_ = s.num_vertices;
  if (!obstacles_.empty()) append_obstacles(&s);
  device_broad_phase_.upload(s);
  device_surface_nodes_ = std::move(s.vertex_node);
  upload_pair_sources_body();
  stats_->broad_phase_seconds += MPI_Wtime() - start;
}

void ContactSet::upload_pair_sources_body() {
  std::vector<std::int32_t> face_nodes(3 * faces_.size()), edge_nodes(2 * edges_.size());
  std::vector<std::int64_t> gid(edges_.size());
  std::vector<double> rest2(edges_.size());
  for (std::size_t f = 0; f < faces_.size(); ++f)
    for (int c = 0; c < 3; ++c) face_nodes[3 * f + c] = faces_[f].node[c];
  for (std::size_t e = 0; e < edges_.size(); ++e) {
    const Primitive& p = edges_[e];
    edge_nodes[2 * e] = p.node[0], edge_nodes[2 * e + 1] = p.node[1];
    gid[e] = p.gid;
    rest2[e] = p.rest_length2;
  }
  // The owned edges' weights (fixed for the run), NaN for the ghosts after them.
  std::vector<double> weight(owned_edge_weight_);
  weight.resize(edges_.size(), std::numeric_limits<double>::quiet_NaN());
  device::DevicePairSources& d = device_pair_sources_;
  d.face_nodes.upload(face_nodes), d.edge_nodes.upload(edge_nodes), d.edge_gid.upload(gid);
  d.edge_rest2.upload(rest2), d.edge_weight.upload(weight);
}

void ContactSet::upload_pair_sources_fixed() {
  std::vector<double> area(mesh_.local_to_global.size(), std::numeric_limits<double>::quiet_NaN());
  for (const auto& [node, a] : node_area_)
    if (static_cast<std::size_t>(node) < area.size()) area[static_cast<std::size_t>(node)] = a;
  // describe's weight of a pair whose edge has the smaller global id, which is always one of the
  // rank's own (pair_filter.hpp).
  owned_edge_weight_.resize(owned_edges_);
  for (std::size_t e = 0; e < owned_edges_; ++e)
    owned_edge_weight_[e] = 0.5 * (node_area_.at(edges_[e].node[0]) + node_area_.at(edges_[e].node[1]));
  std::vector<std::int32_t> faces, edges;
  for (const auto& f : obstacles_.faces) faces.insert(faces.end(), f.begin(), f.end());
  for (const auto& e : obstacles_.edges) edges.insert(edges.end(), e.begin(), e.end());
  device::DevicePairSources& d = device_pair_sources_;
  d.vertex_area.upload(area);
  d.obstacle_face_nodes.upload(faces), d.obstacle_edge_nodes.upload(edges);
  d.obstacle_edge_rest2.upload(obstacles_.edge_rest_length2), d.obstacle_vertex_area.upload(obstacles_.vertex_area);
}

void ContactSet::describe_on_device(device::DeviceContactPairs* out) {
  const std::array<const std::vector<std::array<std::int32_t, 2>>*, kNumCandidateKinds> lists = {
      &vertex_face_, &edge_edge_, &vertex_plane_, &vertex_obstacle_face_, &edge_obstacle_edge_, &obstacle_vertex_face_};
  const std::array<std::size_t, kNumCandidateKinds + 1> first = candidate_starts();
  // Each list straight into its slice (an array of int32 pairs is 2 int32 per pair).
  static_assert(sizeof(std::array<std::int32_t, 2>) == 2 * sizeof(std::int32_t));
  device_candidate_index_.resize(2 * first[kNumCandidateKinds]);
  for (int k = 0; k < kNumCandidateKinds; ++k)
    if (!lists[k]->empty())
      device::copy_to_device(device_candidate_index_.data() + 2 * first[k], lists[k]->data(),
                             lists[k]->size() * sizeof(std::array<std::int32_t, 2>));
  device::build_candidate_pairs(device_pair_sources_, device_candidate_index_, first, out);
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
void ContactSet::append_obstacles(device::BroadPhaseSurface* s) const {
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

void ContactSet::move_obstacles(double t0, double t1) {
  obstacles_.move(parameters_.obstacles, t0, t1);
  // The positions are functions of the two times alone: the device keeps them while those stay.
  if (space_ == MemorySpace::device && !(t0 == uploaded_t0_ && t1 == uploaded_t1_)) {
    upload_obstacle_positions();
    uploaded_t0_ = t0, uploaded_t1_ = t1;
  }
}

// Device space: the obstacle vertices' positions to the device, for the broad phase, the
// barrier and the CCD.
void ContactSet::upload_obstacle_positions() {
  if (obstacles_.empty()) return;
  const std::size_t n = 3 * static_cast<std::size_t>(obstacles_.num_vertices());
  const double* start = obstacles_.start(0);
  const double* end = obstacles_.end(0);
  device_obstacles_.upload_vertices(std::vector<double>(start, start + n), std::vector<double>(end, end + n));
}

void ContactSet::find_candidates(const double* x, const double* p) {
  if (space_ == MemorySpace::device)
    find_candidates_on_device(x, p);
  else
    find_candidates_on_host(x, p);
}

void ContactSet::find_candidates_on_host(const double* x, const double* p) {
  const double start = MPI_Wtime();
  device::BroadPhaseSurface s = number_surface();
  const std::vector<std::int32_t>& node_of = s.vertex_node;
  const std::size_t nv = node_of.size();
  std::vector<double> x0(3 * nv), x1(3 * nv);
  bool moving = false;
  Aabb reach = aabb_empty();  // the body surface over the segment
  for (std::size_t v = 0; v < nv; ++v) {
    for (int c = 0; c < 3; ++c) {
      x0[3 * v + c] = x[3 * node_of[v] + c];
      x1[3 * v + c] = x0[3 * v + c] + p[3 * node_of[v] + c];
      moving = moving || p[3 * node_of[v] + c] != 0.0;
    }
    aabb_add_point(&reach, &x0[3 * v]);
    aabb_add_point(&reach, &x1[3 * v]);
  }
  // Obstacle primitives near this rank's surface (within d̂ of its swept box) join the search
  // after the body's, in group −1, so the body's pairs come out as without obstacles.
  const std::size_t body_edges = edges_.size(), body_faces = faces_.size();
  ObstacleSurface::Near near;
  if (!obstacles_.empty() && nv > 0) {
    aabb_inflate(&reach, parameters_.dhat);
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
  // The filters of the device search (contact/broad_phase/pair_filter.hpp), with the near
  // obstacle primitives' entries as append_obstacles gives them all on the device: obstacle
  // vertices leave their pairs to the face's owner, obstacle edges to the body edge's owner.
  s.owned_vertex.resize(x0.size() / 3, contact::kFaceDecides);
  s.owned_face.assign(s.faces.size() / 3, 0);
  for (std::size_t f = 0; f < owned_faces_; ++f) s.owned_face[f] = 1;
  s.edge_gid.resize(s.edges.size() / 2, std::numeric_limits<std::int64_t>::max());
  s.owned_edge.resize(s.edges.size() / 2, 0);
  contact::PairFilter pf;
  pf.group = s.vertex_group.data();
  pf.self = s.self_contact.data();
  pf.num_self = static_cast<int>(s.self_contact.size());
  pf.owned_vertex = s.owned_vertex.data();
  pf.owned_face = s.owned_face.data();
  pf.edge_gid = s.edge_gid.data();
  pf.owned_edge = s.owned_edge.data();
  contact::CandidateFilter filter;
  filter.allow_groups = [&pf](int a, int b) { return contact::groups_may_touch(pf, a, b); };
  filter.keep_vertex_face = [&pf](std::int32_t v, std::int32_t f) { return contact::keeps_vertex_face(pf, v, f); };
  filter.keep_edge_edge = [&pf](std::int32_t a, std::int32_t b) { return contact::keeps_edge_edge(pf, a, b); };
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
  stats_->broad_phase_seconds += MPI_Wtime() - start;
}

// The same search as find_candidates_on_host on device arrays, over the surface uploaded by the last
// exchange that changed it (device_broad_phase.hpp gives the host search's lists); only the
// candidate lists come back.
void ContactSet::find_candidates_on_device(const double* x, const double* p) {
  const double start = MPI_Wtime();
  contact::Candidates candidates;
  device::PrescribedVertices prescribed;
  if (!obstacles_.empty()) {
    prescribed.start = device_obstacles_.vertex_start.data();
    prescribed.end = device_obstacles_.vertex_end.data();
    prescribed.moving = obstacles_.moving();
  }
  device_broad_phase_.find_candidates_on_segment(x, p, 0.5 * parameters_.dhat, &candidates, prescribed);
  // Split as find_candidates_on_host does: obstacle primitives follow the body's (append_obstacles).
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
  stats_->broad_phase_seconds += MPI_Wtime() - start;
}

ContactSet::PairInfo ContactSet::describe(CandidateKind kind, std::size_t i) const {
  PairInfo info;
  switch (kind) {
    case CandidateKind::vertex_face: {
      info.kind = PairKind::vertex_triangle;
      const auto& f = faces_[vertex_face_[i][1]];
      info.nodes = {vertex_face_[i][0], f.node[0], f.node[1], f.node[2]};
      info.count = 4;
      info.weight = node_area_.at(info.nodes[0]);
      break;
    }
    case CandidateKind::edge_edge: {
      info.kind = PairKind::edge_edge;
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
      break;
    }
    case CandidateKind::vertex_plane:
      info.kind = PairKind::vertex_plane;
      info.nodes = {vertex_plane_[i][0], -1, -1, -1};
      info.count = 1;
      info.plane = &parameters_.planes[vertex_plane_[i][1]];
      info.weight = node_area_.at(info.nodes[0]);
      break;
    case CandidateKind::vertex_obstacle_face: {
      const auto& f = obstacles_.faces[vertex_obstacle_face_[i][1]];
      info.kind = PairKind::vertex_triangle;
      info.nodes = {vertex_obstacle_face_[i][0], obstacle_node(f[0]), obstacle_node(f[1]), obstacle_node(f[2])};
      info.count = 4;
      info.weight = node_area_.at(info.nodes[0]);
      break;
    }
    case CandidateKind::edge_obstacle_edge: {  // the body's edge first, always
      const Primitive& a = edges_[edge_obstacle_edge_[i][0]];
      const std::int32_t b = edge_obstacle_edge_[i][1];
      info.kind = PairKind::edge_edge;
      info.nodes = {a.node[0], a.node[1], obstacle_node(obstacles_.edges[b][0]), obstacle_node(obstacles_.edges[b][1])};
      info.count = 4;
      info.weight = 0.5 * (node_area_.at(a.node[0]) + node_area_.at(a.node[1]));
      info.eps_x = 1e-3 * a.rest_length2 * obstacles_.edge_rest_length2[b];
      break;
    }
    case CandidateKind::obstacle_vertex_face: {
      const std::int32_t v = obstacle_vertex_face_[i][0];
      const auto& f = faces_[obstacle_vertex_face_[i][1]];
      info.kind = PairKind::vertex_triangle;
      info.nodes = {obstacle_node(v), f.node[0], f.node[1], f.node[2]};
      info.count = 4;
      info.weight = obstacles_.vertex_area[v];
      break;
    }
  }
  return info;
}

void ContactSet::gather(const double* x, const PairInfo& info, double* X) const {
  for (int k = 0; k < info.count; ++k) {
    const double* xk = position(x, info.nodes[k]);
    for (int c = 0; c < 3; ++c) X[3 * k + c] = xk[c];
  }
}

void ContactSet::gather_segment(const double* x, const double* p, const PairInfo& info, double* X0, double* X1) const {
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

}  // namespace dipc
