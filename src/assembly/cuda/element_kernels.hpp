// CUDA element kernels over an ElementBlock whose pointers are device memory: hyperelastic
// energy, gradient and PSD-projected Hessian of each element's material (materials.hpp; COO
// values in the order of elastic_coo_pattern), volume ratios, and the inertia and body-force
// terms. They call the same point functions as the CPU loops in element_loops.cpp. Plain C++
// interface; every pointer argument named d_* or documented as device memory lives on the
// current device. Scalars come back to the host through the Reducer, nothing else does.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "assembly/element_loops.hpp"
#include "device/device_runtime.hpp"

namespace dipc::device {

// scale * (energy, gradient, Hessian) of the elements in one launch; any output
// may be null. energy (host) is overwritten, d_gradient (3 per local node) added into,
// d_hessian (576 per element) written. Returns false if an element is inverted at a Gauss
// point (det F <= 0); the outputs are then partial.
bool elastic_evaluate(const ElementBlock& block, const double* d_x, double scale, double* energy, double* d_gradient,
                      double* d_hessian, Reducer& reducer);

// min over elements of hex8_min_volume_ratio (+huge for an empty block).
double min_volume_ratio(const ElementBlock& block, const double* d_x, Reducer& reducer);

// Σ_k ½ m_k (x_k − x̂_k)² over n dofs with one mass per dof (lumped inertia, owned dofs).
double lumped_inertia_energy(const double* d_mass, const double* d_x_hat, const double* d_x, std::size_t n,
                             Reducer& reducer);
// g_k += m_k (x_k − x̂_k).
void lumped_inertia_gradient(const double* d_mass, const double* d_x_hat, const double* d_x, std::size_t n,
                             double* d_g);

// ½ Σ_e (x − x̂)_eᵀ (M_e ⊗ I₃) (x − x̂)_e with 64 scalar masses M_ab per element (consistent inertia).
double consistent_inertia_energy(const ElementBlock& block, const double* d_element_mass, const double* d_x_hat,
                                 const double* d_x, Reducer& reducer);
void consistent_inertia_gradient(const ElementBlock& block, const double* d_element_mass, const double* d_x_hat,
                                 const double* d_x, double* d_g);

// Σ_k f_k x_k over n dofs.
double dot(const double* d_f, const double* d_x, std::size_t n, Reducer& reducer);

// One element form's node-block map on the device (NodeBlockReduction::FormMap): the sources
// 64e + 8a + b of block k are d_sources[d_offsets[k] .. d_offsets[k+1]); the form's values
// start at d_raw + raw_begin, laid out as `layout` says.
struct ElementBlockMap {
  ElementLayout layout = ElementLayout::elastic;
  std::size_t raw_begin = 0;
  const std::uint32_t* d_offsets = nullptr;
  const std::uint32_t* d_sources = nullptr;
};
constexpr int kMaxElementBlockMaps = 4;
// NodeBlockReduction::reduce on the device, bit for bit the same (one thread per entry, summed
// from 0 over the maps in order, then their sources in order): d_unique[d_block_start[k] + rank
// of bit 3i + j in d_block_mask[k]] for the num_blocks blocks. At most kMaxElementBlockMaps maps.
void reduce_element_blocks(const double* d_raw, std::size_t num_blocks, const std::uint16_t* d_block_mask,
                           const std::uint32_t* d_block_start, const ElementBlockMap* maps, int num_maps,
                           double* d_unique);

// The element sums without an array of every element's values (576 per hex: 4.6 KB per element,
// the largest item of a device run's memory): an element form's values are computed for a
// chunk of elements at a time and added onto the entries, chunk after chunk and form after form.
//
// map's elements [first, first + count), whose values d_chunk holds from element `first` on (the
// map's raw_begin is not read), added onto d_unique for the blocks [block_begin, block_end),
// which hold every source of those elements (element_chunk_block_ranges). An entry of no source
// in the chunk is left alone. Sources ascend by element within a block (node_block_pattern.hpp),
// so summing the chunks in element order, and the forms in map order, onto entries that start
// at 0 adds the values in reduce_element_blocks' order: the same bits.
void add_element_block_chunk(const double* d_chunk, std::uint32_t first, std::uint32_t count, std::size_t block_begin,
                             std::size_t block_end, const std::uint16_t* d_block_mask,
                             const std::uint32_t* d_block_start, const ElementBlockMap& map, double* d_unique);
// For map's elements split into chunks of chunk_elements, chunk c = [c chunk_elements, ...): the
// range of blocks [begin[c], end[c]) that holds every source of its elements (empty, begin ==
// end, for a chunk of none). Once per build: the sums run over these ranges only.
void element_chunk_block_ranges(std::size_t num_blocks, const ElementBlockMap& map, std::uint32_t chunk_elements,
                                std::size_t num_chunks, std::vector<std::uint64_t>* begin,
                                std::vector<std::uint64_t>* end);

}  // namespace dipc::device
