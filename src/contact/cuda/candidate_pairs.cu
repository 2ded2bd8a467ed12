// build_candidate_pairs (contact_kernels.hpp): the candidate pair list made on the device from
// the pairs' indices, one thread per pair, with what ContactSet::describe
// (distributed/contact_candidates.cpp) gives each kind and DeviceContactPairs::upload
// (contact_pair_list.cpp) stores. The host list took a pass over every candidate on the host
// and a copy of 48 bytes per pair to the device at every Newton segment; the indices are 8.
//
// Compiled with --fmad=false, as the other contact kernels: ε_x = 1e-3 |ea|² |eb|² rounds as on
// the host.
#include <cub/device/device_scan.cuh>

#include "contact/cuda/contact_kernels.hpp"
#include "contact/obstacle_nodes.hpp"
#include "device/cuda_check.cuh"

namespace dipc::device {

namespace {

constexpr int kThreads = 128;

// Device pointers of the sources, passed by value.
struct SourceView {
  const std::int32_t* face;
  const std::int32_t* edge;
  const std::int64_t* edge_gid;
  const double* edge_rest2;
  const double* edge_weight;
  const double* vertex_area;
  const std::int32_t* obstacle_face;
  const std::int32_t* obstacle_edge;
  const double* obstacle_edge_rest2;
  const double* obstacle_vertex_area;
};

struct Firsts {
  std::size_t at[kNumCandidateKinds + 1];
};

// Pair s: kind, nodes (slot-major), weight, ε_x, plane, and its number of Hessian values (the
// body nodes' block, (3 b)²) in count[s].
__global__ void describe_pairs(SourceView src, const std::int32_t* index, Firsts first, std::size_t n,
                               std::int32_t* kind, std::int32_t* nodes, double* weight, double* eps_x,
                               std::int32_t* plane, std::size_t* count) {
  const std::size_t s = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (s >= n) return;
  int list = 0;
  while (s >= first.at[list + 1]) ++list;
  const std::int32_t a = index[2 * s], b = index[2 * s + 1];
  PairKind k = PairKind::vertex_triangle;
  std::int32_t node[4] = {-1, -1, -1, -1};
  double w = 0, eps = 0;
  std::int32_t pl = -1;
  switch (static_cast<CandidateKind>(list)) {
    case CandidateKind::vertex_face:
      node[0] = a, node[1] = src.face[3 * b], node[2] = src.face[3 * b + 1], node[3] = src.face[3 * b + 2];
      w = src.vertex_area[a];
      break;
    case CandidateKind::edge_edge: {
      // The edge with the smaller global id first; its weight is the pair's (describe).
      const bool swap = src.edge_gid[a] > src.edge_gid[b];
      const std::int32_t ea = swap ? b : a, eb = swap ? a : b;
      node[0] = src.edge[2 * ea], node[1] = src.edge[2 * ea + 1];
      node[2] = src.edge[2 * eb], node[3] = src.edge[2 * eb + 1];
      k = PairKind::edge_edge;
      w = src.edge_weight[src.edge_gid[ea] < src.edge_gid[eb] ? ea : eb];
      eps = 1e-3 * src.edge_rest2[ea] * src.edge_rest2[eb];
      break;
    }
    case CandidateKind::vertex_plane:
      node[0] = a;
      k = PairKind::vertex_plane;
      w = src.vertex_area[a];
      pl = b;
      break;
    case CandidateKind::vertex_obstacle_face:
      node[0] = a;
      for (int c = 0; c < 3; ++c) node[1 + c] = obstacle_node(src.obstacle_face[3 * b + c]);
      w = src.vertex_area[a];
      break;
    case CandidateKind::edge_obstacle_edge:  // the body's edge first
      node[0] = src.edge[2 * a], node[1] = src.edge[2 * a + 1];
      node[2] = obstacle_node(src.obstacle_edge[2 * b]), node[3] = obstacle_node(src.obstacle_edge[2 * b + 1]);
      k = PairKind::edge_edge;
      w = src.edge_weight[a];
      eps = 1e-3 * src.edge_rest2[a] * src.obstacle_edge_rest2[b];
      break;
    case CandidateKind::obstacle_vertex_face:
      node[0] = obstacle_node(a), node[1] = src.face[3 * b], node[2] = src.face[3 * b + 1], node[3] = src.face[3 * b + 2];
      w = src.obstacle_vertex_area[a];
      break;
  }
  kind[s] = static_cast<std::int32_t>(k);
  for (int c = 0; c < 4; ++c) nodes[c * n + s] = node[c];
  weight[s] = w;
  eps_x[s] = eps;
  plane[s] = pl;
  int slots[4];
  const std::size_t values = 3 * static_cast<std::size_t>(body_slots(node, pair_node_count(k), slots));
  count[s] = values * values;
}

}  // namespace

void build_candidate_pairs(const DevicePairSources& sources, const Array<std::int32_t>& index,
                           const std::array<std::size_t, kNumCandidateKinds + 1>& first, DeviceContactPairs* out) {
  const std::size_t n = first[kNumCandidateKinds];
  if (index.size() != 2 * n)
    throw DeviceError("build_candidate_pairs: " + std::to_string(index.size()) + " indices for " + std::to_string(n) +
                      " pairs (2 per pair)");
  out->count = n;
  out->kind.resize(n), out->nodes.resize(4 * n), out->weight.resize(n), out->eps_x.resize(n), out->plane.resize(n);
  // One more count than pairs: the exclusive sum's last entry is the list's number of values.
  out->hessian_offset.resize(n + 1);
  out->hessian_values = 0;
  if (n == 0) {
    out->hessian_offset.resize(0);
    return;
  }
  const SourceView src{sources.face_nodes.data(),          sources.edge_nodes.data(),
                       sources.edge_gid.data(),            sources.edge_rest2.data(),
                       sources.edge_weight.data(),         sources.vertex_area.data(),
                       sources.obstacle_face_nodes.data(), sources.obstacle_edge_nodes.data(),
                       sources.obstacle_edge_rest2.data(), sources.obstacle_vertex_area.data()};
  Firsts f{};
  for (int k = 0; k <= kNumCandidateKinds; ++k) f.at[k] = first[k];
  // The pairs' value counts, then their exclusive sum in place: the offsets.
  std::size_t* offset = out->hessian_offset.data();
  zero(offset + n, sizeof *offset);
  describe_pairs<<<blocks_for(n, kThreads), kThreads>>>(src, index.data(), f, n, out->kind.data(), out->nodes.data(),
                                                        out->weight.data(), out->eps_x.data(), out->plane.data(), offset);
  DIPC_CUDA_CHECK_LAUNCH();
  std::size_t bytes = 0;
  DIPC_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(nullptr, bytes, offset, n + 1));
  Array<unsigned char> scratch("contact pair scan scratch");
  scratch.resize(bytes);
  DIPC_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(scratch.data(), bytes, offset, n + 1));
  copy_to_host(&out->hessian_values, out->hessian_offset.data() + n, sizeof out->hessian_values);
  out->hessian_offset.resize(n);  // shrinking keeps the allocation
}

}  // namespace dipc::device
