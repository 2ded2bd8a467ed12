// ElementBlockPart: the element forms' part of the Hessian's raw values (elastic, consistent
// mass: 576 and 192 values per hex) and its reduction into the matrix's first entries, the
// distinct node blocks (NodeBlockReduction), built once: element patterns never change.
//
// Memory, per hex element (576 raw elastic values, 192 more with a consistent mass; about 27
// node blocks, 243 entries): 4 B per element node pair (64 per hex and element form) and, per
// block, 4 B per element form, 2 B of mask and 8 B of start (4 B on the device), where the
// values are summed (the host, or the device with a device matrix); the summed values take 8 B
// per entry. On the device also 4 B of column node per block and a row start and node per node
// (the pattern, for the contact lookups and the matrix's rows, which share it).
//
// Element forms sum their values element chunk by chunk where they run where the matrix does
// (no array of all their raw values exists: 4.6 KB per hex): a host matrix of host forms on
// the host threads, a device matrix of device forms on the device, through the maps' sources
// over the blocks each chunk reaches. Otherwise the values are summed all at once.
#pragma once
#include <petscsys.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "assembly/cuda/element_kernels.hpp"
#include "assembly/cuda/group_targets.hpp"
#include "assembly/hessian_pattern.hpp"
#include "assembly/node_block_reduction.hpp"
#include "device/device_runtime.hpp"

namespace dipc {

class ElementBlockPart {
 public:
  // The node blocks of the element forms' patterns on a rank that owns the global nodes
  // [owned_begin, owned_end). device_sums: the device sums the values, so the maps are built
  // there and stay there (the host keeps the pattern); chunked: the values are summed element
  // chunk by chunk (add_chunks), on the device where device_sums.
  PetscErrorCode build(const std::vector<NodeBlockReduction::Input>& inputs, bool device_sums, bool chunked,
                       std::int64_t owned_begin, std::int64_t owned_end);
  bool built() const { return built_; }
  bool chunked() const { return chunked_; }
  bool sums_on_device() const { return device_sums_; }
  const NodeBlockReduction& blocks() const { return blocks_; }
  // The blocks' masks and 32-bit entry starts on the device (null before keep_on_device() where
  // the blocks were built on the host), which a device matrix's rows share (DirectMatrix).
  const std::uint16_t* device_masks() const { return d_block_mask_.size() ? d_block_mask_.data() : nullptr; }
  const std::uint32_t* device_starts() const { return d_block_start_.size() ? d_block_start_.data() : nullptr; }
  // ... and the pattern's row starts and column nodes (32-bit) there, null as above.
  const std::uint32_t* device_row_starts() const { return d_row_start_.size() ? d_row_start_.data() : nullptr; }
  const std::uint32_t* device_cols() const { return d_col_.size() ? d_col_.data() : nullptr; }
  // The blocks' entries on the device, for the changing terms' lookups there (group_targets.hpp):
  // the element fields of *index; false (index untouched) before the blocks are on the device.
  bool device_index(device::BlockEntryIndex* index) const;
  // Puts the maps on the device where they are not yet (blocks built on the host for a matrix
  // that now lives on the device), then frees the host's copy; the blocks' layout stays.
  void keep_on_device();

  // unique[k], k < blocks().num_entries(), from the raw values (the element forms' first);
  // nothing when chunked (add_chunks summed them).
  void reduce(const double* raw, double* unique) const;
  void reduce_on_device(const double* d_raw, double* d_unique) const;
  // Element form m's values, computed by `form` at x chunk by chunk, added into unique (zeroed
  // before the first form); false if the form rejects x. x and unique are in the memory space
  // where the values are summed (sums_on_device()).
  bool add_chunks(std::size_t m, HessianPattern& form, const double* x, double* unique);
  // Elements per chunk on the device: their values fill at most kDeviceChunkBytes.
  static constexpr std::size_t kDeviceChunkBytes = std::size_t{512} << 20;

 private:
  bool add_chunks_on_device(std::size_t m, HessianPattern& form, const double* d_x, double* d_unique);
  device::ElementBlockMap map(std::size_t m) const;  // form m's maps on the device

  bool built_ = false;
  bool chunked_ = false;
  bool device_sums_ = false;
  NodeBlockReduction blocks_;
  std::vector<double> chunk_values_;
  // Device chunks: per form, elements per chunk and each chunk's range of blocks; the values of
  // one chunk.
  std::vector<std::uint32_t> chunk_elements_;
  std::vector<std::vector<std::uint64_t>> chunk_block_begin_, chunk_block_end_;
  device::Array<double> d_chunk_values_{"element Hessian values of a chunk"};
  // Uploads the pattern's arrays below (with the masks and starts).
  void upload_pattern();
  device::Array<std::uint16_t> d_block_mask_{"node-block masks"};
  device::Array<std::uint32_t> d_block_start_{"node-block starts"};
  device::Array<std::int64_t> d_row_nodes_{"node-block row nodes"};
  device::Array<std::uint32_t> d_row_start_{"node-block row starts"}, d_col_{"node-block columns"};
  std::vector<device::Array<std::uint32_t>> d_block_offsets_, d_block_sources_;  // per element form
};

}  // namespace dipc
