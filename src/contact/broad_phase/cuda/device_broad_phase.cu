// device_broad_phase.hpp on the CUDA device.
//
// Each search (triangles queried by vertices, edges queried by edges) builds a linear BVH over
// the primitives' boxes: boxes from contact::primitive_box (the CPU's function), 63-bit Morton
// codes of their centres, a radix sort, Karras's parallel hierarchy over the sorted codes, and
// node boxes merged bottom-up. One thread per query box then walks the tree twice: once to
// count the pairs that pass the exclusions and filters, once, after a prefix sum of the
// counts, to write them as 64-bit keys (first << 32 | second), which a radix sort puts in the
// lexicographic order of the CPU's lists.
//
// A BVH rather than a one-axis sort and sweep: surfaces made of axis-aligned faces (every box
// and mesh generator's output) put whole faces of triangles at one coordinate, and a sweep
// along that axis would compare each of their vertices with all of them.
//
// Identity with the CPU: boxes are minima and maxima of coordinates moved by the inflation,
// node boxes unions of those (exact), and every test is the closed aabbs_overlap, so each box
// decision is the CPU's bit for bit. The tree's shape decides how fast a pair is found, never
// whether; each primitive is one leaf, so each pair is found once. The file is compiled with
// --fmad=false like the contact kernels, so no arithmetic on coordinates can round otherwise
// than on the CPU.
#include "contact/broad_phase/cuda/device_broad_phase.hpp"

#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_reduce.cuh>
#include <cub/device/device_scan.cuh>

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <string>

#include "contact/broad_phase/aabb.hpp"
#include "contact/broad_phase/pair_filter.hpp"
#include "device/cuda_check.cuh"

namespace dipc::device {

using contact::BroadPhaseError;

namespace {

constexpr int kThreads = 128;
// Traversal stack. Along a root-to-leaf path the common prefix of the node's sorted keys grows
// by at least one bit per level, and a key is the 63-bit Morton code followed by the leaf
// index (31 bits, which break ties), so a path has fewer than 95 inner nodes; the stack holds
// one pending sibling per level plus the two children of the node being expanded.
constexpr int kStack = 128;
constexpr int kMortonBits = 21;  // per axis

// Device pointers of an uploaded surface, passed to kernels by value.
struct SurfaceData {
  const std::int32_t* edges;
  const std::int32_t* faces;
  contact::PairFilter filter;  // the filters of pair_filter.hpp, on device arrays
};

// A BVH over n >= 1 boxes: nodes 0 .. n−2 are inner nodes (0 the root), nodes n−1 .. 2n−2 the
// leaves in Morton order; a lone leaf is node 0, the root.
struct TreeView {
  int n;
  const Aabb* box;           // 2n − 1 node boxes
  const std::int32_t* left;  // children of the inner nodes
  const std::int32_t* right;
  const std::int32_t* leaf_id;  // the primitive of leaf j (node n − 1 + j)
};

// Calls visit(id) once for every primitive whose box overlaps `query`, as Bvh::for_each_overlap.
template <class Visit>
__device__ void for_each_overlap(const TreeView& t, const Aabb& query, Visit&& visit) {
  std::int32_t stack[kStack];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const std::int32_t node = stack[--top];
    if (!aabbs_overlap(t.box[node], query)) continue;
    if (node >= t.n - 1) {
      visit(t.leaf_id[node - (t.n - 1)]);
    } else {
      stack[top++] = t.right[node];
      stack[top++] = t.left[node];
    }
  }
}

// Vertex v's box against the triangles, with find_candidates' exclusion and filters.
struct VertexFaceQuery {
  TreeView tree;
  SurfaceData s;
  const double* x0;
  const double* x1;
  double inflation;

  __device__ Aabb box(std::int32_t v) const { return contact::primitive_box(x0, x1, &v, 1, inflation); }
  __device__ bool keep(std::int32_t v, std::int32_t f) const {
    const std::int32_t* tri = s.faces + 3 * static_cast<std::int64_t>(f);
    if (tri[0] == v || tri[1] == v || tri[2] == v) return false;
    const contact::PairFilter& pf = s.filter;
    if (pf.group && !contact::groups_may_touch(pf, pf.group[v], pf.group[tri[0]])) return false;
    return contact::keeps_vertex_face(pf, v, f);
  }
};

// Edge a's box against the edges; each unordered pair once, from its smaller edge.
struct EdgeEdgeQuery {
  TreeView tree;
  SurfaceData s;
  const Aabb* boxes;

  __device__ Aabb box(std::int32_t a) const { return boxes[a]; }
  __device__ bool keep(std::int32_t a, std::int32_t b) const {
    if (b <= a) return false;
    const std::int32_t* ea = s.edges + 2 * static_cast<std::int64_t>(a);
    const std::int32_t* eb = s.edges + 2 * static_cast<std::int64_t>(b);
    if (ea[0] == eb[0] || ea[0] == eb[1] || ea[1] == eb[0] || ea[1] == eb[1]) return false;
    const contact::PairFilter& pf = s.filter;
    if (pf.group && !contact::groups_may_touch(pf, pf.group[ea[0]], pf.group[eb[0]])) return false;
    return contact::keeps_edge_edge(pf, a, b);
  }
};

__device__ std::size_t thread_index() { return blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x; }

// x0 and x1 of each vertex: x and x + p at its node's row, or a prescribed vertex's start and
// end (node −2 − k: row k).
__global__ void gather_kernel(const std::int32_t* node, int n, const double* x, const double* p,
                              PrescribedVertices prescribed, double* x0, double* x1, int* moving) {
  const std::size_t v = thread_index();
  if (v >= static_cast<std::size_t>(n)) return;
  if (node[v] <= -2) {
    const std::size_t row = 3 * static_cast<std::size_t>(-2 - node[v]);
    for (int c = 0; c < 3; ++c) {
      x0[3 * v + c] = prescribed.start[row + c];
      x1[3 * v + c] = prescribed.end[row + c];
    }
    return;
  }
  const std::size_t row = 3 * static_cast<std::size_t>(node[v]);
  for (int c = 0; c < 3; ++c) {
    x0[3 * v + c] = x[row + c];
    x1[3 * v + c] = x0[3 * v + c] + p[row + c];
    if (p[row + c] != 0.0) *moving = 1;
  }
}

// *first = the smallest vertex with a non-finite coordinate (left alone when there is none).
__global__ void first_non_finite_kernel(const double* x, int n, int* first) {
  const std::size_t v = thread_index();
  if (v >= static_cast<std::size_t>(n)) return;
  if (!isfinite(x[3 * v]) || !isfinite(x[3 * v + 1]) || !isfinite(x[3 * v + 2])) atomicMin(first, static_cast<int>(v));
}

__global__ void boxes_kernel(const double* x0, const double* x1, const std::int32_t* ids, int per, int n,
                             double inflation, Aabb* boxes) {
  const std::size_t e = thread_index();
  if (e >= static_cast<std::size_t>(n)) return;
  boxes[e] = contact::primitive_box(x0, x1, ids + per * e, per, inflation);
}

// The 21 low bits of v moved to every third bit.
__device__ std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

// Morton code of each box's centre within the bounds of all boxes, and the box's id.
__global__ void morton_kernel(const Aabb* boxes, int n, const Aabb* bounds, std::uint64_t* codes, std::int32_t* ids) {
  const std::size_t i = thread_index();
  if (i >= static_cast<std::size_t>(n)) return;
  const double cells = static_cast<double>(1 << kMortonBits);
  std::uint64_t code = 0;
  for (int k = 0; k < 3; ++k) {
    const double extent = bounds->hi[k] - bounds->lo[k];
    const double centre = 0.5 * boxes[i].lo[k] + 0.5 * boxes[i].hi[k];
    // Quantisation only shapes the tree: fmax/fmin also send an infinite or NaN ratio into range.
    const double u = extent > 0 ? (centre - bounds->lo[k]) / extent : 0.0;
    const double q = fmin(fmax(u * cells, 0.0), cells - 1.0);
    code |= spread_bits(static_cast<std::uint64_t>(q)) << (2 - k);
  }
  codes[i] = code;
  ids[i] = static_cast<std::int32_t>(i);
}

__global__ void leaves_kernel(const Aabb* boxes, const std::int32_t* sorted_ids, int n, Aabb* node_box,
                              std::int32_t* parent) {
  const std::size_t j = thread_index();
  if (j >= static_cast<std::size_t>(n)) return;
  node_box[n - 1 + j] = boxes[sorted_ids[j]];
  if (j == 0) parent[0] = -1;
}

// Length of the common prefix of the keys (code, index) of sorted leaves i and j; −1 when j is
// outside [0, n).
__device__ int common_prefix(const std::uint64_t* codes, int n, int i, long long j) {
  if (j < 0 || j >= n) return -1;
  const std::uint64_t a = codes[i], b = codes[j];
  if (a == b) return 64 + __clz(i ^ static_cast<int>(j));
  return __clzll(a ^ b);
}

// Inner node i of Karras's hierarchy: the range of sorted leaves it covers (one end is i) and
// the split where its keys' common prefix ends.
__global__ void hierarchy_kernel(const std::uint64_t* codes, int n, std::int32_t* left, std::int32_t* right,
                                 std::int32_t* parent) {
  const std::size_t index = thread_index();
  if (index >= static_cast<std::size_t>(n - 1)) return;
  const int i = static_cast<int>(index);
  const int d = common_prefix(codes, n, i, i + 1) > common_prefix(codes, n, i, i - 1) ? 1 : -1;
  const int prefix_min = common_prefix(codes, n, i, i - d);
  long long length_max = 2;
  while (common_prefix(codes, n, i, i + length_max * d) > prefix_min) length_max *= 2;
  long long length = 0;
  for (long long t = length_max / 2; t >= 1; t /= 2)
    if (common_prefix(codes, n, i, i + (length + t) * d) > prefix_min) length += t;
  const int j = static_cast<int>(i + length * d);
  const int prefix_node = common_prefix(codes, n, i, j);
  long long split = 0;
  long long t = length;
  do {
    t = (t + 1) / 2;
    if (common_prefix(codes, n, i, i + (split + t) * d) > prefix_node) split += t;
  } while (t > 1);
  const int gamma = static_cast<int>(i + split * d + (d < 0 ? -1 : 0));
  const int l = (i < j ? i : j) == gamma ? n - 1 + gamma : gamma;
  const int r = (i > j ? i : j) == gamma + 1 ? n - 1 + gamma + 1 : gamma + 1;
  left[i] = l;
  right[i] = r;
  parent[l] = i;
  parent[r] = i;
}

// A node box written by another thread of the running kernel: read from L2, past this
// multiprocessor's L1.
__device__ Aabb load_shared_box(const Aabb* b) {
  Aabb out;
  for (int k = 0; k < 3; ++k) {
    out.lo[k] = __ldcg(&b->lo[k]);
    out.hi[k] = __ldcg(&b->hi[k]);
  }
  return out;
}

// Bottom-up unions: one thread per leaf climbs; at each inner node the first of its two
// children's threads stops and the second, which then sees both child boxes, merges them.
__global__ void refit_kernel(int n, const std::int32_t* left, const std::int32_t* right, const std::int32_t* parent,
                             int* visits, Aabb* node_box) {
  const std::size_t j = thread_index();
  if (j >= static_cast<std::size_t>(n)) return;
  std::int32_t node = parent[n - 1 + j];
  while (node >= 0) {
    __threadfence();  // this thread's box writes before its arrival
    if (atomicAdd(&visits[node], 1) == 0) return;
    Aabb box = load_shared_box(&node_box[left[node]]);
    aabb_merge(&box, load_shared_box(&node_box[right[node]]));
    node_box[node] = box;
    node = parent[node];
  }
}

template <class Query>
__global__ void count_kernel(Query q, int n, long long* counts) {
  const std::size_t i = thread_index();
  if (i > static_cast<std::size_t>(n)) return;
  if (i == static_cast<std::size_t>(n)) {  // so the exclusive sum ends with the total
    counts[n] = 0;
    return;
  }
  const auto a = static_cast<std::int32_t>(i);
  long long count = 0;
  for_each_overlap(q.tree, q.box(a), [&](std::int32_t b) { count += q.keep(a, b) ? 1 : 0; });
  counts[i] = count;
}

template <class Query>
__global__ void write_kernel(Query q, int n, const long long* offsets, std::uint64_t* keys) {
  const std::size_t i = thread_index();
  if (i >= static_cast<std::size_t>(n)) return;
  const auto a = static_cast<std::int32_t>(i);
  long long k = offsets[i];
  for_each_overlap(q.tree, q.box(a), [&](std::int32_t b) {
    if (q.keep(a, b)) keys[k++] = static_cast<std::uint64_t>(a) << 32 | static_cast<std::uint32_t>(b);
  });
}

// Keys back to (first, second) pairs, the layout of std::array<std::int32_t, 2>.
__global__ void split_keys_kernel(const std::uint64_t* keys, long long count, std::int32_t* pairs) {
  const std::size_t k = thread_index();
  if (k >= static_cast<std::size_t>(count)) return;
  pairs[2 * k] = static_cast<std::int32_t>(keys[k] >> 32);
  pairs[2 * k + 1] = static_cast<std::int32_t>(keys[k] & 0xffffffffULL);
}

struct MergeBoxes {
  __host__ __device__ Aabb operator()(const Aabb& a, const Aabb& b) const {
    Aabb r = a;
    aabb_merge(&r, b);
    return r;
  }
};

// CUB scratch: never null, since CUB takes a null pointer as a request for the size.
void* scratch(Array<unsigned char>& temp, std::size_t bytes) {
  temp.resize(bytes > 0 ? bytes : 1);
  return temp.data();
}

// offsets = exclusive sum of counts[0 .. n]; returns offsets[n], the total.
long long exclusive_sum(const Array<long long>& counts, Array<long long>& offsets, std::size_t n,
                        Array<unsigned char>& temp) {
  offsets.resize(n + 1);
  std::size_t bytes = 0;
  DIPC_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(nullptr, bytes, counts.data(), offsets.data(), n + 1));
  DIPC_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(scratch(temp, bytes), bytes, counts.data(), offsets.data(), n + 1));
  long long total = 0;
  copy_to_host(&total, offsets.data() + n, sizeof total);
  return total;
}

static_assert(sizeof(std::array<std::int32_t, 2>) == 2 * sizeof(std::int32_t),
              "pairs are copied into std::array<std::int32_t, 2> as two int32 each");

}  // namespace

struct DeviceBroadPhase::Impl {
  int num_vertices = 0, num_edges = 0, num_faces = 0, num_self = 0;
  bool groups = false, owned_vertices = false, owned_edges = false, nodes = false;
  bool prescribed_rows = false;  // some vertex_node is −2 − k
  Array<std::int32_t> edges{"broad phase edges"}, faces{"broad phase faces"}, group{"broad phase groups"},
      node{"broad phase vertex nodes"};
  Array<char> self{"broad phase self-contact flags"}, owned_vertex{"broad phase owned vertices"},
      owned_face{"broad phase owned faces"}, owned_edge{"broad phase owned edges"};
  Array<std::int64_t> edge_gid{"broad phase edge ids"};

  // Workspace, grown as needed.
  Array<double> x0{"broad phase x0"}, x1{"broad phase x1"};
  Array<int> first_non_finite{"broad phase finiteness check"};  // vertex of x0, of x1
  Array<int> moving{"broad phase motion flag"};
  Array<Aabb> boxes{"broad phase primitive boxes"}, bounds{"broad phase bounds"}, node_box{"BVH node boxes"};
  Array<std::uint64_t> codes{"Morton codes"}, sorted_codes{"sorted Morton codes"};
  Array<std::int32_t> ids{"BVH primitive ids"}, leaf_id{"BVH leaf ids"}, left{"BVH left children"},
      right{"BVH right children"}, parent{"BVH parents"};
  Array<int> visits{"BVH refit counters"};
  Array<long long> counts{"candidate counts"}, offsets{"candidate offsets"};
  Array<std::uint64_t> keys{"candidate keys"}, sorted_keys{"sorted candidate keys"};
  Array<unsigned char> temp{"CUB scratch"};

  SurfaceData surface() const {
    contact::PairFilter filter;
    filter.group = groups ? group.data() : nullptr;
    filter.self = self.data();
    filter.num_self = num_self;
    filter.owned_vertex = owned_vertices ? owned_vertex.data() : nullptr;
    filter.owned_face = owned_face.data();
    filter.edge_gid = owned_edges ? edge_gid.data() : nullptr;
    filter.owned_edge = owned_edge.data();
    return {edges.data(), faces.data(), filter};
  }

  // The BVH over boxes[0 .. n), n >= 1.
  TreeView build_tree(const Aabb* primitive_boxes, int n) {
    const std::size_t count = static_cast<std::size_t>(n);
    const unsigned blocks = blocks_for(count, kThreads);
    const Aabb empty = aabb_empty();
    bounds.resize(1);
    std::size_t bytes = 0;
    DIPC_CUDA_CHECK(
        cub::DeviceReduce::Reduce(nullptr, bytes, primitive_boxes, bounds.data(), count, MergeBoxes{}, empty));
    DIPC_CUDA_CHECK(cub::DeviceReduce::Reduce(scratch(temp, bytes), bytes, primitive_boxes, bounds.data(), count,
                                              MergeBoxes{}, empty));
    codes.resize(count), sorted_codes.resize(count), ids.resize(count), leaf_id.resize(count);
    morton_kernel<<<blocks, kThreads>>>(primitive_boxes, n, bounds.data(), codes.data(), ids.data());
    DIPC_CUDA_CHECK_LAUNCH();
    // Stable: equal codes keep the order of the ids, so the tree depends only on the boxes.
    bytes = 0;
    DIPC_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(nullptr, bytes, codes.data(), sorted_codes.data(), ids.data(),
                                                    leaf_id.data(), count, 0, 3 * kMortonBits));
    DIPC_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(scratch(temp, bytes), bytes, codes.data(), sorted_codes.data(),
                                                    ids.data(), leaf_id.data(), count, 0, 3 * kMortonBits));
    node_box.resize(2 * count - 1), parent.resize(2 * count - 1);
    left.resize(count - 1), right.resize(count - 1), visits.resize(count - 1);
    leaves_kernel<<<blocks, kThreads>>>(primitive_boxes, leaf_id.data(), n, node_box.data(), parent.data());
    DIPC_CUDA_CHECK_LAUNCH();
    if (n > 1) {
      hierarchy_kernel<<<blocks_for(count - 1, kThreads), kThreads>>>(sorted_codes.data(), n, left.data(), right.data(),
                                                                      parent.data());
      DIPC_CUDA_CHECK_LAUNCH();
      visits.set_zero();
      refit_kernel<<<blocks, kThreads>>>(n, left.data(), right.data(), parent.data(), visits.data(), node_box.data());
      DIPC_CUDA_CHECK_LAUNCH();
    }
    return {n, node_box.data(), left.data(), right.data(), leaf_id.data()};
  }

  // Every pair (a, b) of the n queries that the query keeps, sorted, into *out.
  template <class Query>
  void collect(const Query& q, int n, std::vector<std::array<std::int32_t, 2>>* out) {
    const std::size_t count = static_cast<std::size_t>(n);
    counts.resize(count + 1);
    count_kernel<<<blocks_for(count + 1, kThreads), kThreads>>>(q, n, counts.data());
    DIPC_CUDA_CHECK_LAUNCH();
    const long long total = exclusive_sum(counts, offsets, count, temp);
    if (total == 0) return;
    const std::size_t pairs = static_cast<std::size_t>(total);
    keys.resize(pairs), sorted_keys.resize(pairs);
    write_kernel<<<blocks_for(count, kThreads), kThreads>>>(q, n, offsets.data(), keys.data());
    DIPC_CUDA_CHECK_LAUNCH();
    // The first index fills the high word, and needs only as many bits as n − 1 has.
    int first_bits = 0;
    while ((1LL << first_bits) < n) ++first_bits;
    std::size_t bytes = 0;
    DIPC_CUDA_CHECK(
        cub::DeviceRadixSort::SortKeys(nullptr, bytes, keys.data(), sorted_keys.data(), pairs, 0, 32 + first_bits));
    DIPC_CUDA_CHECK(cub::DeviceRadixSort::SortKeys(scratch(temp, bytes), bytes, keys.data(), sorted_keys.data(), pairs,
                                                   0, 32 + first_bits));
    // The unsorted keys are no longer needed: their storage takes the pairs.
    auto* split = reinterpret_cast<std::int32_t*>(keys.data());
    split_keys_kernel<<<blocks_for(pairs, kThreads), kThreads>>>(sorted_keys.data(), total, split);
    DIPC_CUDA_CHECK_LAUNCH();
    out->resize(pairs);
    copy_to_host(out->data(), split, pairs * sizeof(std::array<std::int32_t, 2>));
  }

  // Throws BroadPhaseError naming the first vertex with a non-finite coordinate in x0, else in
  // x1, as find_candidates' input check does.
  void check_finite(const double* p0, const double* p1) {
    const int none[2] = {INT_MAX, INT_MAX};
    first_non_finite.upload(none, 2);
    const unsigned blocks = blocks_for(static_cast<std::size_t>(num_vertices), kThreads);
    first_non_finite_kernel<<<blocks, kThreads>>>(p0, num_vertices, first_non_finite.data());
    DIPC_CUDA_CHECK_LAUNCH();
    if (p1) {
      first_non_finite_kernel<<<blocks, kThreads>>>(p1, num_vertices, first_non_finite.data() + 1);
      DIPC_CUDA_CHECK_LAUNCH();
    }
    int first[2];
    first_non_finite.download(first);
    for (int which = 0; which < 2; ++which) {
      if (first[which] == INT_MAX) continue;
      const int v = first[which];
      double coordinates[3];
      copy_to_host(coordinates, (which == 0 ? p0 : p1) + 3 * static_cast<std::size_t>(v), sizeof coordinates);
      int k = 0;
      while (k < 2 && std::isfinite(coordinates[k])) ++k;
      throw BroadPhaseError("find_candidates: vertex " + std::to_string(v) + " has a non-finite " +
                            (which == 0 ? "x0" : "x1") + " coordinate " + std::to_string(k));
    }
  }
};

namespace {

// find_candidates' check of a connectivity array, with its message.
void check_ids(const std::vector<std::int32_t>& ids, int per, int num_vertices, const char* kind) {
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const std::int32_t v = ids[i];
    if (v < 0 || v >= num_vertices) {
      throw BroadPhaseError("find_candidates: " + std::string(kind) + " " + std::to_string(i / per) + " vertex " +
                            std::to_string(i % per) + " = " + std::to_string(v) + " is outside [0, " +
                            std::to_string(num_vertices) + ")");
    }
  }
}

// Number of primitives in a connectivity array of `per` ids each.
int primitive_count(const std::vector<std::int32_t>& ids, int per, const char* kind) {
  if (ids.size() % per != 0 || ids.size() / per > static_cast<std::size_t>(INT_MAX)) {
    throw BroadPhaseError("DeviceBroadPhase: " + std::to_string(ids.size()) + " " + kind +
                          " vertex ids are not a whole number of " + kind + "s (" + std::to_string(per) +
                          " each) that fit in 32-bit ids");
  }
  return static_cast<int>(ids.size() / per);
}

template <class T>
void check_length(const std::vector<T>& values, int count, const char* what, const char* per) {
  if (!values.empty() && values.size() != static_cast<std::size_t>(count)) {
    throw BroadPhaseError("DeviceBroadPhase: " + std::string(what) + " has " + std::to_string(values.size()) +
                          " entries for " + std::to_string(count) + " " + per + "; give one each or none");
  }
}

}  // namespace

DeviceBroadPhase::DeviceBroadPhase() : impl_(std::make_unique<Impl>()) {}
DeviceBroadPhase::~DeviceBroadPhase() = default;
DeviceBroadPhase::DeviceBroadPhase(DeviceBroadPhase&&) noexcept = default;
DeviceBroadPhase& DeviceBroadPhase::operator=(DeviceBroadPhase&&) noexcept = default;

void DeviceBroadPhase::upload(const BroadPhaseSurface& s) {
  const int num_edges = primitive_count(s.edges, 2, "edge");
  const int num_faces = primitive_count(s.faces, 3, "face");
  if (s.num_vertices < 0) {
    throw BroadPhaseError("find_candidates: negative count (vertices " + std::to_string(s.num_vertices) + ", edges " +
                          std::to_string(num_edges) + ", faces " + std::to_string(num_faces) + ")");
  }
  check_ids(s.edges, 2, s.num_vertices, "edge");
  check_ids(s.faces, 3, s.num_vertices, "face");
  check_length(s.vertex_group, s.num_vertices, "vertex_group", "vertices");
  check_length(s.owned_vertex, s.num_vertices, "owned_vertex", "vertices");
  check_length(s.owned_face, num_faces, "owned_face", "faces");
  if (s.owned_face.empty() && num_faces > 0 &&
      std::find(s.owned_vertex.begin(), s.owned_vertex.end(), kFaceDecides) != s.owned_vertex.end())
    throw BroadPhaseError("DeviceBroadPhase: owned_vertex leaves pairs to the faces' owners (kFaceDecides) "
                          "but owned_face is not given");
  check_length(s.vertex_node, s.num_vertices, "vertex_node", "vertices");
  check_length(s.edge_gid, num_edges, "edge_gid", "edges");
  check_length(s.owned_edge, num_edges, "owned_edge", "edges");
  if (s.edge_gid.empty() != s.owned_edge.empty())
    throw BroadPhaseError("DeviceBroadPhase: the edge ownership filter needs both edge_gid and owned_edge");
  if (s.self_contact.size() > static_cast<std::size_t>(INT_MAX))
    throw BroadPhaseError("DeviceBroadPhase: too many self-contact flags");
  Impl& m = *impl_;
  m.num_vertices = s.num_vertices, m.num_edges = num_edges, m.num_faces = num_faces;
  m.num_self = static_cast<int>(s.self_contact.size());
  // Filters only where their data is given and there is something to filter.
  m.groups = !s.vertex_group.empty() && s.num_vertices > 0;
  m.owned_vertices = !s.owned_vertex.empty() && s.num_vertices > 0;
  m.owned_edges = !s.edge_gid.empty() && num_edges > 0;
  m.nodes = !s.vertex_node.empty() || s.num_vertices == 0;
  m.prescribed_rows = std::any_of(s.vertex_node.begin(), s.vertex_node.end(), [](std::int32_t n) { return n <= -2; });
  m.edges.upload(s.edges);
  m.faces.upload(s.faces);
  m.group.upload(s.vertex_group);
  m.self.upload(s.self_contact);
  m.owned_vertex.upload(s.owned_vertex);
  m.owned_face.upload(s.owned_face);
  m.edge_gid.upload(s.edge_gid);
  m.owned_edge.upload(s.owned_edge);
  m.node.upload(s.vertex_node);
}

void DeviceBroadPhase::find_candidates(const double* x0, const double* x1, double inflation, contact::Candidates* out) {
  if (out == nullptr) throw BroadPhaseError("find_candidates: output is null");
  if (!std::isfinite(inflation) || inflation < 0.0) {
    throw BroadPhaseError("find_candidates: inflation " + std::to_string(inflation) + " must be finite and >= 0");
  }
  Impl& m = *impl_;
  if (m.num_vertices > 0 && x0 == nullptr) {
    throw BroadPhaseError("find_candidates: x0 is null for " + std::to_string(m.num_vertices) + " vertices");
  }
  if (m.num_vertices > 0) m.check_finite(x0, x1);
  out->vertex_face.clear();
  out->edge_edge.clear();
  const SurfaceData s = m.surface();
  if (m.num_vertices > 0 && m.num_faces > 0) {
    m.boxes.resize(static_cast<std::size_t>(m.num_faces));
    boxes_kernel<<<blocks_for(m.boxes.size(), kThreads), kThreads>>>(x0, x1, m.faces.data(), 3, m.num_faces, inflation,
                                                                     m.boxes.data());
    DIPC_CUDA_CHECK_LAUNCH();
    const VertexFaceQuery q{m.build_tree(m.boxes.data(), m.num_faces), s, x0, x1, inflation};
    m.collect(q, m.num_vertices, &out->vertex_face);
  }
  if (m.num_edges > 1) {
    m.boxes.resize(static_cast<std::size_t>(m.num_edges));
    boxes_kernel<<<blocks_for(m.boxes.size(), kThreads), kThreads>>>(x0, x1, m.edges.data(), 2, m.num_edges, inflation,
                                                                     m.boxes.data());
    DIPC_CUDA_CHECK_LAUNCH();
    const EdgeEdgeQuery q{m.build_tree(m.boxes.data(), m.num_edges), s, m.boxes.data()};
    m.collect(q, m.num_edges, &out->edge_edge);
  }
}

void DeviceBroadPhase::find_candidates_on_segment(const double* x, const double* p, double inflation,
                                                  contact::Candidates* out, const PrescribedVertices& prescribed) {
  Impl& m = *impl_;
  if (!m.nodes) throw BroadPhaseError("find_candidates_on_segment: the uploaded surface has no vertex_node");
  if (m.prescribed_rows && (prescribed.start == nullptr || prescribed.end == nullptr))
    throw BroadPhaseError("find_candidates_on_segment: the uploaded surface has prescribed vertices (vertex_node "
                          "<= -2) but no prescribed positions were given");
  if (m.num_vertices == 0) return find_candidates(nullptr, nullptr, inflation, out);
  const std::size_t n = static_cast<std::size_t>(m.num_vertices);
  m.x0.resize(3 * n), m.x1.resize(3 * n), m.moving.resize(1);
  m.moving.set_zero();
  gather_kernel<<<blocks_for(n, kThreads), kThreads>>>(m.node.data(), m.num_vertices, x, p, prescribed, m.x0.data(),
                                                       m.x1.data(), m.moving.data());
  DIPC_CUDA_CHECK_LAUNCH();
  int moving = 0;
  m.moving.download(&moving);
  if (m.prescribed_rows && prescribed.moving) moving = 1;
  find_candidates(m.x0.data(), moving ? m.x1.data() : nullptr, inflation, out);
}

}  // namespace dipc::device
