#include "assembly/cuda/group_targets.hpp"

#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_select.cuh>

#include <algorithm>
#include <limits>

#include "device/cuda_check.cuh"

namespace dipc::device {

namespace {

constexpr int kThreads = 256;

// First index in [lo, hi) whose value is not below v, in an ascending array.
template <class T, class V>
__device__ std::size_t lower_bound(const T* a, std::size_t lo, std::size_t hi, V v) {
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    if (static_cast<V>(a[mid]) < v)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

// NodeBlockReduction::find_row: the block row of row_node, or -1.
__device__ std::int64_t find_row(const BlockEntryIndex& x, std::int64_t row_node) {
  if (row_node < 0 || x.num_rows == 0) return -1;
  if (row_node >= x.dense_begin && row_node < x.dense_end)
    return static_cast<std::int64_t>(x.dense_below + static_cast<std::size_t>(row_node - x.dense_begin));
  const std::size_t r = lower_bound(x.row_nodes, 0, x.num_rows, row_node);
  return r < x.num_rows && x.row_nodes[r] == row_node ? static_cast<std::int64_t>(r) : -1;
}

// The reserve's blocks of row_node: [*first, *last).
__device__ void reserve_row(const BlockEntryIndex& x, std::int64_t row_node, std::size_t* first, std::size_t* last) {
  if (row_node >= x.dense_begin && row_node < x.dense_end) {
    const std::size_t r = static_cast<std::size_t>(row_node - x.dense_begin);
    *first = x.reserve_dense_first[r], *last = x.reserve_dense_first[r + 1];
    return;
  }
  *first = lower_bound(x.reserve_row, 0, x.num_reserved, row_node);
  *last = lower_bound(x.reserve_row, *first, x.num_reserved, row_node + 1);
}

// The fixed part's extra entry of the dof pair (row, col), or -1 (HessianAssembler::find_fixed_extra).
__device__ std::int64_t find_extra(const BlockEntryIndex& x, std::int64_t row, std::int64_t col) {
  std::size_t lo = 0, hi = x.num_extra;
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    if (x.extra_row[mid] < row || (x.extra_row[mid] == row && x.extra_col[mid] < col))
      lo = mid + 1;
    else
      hi = mid;
  }
  if (lo < x.num_extra && x.extra_row[lo] == row && x.extra_col[lo] == col)
    return static_cast<std::int64_t>(x.extra_first) + static_cast<std::int64_t>(lo);
  return -1;
}

__device__ unsigned rank_in_mask(unsigned mask, int bit) { return __popc(mask & ((1u << bit) - 1u)); }

// The element block (block row s, col_node): its mask (0 where none) and first entry.
__device__ unsigned element_block(const BlockEntryIndex& x, std::int64_t s, std::int64_t col_node, std::size_t* start) {
  if (s < 0 || col_node < 0) return 0u;
  const std::size_t k0 = x.row_start[s], k1 = x.row_start[s + 1];
  const std::size_t k = lower_bound(x.col, k0, k1, col_node);
  if (k == k1 || static_cast<std::int64_t>(x.col[k]) != col_node) return 0u;
  *start = x.start[k];
  return x.mask[k];
}

// One thread per group row (group g, node a): node a's blocks with each node b of the group, the
// 9 entries of each, as the host's lookup takes them (element block, reserve, fixed extras).
__global__ void map_node_groups_kernel(const NodeGroupView* groups, const std::uint64_t* value_begin,
                                       std::size_t num_groups, BlockEntryIndex x, std::uint32_t dropped,
                                       std::uint32_t* targets, unsigned long long* missing) {
  const std::size_t t = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  const std::size_t g = t / 4;
  const int a = static_cast<int>(t % 4);
  if (g >= num_groups) return;
  const NodeGroupView group = groups[g];
  if (a >= group.count) return;
  const std::int64_t row_node = group.node[a];
  const std::int64_t s = find_row(x, row_node);
  std::size_t reserve_first = 0, reserve_last = 0;
  if (x.num_reserved) reserve_row(x, row_node, &reserve_first, &reserve_last);
  const int n3 = 3 * group.count;
  unsigned long long none = 0;
  for (int b = 0; b < group.count; ++b) {
    const std::int64_t col_node = group.node[b];
    std::size_t held_start = 0;
    const unsigned held = element_block(x, s, col_node, &held_start);
    unsigned reserved = 0;
    std::size_t reserved_start = 0;
    if (held != 0x1ffu && reserve_first < reserve_last) {
      const std::size_t k = lower_bound(x.reserve_col, reserve_first, reserve_last, col_node);
      if (k < reserve_last && x.reserve_col[k] == col_node)
        reserved = x.reserve_mask[k], reserved_start = x.reserve_start[k];
    }
    for (int bit = 0; bit < 9; ++bit) {
      std::int64_t entry;
      if (held >> bit & 1u)
        entry = static_cast<std::int64_t>(held_start + rank_in_mask(held, bit));
      else if (reserved >> bit & 1u)
        entry = static_cast<std::int64_t>(reserved_start + rank_in_mask(reserved, bit));
      else
        entry = find_extra(x, 3 * row_node + bit / 3, 3 * col_node + bit % 3);
      const std::size_t k = value_begin[g] + static_cast<std::size_t>((3 * a + bit / 3) * n3 + 3 * b + bit % 3);
      if (entry < 0) ++none;
      targets[k] = entry < 0 ? dropped : static_cast<std::uint32_t>(entry);
    }
  }
  if (none) atomicAdd(missing, none);
}

// Reserve candidates: one thread per group row (group g, node a) writes the keys (row node << 32 |
// column node) of its blocks that the elements do not hold whole into keys[16 g + 4 a + b], the
// other slots kNoPair (sorted last).
constexpr std::uint64_t kNoPair = ~std::uint64_t{0};
__global__ void reserve_keys_kernel(const NodeGroupView* groups, std::size_t num_groups, BlockEntryIndex x,
                                    std::uint64_t* keys) {
  const std::size_t t = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  const std::size_t g = t / 4;
  const int a = static_cast<int>(t % 4);
  if (g >= num_groups) return;
  const NodeGroupView group = groups[g];
  std::uint64_t* out = keys + 16 * g + 4 * a;
  for (int b = 0; b < 4; ++b) out[b] = kNoPair;
  if (a >= group.count) return;
  const std::int64_t row_node = group.node[a];
  const std::int64_t s = find_row(x, row_node);
  for (int b = 0; b < group.count; ++b) {
    std::size_t start;
    if (element_block(x, s, group.node[b], &start) != 0x1ffu)
      out[b] = static_cast<std::uint64_t>(row_node) << 32 | static_cast<std::uint64_t>(group.node[b]);
  }
}

// Each distinct pair's entries that neither its element block nor the fixed extras hold.
__global__ void reserve_masks_kernel(const std::uint64_t* keys, std::size_t n, BlockEntryIndex x,
                                     std::uint16_t* masks) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k >= n) return;
  const std::int64_t row_node = static_cast<std::int64_t>(keys[k] >> 32);
  const std::int64_t col_node = static_cast<std::int64_t>(keys[k] & 0xffffffffu);
  std::size_t start;
  unsigned m = 0x1ffu & ~element_block(x, find_row(x, row_node), col_node, &start);
  for (int bit = 0; bit < 9; ++bit)
    if (m >> bit & 1u && find_extra(x, 3 * row_node + bit / 3, 3 * col_node + bit % 3) >= 0) m &= ~(1u << bit);
  masks[k] = static_cast<std::uint16_t>(m);
}

}  // namespace

std::size_t map_node_groups(const NodeGroupView* groups, const std::uint64_t* value_begin, std::size_t num_groups,
                            const BlockEntryIndex& index, std::uint32_t dropped, std::uint32_t* targets) {
  if (!num_groups) return 0;
  Array<unsigned long long> missing("missing Hessian entries");
  missing.resize(1);
  missing.set_zero();
  map_node_groups_kernel<<<blocks_for(4 * num_groups, kThreads), kThreads>>>(groups, value_begin, num_groups, index,
                                                                             dropped, targets, missing.data());
  DIPC_CUDA_CHECK_LAUNCH();
  unsigned long long count = 0;
  missing.download(&count);
  return static_cast<std::size_t>(count);
}

void reserve_node_groups(const NodeGroupView* groups, std::size_t num_groups, const BlockEntryIndex& index,
                         std::vector<std::int64_t>* rows, std::vector<std::int64_t>* cols,
                         std::vector<std::uint16_t>* masks) {
  rows->clear(), cols->clear(), masks->clear();
  if (!num_groups) return;
  if (16 * num_groups > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw DeviceError("the reserve's node pairs: more than the device sort's 2^31 - 1 on one rank: run on more ranks");
  Array<NodeGroupView> d_groups("reserve's node groups");
  d_groups.upload(groups, num_groups);
  const std::size_t slots = 16 * num_groups;
  Array<std::uint64_t> keys("reserve keys"), sorted("reserve keys, sorted");
  keys.resize(slots), sorted.resize(slots);
  reserve_keys_kernel<<<blocks_for(4 * num_groups, kThreads), kThreads>>>(d_groups.data(), num_groups, index,
                                                                          keys.data());
  DIPC_CUDA_CHECK_LAUNCH();
  // Sorted, then made distinct into keys (its first `distinct`).
  Array<unsigned char> scratch("reserve scratch");
  Array<int> count("reserve count");
  count.resize(1);
  std::size_t sort_bytes = 0, unique_bytes = 0;
  const int n = static_cast<int>(slots);
  DIPC_CUDA_CHECK(cub::DeviceRadixSort::SortKeys(nullptr, sort_bytes, keys.data(), sorted.data(), n));
  DIPC_CUDA_CHECK(cub::DeviceSelect::Unique(nullptr, unique_bytes, sorted.data(), keys.data(), count.data(), n));
  scratch.resize(std::max<std::size_t>({sort_bytes, unique_bytes, 1}));
  DIPC_CUDA_CHECK(cub::DeviceRadixSort::SortKeys(scratch.data(), sort_bytes, keys.data(), sorted.data(), n));
  DIPC_CUDA_CHECK(cub::DeviceSelect::Unique(scratch.data(), unique_bytes, sorted.data(), keys.data(), count.data(), n));
  int distinct = 0;
  count.download(&distinct);
  std::uint64_t last = 0;
  if (distinct > 0) copy_to_host(&last, keys.data() + distinct - 1, sizeof(last));
  const std::size_t pairs = static_cast<std::size_t>(distinct) - (distinct > 0 && last == kNoPair ? 1 : 0);
  Array<std::uint16_t> d_masks("reserve masks");
  d_masks.resize(pairs);
  if (pairs) {
    reserve_masks_kernel<<<blocks_for(pairs, kThreads), kThreads>>>(keys.data(), pairs, index, d_masks.data());
    DIPC_CUDA_CHECK_LAUNCH();
  }
  std::vector<std::uint64_t> host_keys(pairs);
  if (pairs) copy_to_host(host_keys.data(), keys.data(), pairs * sizeof(std::uint64_t));
  masks->resize(pairs);
  d_masks.download(masks->data());
  rows->resize(pairs), cols->resize(pairs);
  for (std::size_t p = 0; p < pairs; ++p) {
    (*rows)[p] = static_cast<std::int64_t>(host_keys[p] >> 32);
    (*cols)[p] = static_cast<std::int64_t>(host_keys[p] & 0xffffffffu);
  }
}

}  // namespace dipc::device
