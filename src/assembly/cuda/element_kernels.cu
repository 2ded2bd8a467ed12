// CUDA element kernels (element_kernels.hpp).
//
// Blocks with mean-dilatation elements (hex8_mean_dilatation.hpp) run a variant of the elastic
// kernel that first sums each such element's reference and current volumes over its 8 threads.
// The kernel takes the element material (materials.hpp) as a template parameter: blocks whose
// elements are all neo-Hookean (ElementBlock::model null) run the NeoHookean instantiation,
// others a variant that picks each element's material through visit_material.
//
// The elastic kernel gives each element 8 threads and runs in two phases, because a 24×24
// Hessian does not fit one thread's registers:
//   1. thread t evaluates Gauss point q = t: the shape gradients G_q, F, ψ, P and the
//      PSD-projected ∂P/∂F (hex8_quadrature_point and the material's point functions, as on
//      the CPU), and leaves w|J0|·(G, P, ∂P/∂F) in shared memory (∂P/∂F as its 45-entry upper
//      triangle: it is symmetric);
//   2. thread t then owns node a = t: its 3 gradient entries g_ak = Σ_q Σ_j wP_kj G_aj, and its
//      three Hessian rows H_(ak)(bl) = Σ_q Σ_jm G_aj wC_(kj)(lm) G_bm, one row at a time (24
//      accumulators), written straight into the COO value array at elastic_coo_offset, whose
//      order makes the 8 threads of an element store 8 consecutive doubles at a time.
#include "assembly/cuda/element_kernels.hpp"
#include "device/cuda_check.cuh"
#include "physics/hex8_elasticity.hpp"
#include "physics/hex8_mass.hpp"
#include "physics/hex8_mean_dilatation.hpp"
#include "physics/materials.hpp"

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
// point G (24), wP (9) when the gradient is wanted, wC (45) when the Hessian is, and, in the
// mean-dilatation variant, w|J0| and w|J0| J (2) and, with the Hessian, w|J0| J F^{-T} (9);
// padded to 4 (mod 16) doubles. A warp holds 4 elements whose threads read the same offsets
// in their own element's area; shared memory has 32 four-byte banks (16 doubles a row), so an
// unpadded stride that is a multiple of 16 doubles (672 with the Hessian) sent all 4 reads
// to one bank pair, 4-way conflicts. A stride of 4 (mod 16) spreads them over 4 bank pairs.
template <bool Grad, bool Hess, bool MeanDilatation>
__host__ __device__ constexpr int shared_per_element() {
  constexpr int used = 48 + 8 * ((Grad || Hess ? 24 : 0) + (Grad ? 9 : 0) + (Hess ? 45 : 0)) +
                       (MeanDilatation ? 8 * (2 + (Hess ? 9 : 0)) : 0);
  return used + (20 - used % 16) % 16;
}

// Blocks per SM the compiler must leave registers for (occupancy against spills).
#ifndef DIPC_ELASTIC_MIN_BLOCKS
#define DIPC_ELASTIC_MIN_BLOCKS 4
#endif

// ψ of a Material at one quadrature point, with P (Grad) and the PSD-projected ∂P/∂F (Hess).
template <class Material, bool Grad, bool Hess>
__device__ double material_point(const double F[9], double lambda, double mu, double P[9], double C[81]) {
  if (Grad) Material::stress(F, lambda, mu, P);
  if (Hess) stress_derivative_psd<Material>(F, lambda, mu, C);
  return Material::energy(F, lambda, mu);
}

// MeanDilatation: the block has mean-dilatation elements (hex8_mean_dilatation.hpp); each
// element then branches on its own kind, and those of that kind first reduce their reference
// and current volumes V, v over their 8 threads. Blocks without any keep the plain kernel.
// AnyModel: the block has elements of other materials than neo-Hookean; each element's point
// functions are then those of its own material (mean-dilatation elements are neo-Hookean).
template <bool Grad, bool Hess, bool MeanDilatation, bool AnyModel>
__global__ void __launch_bounds__(kElasticThreads, DIPC_ELASTIC_MIN_BLOCKS)
    elastic_kernel(ElementBlock block, const double* __restrict__ x, double scale, double* partials, int* failed,
                   double* __restrict__ g, double* __restrict__ coo) {
  extern __shared__ double shared[];
  __shared__ double reduction[kElasticThreads];
  constexpr int kPerElement = shared_per_element<Grad, Hess, MeanDilatation>();
  // Offsets of the areas that shared_per_element counts, in its order (absent ones take no room).
  constexpr int kG = 48, kP = kG + (Grad || Hess ? 8 * 24 : 0), kC = kP + (Grad ? 8 * 9 : 0),
                kVol = kC + (Hess ? 8 * 45 : 0), kB = kVol + 16;
  static_assert(!MeanDilatation || kB + (Hess ? 8 * 9 : 0) <= kPerElement, "shared area overflow");
  const int slot = threadIdx.x / kThreadsPerElement, t = threadIdx.x % kThreadsPerElement;
  const long e = static_cast<long>(blockIdx.x) * kElementsPerBlock + slot;
  const bool active = e < block.num_elements;
  const bool mean_dilatation = MeanDilatation && active && block.volumetric_term(e) == VolumetricTerm::mean_dilatation;
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
  double G[24], F[9], wdet = 0, J = 1;
  if (active) {
    wdet = hex8_quadrature_point(s, s + 24, t, G, F);
    J = det3x3(F);
    if (!(J > 0)) *failed = 1;
    if (MeanDilatation) s[kVol + t] = wdet, s[kVol + 8 + t] = wdet * J;
  }
  // Mean dilatation: V = sum_q w|J0|, v = sum_q w|J0| J, summed in the same order by every thread.
  double p = 0, f2 = 0;
  if (MeanDilatation) {
    __syncthreads();
    if (mean_dilatation) {
      double V = 0, v = 0;
      for (int q = 0; q < 8; ++q) V += s[kVol + q], v += s[kVol + 8 + q];
      const double lambda = block.lambda[e], Jbar = v / V, log_Jbar = log(Jbar);
      p = lambda * log_Jbar / Jbar;
      f2 = lambda * (1.0 - log_Jbar) / (V * Jbar * Jbar);
      if (f2 < 0) f2 = 0;
      if (t == 0) energy = 0.5 * V * lambda * log_Jbar * log_Jbar;
    }
  }
  if (active) {
    const double mu = block.mu[e];
    if (Grad || Hess)
      for (int k = 0; k < 24; ++k) s[kG + 24 * t + k] = G[k];
    double P[9], C[81];
    if (mean_dilatation) {
      // The deviatoric neo-Hookean part (lambda = 0) plus p J F^{-T} and its tangent.
      double FinvT[9];
      inverse_transpose3x3(F, FinvT);
      energy += wdet * material_point<NeoHookean, Grad, false>(F, 0.0, mu, P, C);
      if (Grad)
        for (int k = 0; k < 9; ++k) P[k] += p * J * FinvT[k];
      if (Hess) {
        mean_dilatation_point_tangent(F, mu, p, C);
        IsotropicEigensystem es;
        mean_dilatation_eigensystem(F, mu, p, &es);
        add_psd_correction(es, C);
        for (int k = 0; k < 9; ++k) s[kB + 9 * t + k] = wdet * J * FinvT[k];
      }
    } else if (AnyModel) {
      const double lambda = block.lambda[e];
      energy += wdet * visit_material(block.material_model(e), [&](auto material) {
                  return material_point<decltype(material), Grad, Hess>(F, lambda, mu, P, C);
                });
    } else {
      energy += wdet * material_point<NeoHookean, Grad, Hess>(F, block.lambda[e], mu, P, C);
    }
    if (Grad)
      for (int k = 0; k < 9; ++k) s[kP + 9 * t + k] = wdet * P[k];
    if (Hess) {
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
    // Mean dilatation: b = dv/dx = sum_q B_q^T (w|J0| J F^{-T}) for the rank-one term f'' b b^T.
    double b[MeanDilatation ? 24 : 1];
    if (MeanDilatation && mean_dilatation) {
      for (int k = 0; k < 24; ++k) b[k] = 0;
      for (int q = 0; q < 8; ++q) {
        const double* Gq = s + kG + 24 * q;
        const double* Wq = s + kB + 9 * q;
        for (int c = 0; c < 8; ++c)
          for (int l = 0; l < 3; ++l)
            b[3 * c + l] += Wq[3 * l] * Gq[3 * c] + Wq[3 * l + 1] * Gq[3 * c + 1] + Wq[3 * l + 2] * Gq[3 * c + 2];
      }
    }
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
      if (MeanDilatation && mean_dilatation)
        for (int j = 0; j < 24; ++j) row[j] += f2 * b[3 * a + k] * b[j];
#pragma unroll
      for (int c = 0; c < 8; ++c)
#pragma unroll
        for (int l = 0; l < 3; ++l) out[elastic_coo_offset(a, k, c, l)] = scale * row[3 * c + l];
    }
  }
  const double total = block_sum(energy, reduction);
  if (threadIdx.x == 0) partials[blockIdx.x] = scale * total;
}

template <bool Grad, bool Hess, bool MeanDilatation, bool AnyModel>
void launch_elastic(const ElementBlock& block, const double* x, double scale, double* partials, int* failed, double* g,
                    double* coo, unsigned blocks) {
  const std::size_t bytes = sizeof(double) * kElementsPerBlock * shared_per_element<Grad, Hess, MeanDilatation>();
  static bool configured = false;
  if (!configured) {
    DIPC_CUDA_CHECK(cudaFuncSetAttribute(elastic_kernel<Grad, Hess, MeanDilatation, AnyModel>,
                                         cudaFuncAttributeMaxDynamicSharedMemorySize, static_cast<int>(bytes)));
    configured = true;
  }
  elastic_kernel<Grad, Hess, MeanDilatation, AnyModel>
      <<<blocks, kElasticThreads, bytes>>>(block, x, scale, partials, failed, g, coo);
  DIPC_CUDA_CHECK_LAUNCH();
}

template <bool MeanDilatation, bool AnyModel>
void launch_elastic_outputs(const ElementBlock& block, const double* x, double scale, double* partials, int* failed,
                            double* g, double* coo, unsigned blocks) {
  if (g && coo)
    launch_elastic<true, true, MeanDilatation, AnyModel>(block, x, scale, partials, failed, g, coo, blocks);
  else if (g)
    launch_elastic<true, false, MeanDilatation, AnyModel>(block, x, scale, partials, failed, g, nullptr, blocks);
  else if (coo)
    launch_elastic<false, true, MeanDilatation, AnyModel>(block, x, scale, partials, failed, nullptr, coo, blocks);
  else
    launch_elastic<false, false, MeanDilatation, AnyModel>(block, x, scale, partials, failed, nullptr, nullptr, blocks);
}

template <bool MeanDilatation>
void launch_elastic_models(const ElementBlock& block, const double* x, double scale, double* partials, int* failed,
                           double* g, double* coo, unsigned blocks) {
  if (block.model)
    launch_elastic_outputs<MeanDilatation, true>(block, x, scale, partials, failed, g, coo, blocks);
  else
    launch_elastic_outputs<MeanDilatation, false>(block, x, scale, partials, failed, g, coo, blocks);
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
                                          const double* __restrict__ xh, const double* __restrict__ x, double* partials,
                                          double* g) {
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

struct ElementBlockMaps {
  ElementBlockMap map[kMaxElementBlockMaps];
  int count;
};

// One thread per (block, bit 3i + j): the entry's serial sum over the maps and their sources in
// order is NodeBlockReduction::reduce's, so both give the same bits.
__global__ void reduce_element_blocks_kernel(const double* __restrict__ raw, std::size_t num_blocks,
                                             const std::uint16_t* __restrict__ block_mask,
                                             const std::uint32_t* __restrict__ block_start, ElementBlockMaps maps,
                                             double* __restrict__ unique) {
  const std::size_t t = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  const std::size_t k = t / 9;
  const int bit = static_cast<int>(t % 9);
  if (k >= num_blocks) return;
  const unsigned mask = block_mask[k];
  if (!(mask >> bit & 1u)) return;
  const int i = bit / 3, j = bit % 3;
  double sum = 0.0;
  for (int m = 0; m < maps.count; ++m) {
    const ElementBlockMap& map = maps.map[m];
    if (!(element_block_mask(map.layout) >> bit & 1u)) continue;
    const std::size_t per = static_cast<std::size_t>(element_values(map.layout));
    for (std::uint32_t s = map.d_offsets[k]; s < map.d_offsets[k + 1]; ++s) {
      const std::uint32_t src = map.d_sources[s];
      sum += raw[map.raw_begin + per * (src >> 6) +
                 element_value_offset(map.layout, static_cast<int>(src >> 3 & 7u), i, static_cast<int>(src & 7u), j)];
    }
  }
  unique[block_start[k] + __popc(mask & ((1u << bit) - 1u))] = sum;
}

// One thread per (block k of the chunk's range, bit 3i + j): the chunk's sources of entry
// (k, bit), in order, added onto its sum so far.
__global__ void add_element_block_chunk_kernel(const double* __restrict__ chunk, std::uint32_t first,
                                               std::uint32_t last, std::size_t block_begin, std::size_t num_blocks,
                                               const std::uint16_t* __restrict__ block_mask,
                                               const std::uint32_t* __restrict__ block_start, ElementBlockMap map,
                                               double* __restrict__ unique) {
  const std::size_t t = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (t / 9 >= num_blocks) return;
  const std::size_t k = block_begin + t / 9;
  const int bit = static_cast<int>(t % 9);
  const unsigned mask = block_mask[k];
  if (!(mask >> bit & 1u) || !(element_block_mask(map.layout) >> bit & 1u)) return;
  const int i = bit / 3, j = bit % 3;
  const std::size_t per = static_cast<std::size_t>(element_values(map.layout));
  double* const entry = unique + block_start[k] + __popc(mask & ((1u << bit) - 1u));
  double sum = *entry;
  bool any = false;
  for (std::uint32_t s = map.d_offsets[k]; s < map.d_offsets[k + 1]; ++s) {
    const std::uint32_t src = map.d_sources[s];
    const std::uint32_t e = src >> 6;
    if (e < first) continue;
    if (e >= last) break;  // sources ascend by element within a block
    sum += chunk[per * (e - first) +
                 element_value_offset(map.layout, static_cast<int>(src >> 3 & 7u), i, static_cast<int>(src & 7u), j)];
    any = true;
  }
  if (any) *entry = sum;
}

// One thread per block: the chunks of its sources' elements take it into their ranges.
__global__ void element_chunk_block_ranges_kernel(std::size_t num_blocks, ElementBlockMap map,
                                                  std::uint32_t chunk_elements, unsigned long long* begin,
                                                  unsigned long long* end) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k >= num_blocks) return;
  for (std::uint32_t s = map.d_offsets[k]; s < map.d_offsets[k + 1]; ++s) {
    const std::uint32_t c = (map.d_sources[s] >> 6) / chunk_elements;
    atomicMin(begin + c, static_cast<unsigned long long>(k));
    atomicMax(end + c, static_cast<unsigned long long>(k + 1));
  }
}

}  // namespace

void reduce_element_blocks(const double* d_raw, std::size_t num_blocks, const std::uint16_t* d_block_mask,
                           const std::uint32_t* d_block_start, const ElementBlockMap* maps, int num_maps,
                           double* d_unique) {
  if (num_maps > kMaxElementBlockMaps) throw DeviceError("reduce_element_blocks: more element forms than kernel slots");
  if (num_blocks == 0) return;
  ElementBlockMaps all{};
  for (int m = 0; m < num_maps; ++m) all.map[m] = maps[m];
  all.count = num_maps;
  reduce_element_blocks_kernel<<<blocks_for(9 * num_blocks, 256), 256>>>(d_raw, num_blocks, d_block_mask, d_block_start,
                                                                         all, d_unique);
  DIPC_CUDA_CHECK_LAUNCH();
}

void add_element_block_chunk(const double* d_chunk, std::uint32_t first, std::uint32_t count, std::size_t block_begin,
                             std::size_t block_end, const std::uint16_t* d_block_mask,
                             const std::uint32_t* d_block_start, const ElementBlockMap& map, double* d_unique) {
  if (block_end <= block_begin || count == 0) return;
  const std::size_t num_blocks = block_end - block_begin;
  add_element_block_chunk_kernel<<<blocks_for(9 * num_blocks, 256), 256>>>(
      d_chunk, first, first + count, block_begin, num_blocks, d_block_mask, d_block_start, map, d_unique);
  DIPC_CUDA_CHECK_LAUNCH();
}

void element_chunk_block_ranges(std::size_t num_blocks, const ElementBlockMap& map, std::uint32_t chunk_elements,
                                std::size_t num_chunks, std::vector<std::uint64_t>* begin,
                                std::vector<std::uint64_t>* end) {
  std::vector<unsigned long long> lo(num_chunks, ~0ull), hi(num_chunks, 0ull);
  Array<unsigned long long> d_lo("element chunk block ranges"), d_hi("element chunk block ranges");
  d_lo.upload(lo);
  d_hi.upload(hi);
  if (num_blocks > 0 && num_chunks > 0) {
    element_chunk_block_ranges_kernel<<<blocks_for(num_blocks, 256), 256>>>(num_blocks, map, chunk_elements,
                                                                           d_lo.data(), d_hi.data());
    DIPC_CUDA_CHECK_LAUNCH();
  }
  d_lo.download(lo.data());
  d_hi.download(hi.data());
  begin->assign(num_chunks, 0);
  end->assign(num_chunks, 0);
  for (std::size_t c = 0; c < num_chunks; ++c)
    if (lo[c] < hi[c]) (*begin)[c] = lo[c], (*end)[c] = hi[c];
}

bool elastic_evaluate(const ElementBlock& block, const double* d_x, double scale, double* energy, double* d_gradient,
                      double* d_hessian, Reducer& reducer) {
  if (block.num_elements == 0) {
    if (energy) *energy = 0;
    return true;
  }
  const unsigned blocks = blocks_for(block.num_elements, kElementsPerBlock);
  double* partials = reducer.partials(blocks);
  reducer.reset_flag();
  int* failed = reducer.flag();
  // block.volumetric is non-null (on the device) only when some element is mean-dilatation,
  // block.model only when some element is not neo-Hookean (DeviceElementData).
  if (block.volumetric)
    launch_elastic_models<true>(block, d_x, scale, partials, failed, d_gradient, d_hessian, blocks);
  else
    launch_elastic_models<false>(block, d_x, scale, partials, failed, d_gradient, d_hessian, blocks);
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
  consistent_inertia_kernel<true>
      <<<blocks, kReduceThreads>>>(block, d_element_mass, d_x_hat, d_x, reducer.partials(blocks), nullptr);
  DIPC_CUDA_CHECK_LAUNCH();
  return reducer.sum_partials(blocks);
}

void consistent_inertia_gradient(const ElementBlock& block, const double* d_element_mass, const double* d_x_hat,
                                 const double* d_x, double* d_g) {
  if (block.num_elements == 0) return;
  consistent_inertia_kernel<false>
      <<<blocks_for(block.num_elements, kReduceThreads), kReduceThreads>>>(block, d_element_mass, d_x_hat, d_x, nullptr,
                                                                           d_g);
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
