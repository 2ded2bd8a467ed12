#include "assembly/element_block_part.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "assembly/cuda/element_kernels.hpp"

namespace dipc {

PetscErrorCode ElementBlockPart::build(const std::vector<NodeBlockReduction::Input>& inputs, bool device_sums,
                                       bool chunked, std::int64_t owned_begin, std::int64_t owned_end) {
  PetscFunctionBeginUser;
  PetscCheck(inputs.size() <= static_cast<std::size_t>(device::kMaxElementBlockMaps), PETSC_COMM_SELF, PETSC_ERR_SUP,
             "%zu element forms; the node-block reduction takes at most %d", inputs.size(),
             device::kMaxElementBlockMaps);
  try {
    if (device_sums) {
      // The device sums the values through the maps: they are built there (a radix sort of the
      // element node pairs) and stay there; the host gets the pattern.
      device::NodeBlocks on_device;
      blocks_ = NodeBlockReduction::build_on_device(inputs, owned_begin, owned_end, &on_device);
      d_block_mask_.resize(on_device.mask.size());
      device::copy_on_device(d_block_mask_.data(), on_device.mask.data(),
                             on_device.mask.size() * sizeof(std::uint16_t));
      upload_pattern();
      for (std::size_t m = 0; m < inputs.size(); ++m) {
        d_block_offsets_.push_back(std::move(on_device.offsets[m]));
        d_block_sources_.push_back(std::move(on_device.sources[m]));
      }
    } else {
      blocks_ = NodeBlockReduction::build(inputs, owned_begin, owned_end);
    }
    chunked_ = chunked;
    device_sums_ = device_sums;
    if (chunked_ && !device_sums_) blocks_.index_elements();
    if (chunked_ && device_sums_) {
      // Each chunk's blocks, found once: with elements and nodes numbered along the partition,
      // a chunk of elements reaches a narrow band of the blocks, and its sums run over that band.
      for (std::size_t m = 0; m < inputs.size(); ++m) {
        const std::size_t num_elements = static_cast<std::size_t>(inputs[m].pattern.num_elements);
        const std::size_t per = kDeviceChunkBytes / (sizeof(double) * element_values(inputs[m].pattern.layout));
        const std::size_t chunk = std::max<std::size_t>(1, std::min(per, num_elements));
        chunk_elements_.push_back(static_cast<std::uint32_t>(chunk));
        chunk_block_begin_.emplace_back();
        chunk_block_end_.emplace_back();
        device::element_chunk_block_ranges(blocks_.num_blocks(), map(m), chunk_elements_[m],
                                           (num_elements + chunk - 1) / chunk, &chunk_block_begin_[m],
                                           &chunk_block_end_[m]);
      }
    }
  } catch (const std::length_error& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_SUP, "%s", e.what());
  }
  built_ = true;
  PetscFunctionReturn(0);
}

void ElementBlockPart::upload_pattern() {
  d_block_start_.upload(blocks_.block_start_32());
  d_row_start_.upload(blocks_.row_start_32());
  d_col_.upload(blocks_.block_col_32());
  d_row_nodes_.upload(blocks_.row_nodes);
}

bool ElementBlockPart::device_index(device::BlockEntryIndex* index) const {
  if (d_block_start_.size() != blocks_.num_blocks() + 1) return false;
  index->num_rows = blocks_.row_nodes.size();
  index->row_nodes = d_row_nodes_.data();
  index->dense_begin = blocks_.dense_begin, index->dense_end = blocks_.dense_end;
  index->dense_below = blocks_.dense_below;
  index->row_start = d_row_start_.data();
  index->col = d_col_.data();
  index->mask = d_block_mask_.data();
  index->start = d_block_start_.data();
  return true;
}

void ElementBlockPart::keep_on_device() {
  if (!d_block_sources_.empty()) return;
  d_block_mask_.upload(blocks_.block_mask);
  upload_pattern();
  for (auto& form : blocks_.forms) {
    d_block_offsets_.emplace_back("node-block offsets");
    d_block_offsets_.back().upload(form.offsets);
    d_block_sources_.emplace_back("node-block sources");
    d_block_sources_.back().upload(form.sources);
    LargePageVector<std::uint32_t>().swap(form.offsets);
    LargePageVector<std::uint32_t>().swap(form.sources);
  }
}

void ElementBlockPart::reduce(const double* raw, double* unique) const {
  if (!chunked_) blocks_.reduce(raw, unique);
}

device::ElementBlockMap ElementBlockPart::map(std::size_t m) const {
  return {blocks_.forms[m].layout, blocks_.forms[m].raw_begin, d_block_offsets_[m].data(), d_block_sources_[m].data()};
}

void ElementBlockPart::reduce_on_device(const double* d_raw, double* d_unique) const {
  if (chunked_) return;
  std::vector<device::ElementBlockMap> maps;
  for (std::size_t m = 0; m < blocks_.forms.size(); ++m) maps.push_back(map(m));
  device::reduce_element_blocks(d_raw, blocks_.num_blocks(), d_block_mask_.data(), d_block_start_.data(), maps.data(),
                                static_cast<int>(maps.size()), d_unique);
}

bool ElementBlockPart::add_chunks_on_device(std::size_t m, HessianPattern& form, const double* d_x, double* d_unique) {
  ElementPattern pattern;
  form.element_pattern(&pattern);
  const std::size_t chunk = chunk_elements_[m];
  d_chunk_values_.resize(chunk * element_values(pattern.layout));
  const device::ElementBlockMap form_map = map(m);
  bool ok = true;
  for (std::size_t c = 0, first = 0; first < static_cast<std::size_t>(pattern.num_elements); ++c, first += chunk) {
    const std::size_t count = std::min(chunk, static_cast<std::size_t>(pattern.num_elements) - first);
    ok = form.element_hessian(d_x, static_cast<int>(first), static_cast<int>(count), d_chunk_values_.data()) && ok;
    device::add_element_block_chunk(d_chunk_values_.data(), static_cast<std::uint32_t>(first),
                                    static_cast<std::uint32_t>(count), chunk_block_begin_[m][c], chunk_block_end_[m][c],
                                    d_block_mask_.data(), d_block_start_.data(), form_map, d_unique);
  }
  return ok;
}

bool ElementBlockPart::add_chunks(std::size_t m, HessianPattern& form, const double* x, double* unique) {
  if (device_sums_) return add_chunks_on_device(m, form, x, unique);
  // Small enough to stay in cache (9.4 MB of elastic values), large enough that the calls cost
  // nothing.
  constexpr int kChunk = 2048;
  ElementPattern pattern;
  form.element_pattern(&pattern);
  chunk_values_.resize(static_cast<std::size_t>(kChunk) * element_values(pattern.layout));
  bool ok = true;
  for (int first = 0; first < pattern.num_elements; first += kChunk) {
    const int count = std::min(kChunk, pattern.num_elements - first);
    ok = form.element_hessian(x, first, count, chunk_values_.data()) && ok;
    blocks_.add_elements(m, first, count, chunk_values_.data(), unique);
  }
  return ok;
}

}  // namespace dipc
