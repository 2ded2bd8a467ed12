// contact_kernels.hpp on the CUDA device: one thread per contact pair, each calling the point
// functions of contact/contact_pair_terms.hpp.
//
// This file is compiled with --fmad=false (src/contact/CMakeLists.txt): without fused
// multiply-adds every +, −, ×, ÷ and √ rounds as on the CPU, so distances, active sets and
// times of impact are bit-identical to ContactForm's CPU loops (the CCD uses nothing else);
// the barrier terms differ only through log/log1p, within an ulp of the CPU's libm.
#include "contact/contact_pair_terms.hpp"
#include "contact/cuda/contact_kernels.hpp"
#include "contact/obstacle_nodes.hpp"
#include "device/cuda_check.cuh"

namespace dipc::device {

namespace {

// Threads per block. The reduction passes use kReduceThreads (cuda_check.cuh), the reducer's
// block size. The Hessian pass keeps three 12×12 matrices and the eigensolver's work in local
// memory per thread; smaller blocks spread that over more multiprocessors.
constexpr int kHessianThreads = 64;
constexpr int kThreads = 128;

// Device pointers of a pair list and the obstacles, passed to kernels by value.
struct PairView {
  std::size_t count;
  const std::int32_t* kind;
  const std::int32_t* nodes;
  const double* weight;
  const double* eps_x;
  const std::int32_t* plane;
  const double* plane_point;
  const double* plane_normal;
  const double* obstacle_start;  // triangle-mesh obstacle vertices, 3 per vertex
  const double* obstacle_end;
};

PairView view(const DeviceContactPairs& pairs, const DeviceContactObstacles& obstacles) {
  return {pairs.count,
          pairs.kind.data(),
          pairs.nodes.data(),
          pairs.weight.data(),
          pairs.eps_x.data(),
          pairs.plane.data(),
          obstacles.point.data(),
          obstacles.normal.data(),
          obstacles.vertex_start.data(),
          obstacles.vertex_end.data()};
}

// Position of a pair's node: row `node` of x, or an obstacle vertex's row of `obstacle`.
__device__ const double* node_position(const double* x, const double* obstacle, std::int32_t node) {
  return is_obstacle_node(node) ? obstacle + 3 * static_cast<std::size_t>(obstacle_vertex(node))
                                : x + 3 * static_cast<std::size_t>(node);
}

// One pair read from the list: kind, node count, ext-local nodes, stacked positions at x
// (obstacle vertices at their end positions) and plane (nullptr unless a vertex–plane pair).
struct Pair {
  PairKind kind;
  int count;
  std::int32_t node[4];
  double X[12];
  const double* plane_point;
  const double* plane_normal;
};

__device__ void load_pair(const PairView& v, std::size_t i, const double* x, Pair* pair) {
  pair->kind = static_cast<PairKind>(v.kind[i]);
  pair->count = pair_node_count(pair->kind);
  for (int k = 0; k < pair->count; ++k) {
    pair->node[k] = v.nodes[k * v.count + i];
    const double* xk = node_position(x, v.obstacle_end, pair->node[k]);
    for (int c = 0; c < 3; ++c) pair->X[3 * k + c] = xk[c];
  }
  const std::int32_t plane = v.plane[i];
  pair->plane_point = plane >= 0 ? v.plane_point + 3 * plane : nullptr;
  pair->plane_normal = plane >= 0 ? v.plane_normal + 3 * plane : nullptr;
}

__device__ bool pair_terms(const PairView& v, std::size_t i, const Pair& pair, const BarrierConstants& c, bool want_g,
                           bool want_H, bool* active, ContactPairTerms* t) {
  return contact_pair_terms(pair.kind, pair.X, pair.plane_point, pair.plane_normal, c.dhat2, c.kappa, v.weight[i],
                            v.eps_x[i], want_g, want_H, c.project, active, t);
}

__global__ void energy_kernel(PairView v, BarrierConstants c, const double* x, double* partials, int* failed) {
  __shared__ double scratch[kReduceThreads];
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  double e = 0;
  if (i < v.count) {
    Pair pair;
    load_pair(v, i, x, &pair);
    bool active;
    ContactPairTerms t;
    if (pair_terms(v, i, pair, c, false, false, &active, &t))
      e = t.energy;
    else
      *failed = 1;
  }
  const double sum = block_sum(e, scratch);
  if (threadIdx.x == 0) partials[blockIdx.x] = sum;
}

__global__ void gradient_kernel(PairView v, BarrierConstants c, const double* x, double* g, int* failed) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= v.count) return;
  Pair pair;
  load_pair(v, i, x, &pair);
  bool active;
  ContactPairTerms t;
  if (!pair_terms(v, i, pair, c, true, false, &active, &t)) {
    *failed = 1;
    return;
  }
  if (!active) return;
  for (int k = 0; k < pair.count; ++k)
    if (!is_obstacle_node(pair.node[k]))
      for (int d = 0; d < 3; ++d) atomicAdd(g + 3 * static_cast<std::size_t>(pair.node[k]) + d, t.g[3 * k + d]);
}

__global__ void hessian_kernel(PairView v, const std::size_t* offset, BarrierConstants c, const double* x,
                               double* values, int* failed) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= v.count) return;
  Pair pair;
  load_pair(v, i, x, &pair);
  bool active;
  ContactPairTerms t;
  if (!pair_terms(v, i, pair, c, true, true, &active, &t)) *failed = 1;
  // The body nodes' block (all of H without obstacle nodes), as ContactForm's COO pattern.
  int slots[4];
  const int num_slots = body_slots(pair.node, pair.count, slots);
  const int n = 3 * num_slots;
  double* out = values + offset[i];
  if (!active)
    for (int r = 0; r < n * n; ++r) out[r] = 0.0;
  else if (num_slots == pair.count)
    for (int r = 0; r < n * n; ++r) out[r] = t.H[r];
  else
    body_block(t.H, pair.count, slots, num_slots, out);
}

__global__ void active_kernel(PairView v, BarrierConstants c, const double* x, std::int32_t* active_out, int* failed) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= v.count) return;
  Pair pair;
  load_pair(v, i, x, &pair);
  bool active;
  ContactPairTerms t;
  if (!pair_terms(v, i, pair, c, false, false, &active, &t)) *failed = 1;
  active_out[i] = active ? 1 : 0;
}

__global__ void squared_distance_kernel(PairView v, const double* x, double* partials) {
  __shared__ double scratch[kReduceThreads];
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  double d = INFINITY;
  if (i < v.count) {
    Pair pair;
    load_pair(v, i, x, &pair);
    d = contact_pair_squared_distance(pair.kind, pair.X, pair.plane_point, pair.plane_normal);
  }
  const double m = block_min(d, scratch);
  if (threadIdx.x == 0) partials[blockIdx.x] = m;
}

// Time of impact of pair i along x + t p, obstacle vertices moving from their start to their
// end positions; the positions are formed as the CPU forms them (ContactForm::gather_segment).
__device__ double pair_time_of_impact(const PairView& v, std::size_t i, const double* x, const double* p,
                                      double t_max) {
  Pair pair;
  load_pair(v, i, x, &pair);
  double X1[12];
  for (int k = 0; k < pair.count; ++k) {
    const std::int32_t node = pair.node[k];
    if (is_obstacle_node(node)) {
      const double* start = v.obstacle_start + 3 * static_cast<std::size_t>(obstacle_vertex(node));
      const double* end = v.obstacle_end + 3 * static_cast<std::size_t>(obstacle_vertex(node));
      for (int c = 0; c < 3; ++c) pair.X[3 * k + c] = start[c], X1[3 * k + c] = end[c];
    } else {
      for (int c = 0; c < 3; ++c) X1[3 * k + c] = pair.X[3 * k + c] + p[3 * static_cast<std::size_t>(node) + c];
    }
  }
  return contact_pair_time_of_impact(pair.kind, pair.X, X1, pair.plane_point, pair.plane_normal, t_max);
}

__global__ void times_of_impact_kernel(PairView v, const double* x, const double* p, double t_max, double* toi) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i < v.count) toi[i] = pair_time_of_impact(v, i, x, p, t_max);
}

__global__ void min_time_of_impact_kernel(PairView v, const double* x, const double* p, double t_max,
                                          double* partials) {
  __shared__ double scratch[kReduceThreads];
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  const double toi = i < v.count ? pair_time_of_impact(v, i, x, p, t_max) : t_max;
  const double m = block_min(toi, scratch);
  if (threadIdx.x == 0) partials[blockIdx.x] = m;
}

}  // namespace

bool contact_barrier_energy(const DeviceContactPairs& pairs, const DeviceContactObstacles& obstacles,
                            const BarrierConstants& c, const double* x, Reducer& reducer, double* energy) {
  *energy = 0;
  if (pairs.count == 0) return true;
  const unsigned blocks = blocks_for(pairs.count, kReduceThreads);
  reducer.reset_flag();
  energy_kernel<<<blocks, kReduceThreads>>>(view(pairs, obstacles), c, x, reducer.partials(blocks), reducer.flag());
  DIPC_CUDA_CHECK_LAUNCH();
  *energy = reducer.sum_partials(blocks);
  return !reducer.flag_set();
}

bool add_contact_barrier_gradient(const DeviceContactPairs& pairs, const DeviceContactObstacles& obstacles,
                                  const BarrierConstants& c, const double* x, double* g, Reducer& reducer) {
  if (pairs.count == 0) return true;
  reducer.reset_flag();
  gradient_kernel<<<blocks_for(pairs.count, kThreads), kThreads>>>(view(pairs, obstacles), c, x, g, reducer.flag());
  DIPC_CUDA_CHECK_LAUNCH();
  return !reducer.flag_set();
}

bool contact_barrier_hessian(const DeviceContactPairs& pairs, const DeviceContactObstacles& obstacles,
                             const BarrierConstants& c, const double* x, double* values, Reducer& reducer) {
  if (pairs.count == 0) return true;
  reducer.reset_flag();
  hessian_kernel<<<blocks_for(pairs.count, kHessianThreads), kHessianThreads>>>(view(pairs, obstacles),
                                                                                pairs.hessian_offset.data(), c, x,
                                                                                values, reducer.flag());
  DIPC_CUDA_CHECK_LAUNCH();
  return !reducer.flag_set();
}

bool contact_active_flags(const DeviceContactPairs& pairs, const DeviceContactObstacles& obstacles,
                          const BarrierConstants& c, const double* x, std::int32_t* active, Reducer& reducer) {
  if (pairs.count == 0) return true;
  reducer.reset_flag();
  active_kernel<<<blocks_for(pairs.count, kThreads), kThreads>>>(view(pairs, obstacles), c, x, active, reducer.flag());
  DIPC_CUDA_CHECK_LAUNCH();
  return !reducer.flag_set();
}

double contact_min_squared_distance(const DeviceContactPairs& pairs, const DeviceContactObstacles& obstacles,
                                    const double* x, Reducer& reducer) {
  if (pairs.count == 0) return INFINITY;
  const unsigned blocks = blocks_for(pairs.count, kReduceThreads);
  squared_distance_kernel<<<blocks, kReduceThreads>>>(view(pairs, obstacles), x, reducer.partials(blocks));
  DIPC_CUDA_CHECK_LAUNCH();
  return reducer.min_partials(blocks);
}

void contact_times_of_impact(const DeviceContactPairs& pairs, const DeviceContactObstacles& obstacles, const double* x,
                             const double* p, double t_max, double* toi) {
  if (pairs.count == 0) return;
  times_of_impact_kernel<<<blocks_for(pairs.count, kThreads), kThreads>>>(view(pairs, obstacles), x, p, t_max, toi);
  DIPC_CUDA_CHECK_LAUNCH();
}

double contact_min_time_of_impact(const DeviceContactPairs& pairs, const DeviceContactObstacles& obstacles,
                                  const double* x, const double* p, double t_max, Reducer& reducer) {
  if (pairs.count == 0) return t_max;
  const unsigned blocks = blocks_for(pairs.count, kReduceThreads);
  min_time_of_impact_kernel<<<blocks, kReduceThreads>>>(view(pairs, obstacles), x, p, t_max, reducer.partials(blocks));
  DIPC_CUDA_CHECK_LAUNCH();
  return reducer.min_partials(blocks);
}

}  // namespace dipc::device
