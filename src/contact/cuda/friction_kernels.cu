// friction_kernels.hpp on the CUDA device: one thread per friction pair, each gathering the
// pair's positions as FrictionForm::gather does on the host and calling the same point functions
// (contact/friction/friction_potential.hpp). Compiled without fused multiply-adds, as the other
// contact kernels.
#include "contact/cuda/friction_kernels.hpp"
#include "contact/friction/friction_potential.hpp"
#include "contact/obstacle_nodes.hpp"
#include "device/cuda_check.cuh"

namespace dipc::device {

namespace {

constexpr int kThreads = 128;

struct FrictionView {
  std::size_t n;
  const std::int32_t* count;
  const std::int32_t* nodes;
  const double* x_start;
  const contact::LaggedPairFriction* pair;
  const contact::LaggedPointPlaneFriction* plane;
  const std::size_t* hessian_offset;
  const std::int32_t* reversing;
  const double* obstacle_end;
};

FrictionView view(const DeviceFrictionPairs& p, const double* obstacle_end) {
  return {p.size,
          p.count.data(),
          p.nodes.data(),
          p.x_start.data(),
          p.pair.data(),
          p.plane.data(),
          p.hessian_offset.data(),
          p.reversing.data(),
          obstacle_end};
}

// Pair i's node ids and positions at x (obstacle vertices at the segment's end); false if the
// rank does not know one of its nodes.
__device__ bool gather(const FrictionView& v, std::size_t i, const double* x, int* count, std::int32_t node[4],
                       double X[12]) {
  *count = v.count[i];
  for (int k = 0; k < *count; ++k) {
    node[k] = v.nodes[k * v.n + i];
    if (node[k] == -1) return false;
    const double* xk = is_obstacle_node(node[k]) ? v.obstacle_end + 3 * static_cast<std::size_t>(obstacle_vertex(node[k]))
                                                  : x + 3 * static_cast<std::size_t>(node[k]);
    for (int c = 0; c < 3; ++c) X[3 * k + c] = xk[c];
  }
  return true;
}

__global__ void energy_kernel(FrictionView v, const double* x, double* energy, int* failed) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= v.n) return;
  int count;
  std::int32_t node[4];
  double X[12];
  if (!gather(v, i, x, &count, node, X)) {
    *failed = 1;
    energy[i] = 0;
    return;
  }
  const double* xs = v.x_start + 12 * i;
  energy[i] = count == 1 ? contact::friction_energy(X, xs, v.plane[i]) : contact::friction_energy(X, xs, v.pair[i]);
}

__global__ void gradient_kernel(FrictionView v, const double* x, double* g, int* failed) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= v.n) return;
  int count;
  std::int32_t node[4];
  double X[12], gp[12];
  if (!gather(v, i, x, &count, node, X)) {
    *failed = 1;
    return;
  }
  const double* xs = v.x_start + 12 * i;
  if (count == 1)
    contact::friction_gradient(X, xs, v.plane[i], gp);
  else
    contact::friction_gradient(X, xs, v.pair[i], gp);
  for (int k = 0; k < count; ++k)
    if (!is_obstacle_node(node[k]))
      for (int c = 0; c < 3; ++c) atomicAdd(g + 3 * static_cast<std::size_t>(node[k]) + c, gp[3 * k + c]);
}

__global__ void hessian_kernel(FrictionView v, const double* x, double* values, int* failed) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= v.n) return;
  int count;
  std::int32_t node[4];
  double X[12];
  if (!gather(v, i, x, &count, node, X)) {
    *failed = 1;
    return;
  }
  const double* xs = v.x_start + 12 * i;
  double* out = values + v.hessian_offset[i];
  const auto model = v.reversing[i] ? contact::FrictionModel::majorizer : contact::FrictionModel::projected;
  int slots[4];
  const int b = body_slots(node, count, slots);
  if (count == 1) {
    contact::friction_hessian(X, xs, v.plane[i], model, out);
  } else if (b == count) {
    contact::friction_hessian(X, xs, v.pair[i], model, out);
  } else {  // a pair with an obstacle: the body nodes' block
    double H[144];
    contact::friction_hessian(X, xs, v.pair[i], model, H);
    body_block(H, count, slots, b, out);
  }
}

__global__ void reversal_kernel(FrictionView v, const double* x, const double* p, double eps_u, std::int32_t* reversing) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= v.n) return;
  int count;
  std::int32_t node[4];
  double X[12], X1[12], u0[2], u1[2];
  reversing[i] = 0;
  if (!gather(v, i, x, &count, node, X)) return;
  for (int k = 0; k < count; ++k)
    for (int c = 0; c < 3; ++c)
      X1[3 * k + c] = X[3 * k + c] + (is_obstacle_node(node[k]) ? 0.0 : p[3 * static_cast<std::size_t>(node[k]) + c]);
  const double* xs = v.x_start + 12 * i;
  if (count == 1) {
    contact::tangential_displacement(X, xs, v.plane[i], u0);
    contact::tangential_displacement(X1, xs, v.plane[i], u1);
  } else {
    contact::tangential_displacement(X, xs, v.pair[i], u0);
    contact::tangential_displacement(X1, xs, v.pair[i], u1);
  }
  reversing[i] = contact::slip_reverses(u0, u1, eps_u) ? 1 : 0;
}

}  // namespace

bool friction_energy(DeviceFrictionPairs& pairs, const double* obstacle_end, const double* x, Reducer& reducer,
                     double* energy) {
  if (pairs.size == 0) {
    *energy = 0;
    return true;
  }
  pairs.scratch.resize(pairs.size);
  reducer.reset_flag();
  energy_kernel<<<blocks_for(pairs.size, kThreads), kThreads>>>(view(pairs, obstacle_end), x, pairs.scratch.data(),
                                                                reducer.flag());
  DIPC_CUDA_CHECK_LAUNCH();
  if (reducer.flag_set()) return false;
  *energy = reducer.sum(pairs.scratch.data(), pairs.size);
  return true;
}

bool add_friction_gradient(const DeviceFrictionPairs& pairs, const double* obstacle_end, const double* x, double* g,
                           Reducer& reducer) {
  if (pairs.size == 0) return true;
  reducer.reset_flag();
  gradient_kernel<<<blocks_for(pairs.size, kThreads), kThreads>>>(view(pairs, obstacle_end), x, g, reducer.flag());
  DIPC_CUDA_CHECK_LAUNCH();
  return !reducer.flag_set();
}

bool friction_hessian_values(const DeviceFrictionPairs& pairs, const double* obstacle_end, const double* x,
                             double* values, Reducer& reducer) {
  if (pairs.size == 0) return true;
  reducer.reset_flag();
  hessian_kernel<<<blocks_for(pairs.size, kThreads), kThreads>>>(view(pairs, obstacle_end), x, values, reducer.flag());
  DIPC_CUDA_CHECK_LAUNCH();
  return !reducer.flag_set();
}

void mark_friction_reversals(DeviceFrictionPairs& pairs, const double* obstacle_end, const double* x, const double* p,
                             double eps_u) {
  if (pairs.size == 0) return;
  reversal_kernel<<<blocks_for(pairs.size, kThreads), kThreads>>>(view(pairs, obstacle_end), x, p, eps_u,
                                                                  pairs.reversing.data());
  DIPC_CUDA_CHECK_LAUNCH();
}

}  // namespace dipc::device
