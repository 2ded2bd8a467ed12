// ElementBlockPart: the element forms' part of the Hessian's raw values (elastic, consistent
// mass: 576 and 192 values per hex) and its reduction into the matrix's first entries, the
// distinct node blocks (NodeBlockReduction), built once: element patterns never change.
//
// Memory, per hex element (576 raw elastic values, 192 more with a consistent mass; about 27
// node blocks, 243 entries): 4 B per element node pair (64 per hex and element form) and, per
// block, 4 B per element form, 2 B of mask and 8 B of start, where the values are summed (the
// host, or the device with a device matrix); the summed values take 8 B per entry.
//
// A host matrix of host element forms sums their values element chunk by chunk (no array of
// all their raw values exists); the device sums them all at once, through the maps' sources.
#pragma once
#include <petscsys.h>

#include <cstdint>
#include <vector>

#include "assembly/hessian_pattern.hpp"
#include "assembly/node_block_reduction.hpp"
#include "device/device_runtime.hpp"

namespace dipc {

class ElementBlockPart {
 public:
  // The node blocks of the element forms' patterns on a rank that owns the global nodes
  // [owned_begin, owned_end). device_sums: the device sums the values, so the maps are built
  // there and stay there (the host keeps the pattern); chunked: the host sums them element
  // chunk by chunk (add_chunks).
  PetscErrorCode build(const std::vector<NodeBlockReduction::Input>& inputs, bool device_sums, bool chunked,
                       std::int64_t owned_begin, std::int64_t owned_end);
  bool built() const { return built_; }
  bool chunked() const { return chunked_; }
  const NodeBlockReduction& blocks() const { return blocks_; }
  // Puts the maps on the device where they are not yet (blocks built on the host for a matrix
  // that now lives on the device), then frees the host's copy; the blocks' layout stays.
  void keep_on_device();

  // unique[k], k < blocks().num_entries(), from the raw values (the element forms' first);
  // nothing when chunked (add_chunks summed them).
  void reduce(const double* raw, double* unique) const;
  void reduce_on_device(const double* d_raw, double* d_unique) const;
  // Element form m's values, computed by `form` at x chunk by chunk, added into unique (zeroed
  // before the first form); false if the form rejects x.
  bool add_chunks(std::size_t m, HessianPattern& form, const double* x, double* unique);

 private:
  bool built_ = false;
  bool chunked_ = false;
  NodeBlockReduction blocks_;
  std::vector<double> chunk_values_;
  device::Array<std::uint16_t> d_block_mask_{"node-block masks"};
  device::Array<std::uint64_t> d_block_start_{"node-block starts"};
  std::vector<device::Array<std::uint32_t>> d_block_offsets_, d_block_sources_;  // per element form
};

}  // namespace dipc
