// CUDA element kernels (element_kernels.hpp).
//
// The elastic kernel gives each element 8 threads and runs in two phases, because a 24×24
// Hessian does not fit one thread's registers:
//   1. thread t evaluates Gauss point q = t: the shape gradients G_q, F, ψ, P and the
//      PSD-projected ∂P/∂F (hex8_quadrature_point and the neo_hookean.hpp point functions, as on
//      the CPU), and leaves w|J0|·(G, P, ∂P/∂F) in shared memory (∂P/∂F as its 45-entry upper
//      triangle: it is symmetric);
//   2. thread t then owns node a = t: its 3 gradient entries g_ak = Σ_q Σ_j wP_kj G_aj, and its
//      three Hessian rows H_(ak)(bl) = Σ_q Σ_jm G_aj wC_(kj)(lm) G_bm, one row at a time (24
//      accumulators), written straight into the COO value array at elastic_coo_offset, whose
//      order makes the 8 threads of an element store 8 consecutive doubles at a time.
#include "assembly/cuda/element_kernels.hpp"
#include "assembly/hex8_elasticity.hpp"
#include "assembly/hex8_mass.hpp"
#include "device/cuda_check.cuh"

namespace dipc::device {

namespace {

constexpr int kThreadsPerElement = 8;
constexpr int kElementsPerBlock = 8;
constexpr int kElasticThreads = kThreadsPerElement * kElementsPerBlock;  // 64

// Index of entry (r, c) of a symmetric 9×9 matrix stored as its upper triangle, row-major.
__host__ __device__ constexpr int packed(int r, int c) {
  return r <= c ? r * 9 - r * (r - 1) / 2 + (c - r) : c * 9 - c * (c - 1) / 2 + (r - c);
}

// Shared doubles per element for the outputs asked for: X and x (24 each), then per Gauss
// point G (24), wP (9) when the gradient is wanted, wC (45) when the Hessian is; padded to
// 4 (mod 16) doubles. A warp holds 4 elements whose threads read the same offsets in their
// own element's area; shared memory has 32 four-byte banks (16 doubles a row), so an
// unpadded stride that is a multiple of 16 doubles (672 with the Hessian) sent all 4 reads
// to one bank pair, 4-way conflicts. A stride of 4 (mod 16) spreads them over 4 bank pairs.
template <bool Grad, bool Hess>
__host__ __device__ constexpr int shared_per_element() {
  constexpr int used = 48 + 8 * ((Grad || Hess ? 24 : 0) + (Grad ? 9 : 0) + (Hess ? 45 : 0));
  return used + (20 - used % 16) % 16;
}

// Blocks per SM the compiler must leave registers for (occupancy against spills).
#ifndef DIPC_ELASTIC_MIN_BLOCKS
#define DIPC_ELASTIC_MIN_BLOCKS 4
#endif

template <bool Grad, bool Hess>
__global__ void __launch_bounds__(kElasticThreads, DIPC_ELASTIC_MIN_BLOCKS)
    elastic_kernel(ElementBlock block, const double* __restrict__ x, double scale, double* partials, int* failed,
                   double* __restrict__ g, double* __restrict__ coo) {
  extern __shared__ double shared[];
  __shared__ double reduction[kElasticThreads];
  constexpr int kPerElement = shared_per_element<Grad, Hess>();
  constexpr int kG = 48, kP = kG + 8 * 24, kC = kP + (Grad ? 8 * 9 : 0);
  const int slot = threadIdx.x / kThreadsPerElement, t = threadIdx.x % kThreadsPerElement;
  const long e = static_cast<long>(blockIdx.x) * kElementsPerBlock + slot;
  const bool active = e < block.num_elements;
  double* s = shared + slot * kPerElement;
  int node = 0;
  if (active) {
    // Thread t brings node t of its element: X to s[0..24), x to s[24..48).
    node = block.nodes[8 * e + t];
    for (int i = 0; i < 3; ++i) {
      s[3 * t + i] = block.reference[3 * static_cast<long>(node) + i];
      s[24 + 3 * t + i] = x[3 * static_cast<long>(node) + i];
    }
  }
  __syncthreads();
  double energy = 0;
  if (active) {
    const double lambda = block.lambda[e], mu = block.mu[e];
    double G[24], F[9];
    const double wdet = hex8_quadrature_point(s, s + 24, t, G, F);
    if (!(det3x3(F) > 0)) *failed = 1;
    energy = wdet * neo_hookean_energy(F, lambda, mu);
    if (Grad || Hess)
      for (int k = 0; k < 24; ++k) s[kG + 24 * t + k] = G[k];
    if (Grad) {
      double P[9];
      neo_hookean_stress(F, lambda, mu, P);
      for (int k = 0; k < 9; ++k) s[kP + 9 * t + k] = wdet * P[k];
    }
    if (Hess) {
      double C[81];
      neo_hookean_stress_derivative_psd(F, lambda, mu, C);
#pragma unroll
      for (int r = 0; r < 9; ++r)
#pragma unroll
        for (int c = r; c < 9; ++c) s[kC + 45 * t + packed(r, c)] = wdet * C[9 * r + c];
    }
  }
  __syncthreads();
  if (active && Grad) {
    const int a = t;
    double ga[3] = {0, 0, 0};
    for (int q = 0; q < 8; ++q) {
      const double* Gq = s + kG + 24 * q;
      const double* Pq = s + kP + 9 * q;
#pragma unroll
      for (int k = 0; k < 3; ++k)
        ga[k] += Pq[3 * k] * Gq[3 * a] + Pq[3 * k + 1] * Gq[3 * a + 1] + Pq[3 * k + 2] * Gq[3 * a + 2];
    }
    for (int k = 0; k < 3; ++k) atomicAdd(g + 3 * static_cast<long>(node) + k, scale * ga[k]);
  }
  if (active && Hess) {
    const int a = t;
    double* out = coo + kElasticCooPerElement * e;
#pragma unroll
    for (int k = 0; k < 3; ++k) {
      double row[24];
#pragma unroll
      for (int j = 0; j < 24; ++j) row[j] = 0;
      for (int q = 0; q < 8; ++q) {
        const double* Gq = s + kG + 24 * q;
        const double* Cq = s + kC + 45 * q;
        const double ga0 = Gq[3 * a], ga1 = Gq[3 * a + 1], ga2 = Gq[3 * a + 2];
        // T_(lm) = Σ_j G_aj wC_(kj)(lm): the left contraction for this row block.
        double T[9];
#pragma unroll
        for (int lm = 0; lm < 9; ++lm)
          T[lm] = ga0 * Cq[packed(3 * k, lm)] + ga1 * Cq[packed(3 * k + 1, lm)] + ga2 * Cq[packed(3 * k + 2, lm)];
#pragma unroll
        for (int b = 0; b < 8; ++b)
#pragma unroll
          for (int l = 0; l < 3; ++l)
            row[3 * b + l] += T[3 * l] * Gq[3 * b] + T[3 * l + 1] * Gq[3 * b + 1] + T[3 * l + 2] * Gq[3 * b + 2];
      }
#pragma unroll
      for (int b = 0; b < 8; ++b)
#pragma unroll
        for (int l = 0; l < 3; ++l) out[elastic_coo_offset(a, k, b, l)] = scale * row[3 * b + l];
    }
  }
  const double total = block_sum(energy, reduction);
  if (threadIdx.x == 0) partials[blockIdx.x] = scale * total;
}

template <bool Grad, bool Hess>
void launch_elastic(const ElementBlock& block, const double* x, double scale, double* partials, int* failed,
                    double* g, double* coo, unsigned blocks) {
  const std::size_t bytes = sizeof(double) * kElementsPerBlock * shared_per_element<Grad, Hess>();
  static bool configured = false;
  if (!configured) {
    DIPC_CUDA_CHECK(cudaFuncSetAttribute(elastic_kernel<Grad, Hess>, cudaFuncAttributeMaxDynamicSharedMemorySize,
                                         static_cast<int>(bytes)));
    configured = true;
  }
  elastic_kernel<Grad, Hess><<<blocks, kElasticThreads, bytes>>>(block, x, scale, partials, failed, g, coo);
  DIPC_CUDA_CHECK_LAUNCH();
}

__global__ void min_volume_ratio_kernel(ElementBlock block, const double* __restrict__ x, double* partials) {
  __shared__ double reduction[kReduceThreads];
  const long e = static_cast<long>(blockIdx.x) * blockDim.x + threadIdx.x;
  double r = 1e300;
  if (e < block.num_elements) {
    double X[24], xe[24];
    for (int a = 0; a < 8; ++a) {
      const long n = block.nodes[8 * e + a];
      for (int i = 0; i < 3; ++i) X[3 * a + i] = block.reference[3 * n + i], xe[3 * a + i] = x[3 * n + i];
    }
    r = hex8_min_volume_ratio(X, xe);
  }
  const double m = block_min(r, reduction);
  if (threadIdx.x == 0) partials[blockIdx.x] = m;
}

__global__ void lumped_energy_kernel(const double* m, const double* xh, const double* x, std::size_t n,
                                     double* partials) {
  __shared__ double reduction[kReduceThreads];
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  double e = 0;
  if (k < n) {
    const double d = x[k] - xh[k];
    e = 0.5 * m[k] * d * d;
  }
  const double s = block_sum(e, reduction);
  if (threadIdx.x == 0) partials[blockIdx.x] = s;
}

__global__ void lumped_gradient_kernel(const double* m, const double* xh, const double* x, std::size_t n, double* g) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k < n) g[k] += m[k] * (x[k] - xh[k]);
}

__global__ void dot_kernel(const double* f, const double* x, std::size_t n, double* partials) {
  __shared__ double reduction[kReduceThreads];
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  const double s = block_sum(k < n ? f[k] * x[k] : 0.0, reduction);
  if (threadIdx.x == 0) partials[blockIdx.x] = s;
}

// One thread per element: d = x − x̂ at its 8 nodes, then energy ½ dᵀ(M⊗I)d or gradient (M⊗I)d.
template <bool Energy>
__global__ void consistent_inertia_kernel(ElementBlock block, const double* __restrict__ mass,
                                          const double* __restrict__ xh, const double* __restrict__ x,
                                          double* partials, double* g) {
  __shared__ double reduction[kReduceThreads];
  const long e = static_cast<long>(blockIdx.x) * blockDim.x + threadIdx.x;
  double energy = 0;
  if (e < block.num_elements) {
    const double* M = mass + 64 * e;
    long n[8];
    double d[24];
    for (int a = 0; a < 8; ++a) {
      n[a] = block.nodes[8 * e + a];
      for (int c = 0; c < 3; ++c) d[3 * a + c] = x[3 * n[a] + c] - xh[3 * n[a] + c];
    }
    for (int a = 0; a < 8; ++a)
      for (int c = 0; c < 3; ++c) {
        double Md = 0;
        for (int b = 0; b < 8; ++b) Md += M[8 * a + b] * d[3 * b + c];
        if (Energy)
          energy += 0.5 * d[3 * a + c] * Md;
        else
          atomicAdd(g + 3 * n[a] + c, Md);
      }
  }
  if (Energy) {
    const double s = block_sum(energy, reduction);
    if (threadIdx.x == 0) partials[blockIdx.x] = s;
  }
}

}  // namespace

bool elastic_evaluate(const ElementBlock& block, const double* d_x, double scale, double* energy,
                      double* d_gradient, double* d_hessian, Reducer& reducer) {
  if (block.num_elements == 0) {
    if (energy) *energy = 0;
    return true;
  }
  const unsigned blocks = blocks_for(block.num_elements, kElementsPerBlock);
  double* partials = reducer.partials(blocks);
  reducer.reset_flag();
  int* failed = reducer.flag();
  if (d_gradient && d_hessian)
    launch_elastic<true, true>(block, d_x, scale, partials, failed, d_gradient, d_hessian, blocks);
  else if (d_gradient)
    launch_elastic<true, false>(block, d_x, scale, partials, failed, d_gradient, nullptr, blocks);
  else if (d_hessian)
    launch_elastic<false, true>(block, d_x, scale, partials, failed, nullptr, d_hessian, blocks);
  else
    launch_elastic<false, false>(block, d_x, scale, partials, failed, nullptr, nullptr, blocks);
  if (energy) *energy = reducer.sum_partials(blocks);
  return !reducer.flag_set();
}

double min_volume_ratio(const ElementBlock& block, const double* d_x, Reducer& reducer) {
  if (block.num_elements == 0) return 1e300;
  const unsigned blocks = blocks_for(block.num_elements, kReduceThreads);
  min_volume_ratio_kernel<<<blocks, kReduceThreads>>>(block, d_x, reducer.partials(blocks));
  DIPC_CUDA_CHECK_LAUNCH();
  return reducer.min_partials(blocks);
}

double lumped_inertia_energy(const double* d_mass, const double* d_x_hat, const double* d_x, std::size_t n,
                             Reducer& reducer) {
  if (n == 0) return 0;
  const unsigned blocks = blocks_for(n, kReduceThreads);
  lumped_energy_kernel<<<blocks, kReduceThreads>>>(d_mass, d_x_hat, d_x, n, reducer.partials(blocks));
  DIPC_CUDA_CHECK_LAUNCH();
  return reducer.sum_partials(blocks);
}

void lumped_inertia_gradient(const double* d_mass, const double* d_x_hat, const double* d_x, std::size_t n,
                             double* d_g) {
  if (n == 0) return;
  lumped_gradient_kernel<<<blocks_for(n, 256), 256>>>(d_mass, d_x_hat, d_x, n, d_g);
  DIPC_CUDA_CHECK_LAUNCH();
}

double consistent_inertia_energy(const ElementBlock& block, const double* d_element_mass, const double* d_x_hat,
                                 const double* d_x, Reducer& reducer) {
  if (block.num_elements == 0) return 0;
  const unsigned blocks = blocks_for(block.num_elements, kReduceThreads);
  consistent_inertia_kernel<true><<<blocks, kReduceThreads>>>(block, d_element_mass, d_x_hat, d_x,
                                                               reducer.partials(blocks), nullptr);
  DIPC_CUDA_CHECK_LAUNCH();
  return reducer.sum_partials(blocks);
}

void consistent_inertia_gradient(const ElementBlock& block, const double* d_element_mass, const double* d_x_hat,
                                 const double* d_x, double* d_g) {
  if (block.num_elements == 0) return;
  consistent_inertia_kernel<false><<<blocks_for(block.num_elements, kReduceThreads), kReduceThreads>>>(
      block, d_element_mass, d_x_hat, d_x, nullptr, d_g);
  DIPC_CUDA_CHECK_LAUNCH();
}

double dot(const double* d_f, const double* d_x, std::size_t n, Reducer& reducer) {
  if (n == 0) return 0;
  const unsigned blocks = blocks_for(n, kReduceThreads);
  dot_kernel<<<blocks, kReduceThreads>>>(d_f, d_x, n, reducer.partials(blocks));
  DIPC_CUDA_CHECK_LAUNCH();
  return reducer.sum_partials(blocks);
}

}  // namespace dipc::device
