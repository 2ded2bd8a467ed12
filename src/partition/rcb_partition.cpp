// element_centroids and rcb_partition (see rcb_partition.hpp).
#include "partition/rcb_partition.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

#include "partition/mpi_exchange.hpp"
#include "partition/touched_nodes.hpp"

namespace dipc {
namespace {

// An unsigned integer whose order is that of the double: flip every bit of a negative number,
// only the sign bit of a positive one (IEEE 754 orders magnitudes like their bit patterns).
std::uint64_t ordered_bits(double x) {
  std::uint64_t u;
  std::memcpy(&u, &x, sizeof u);
  return (u >> 63) ? ~u : u | (std::uint64_t{1} << 63);
}

// One level's group: the elements that are to become parts [first, first + parts).
struct Group {
  int first, parts;
};

// Per group, the smallest value v in [lo, hi] whose count(v) (summed over the ranks) reaches
// target; count must not decrease in v and count(hi) must reach target. Groups with lo == hi
// on entry are settled. One pass of `count_at` and one MPI_Allreduce per halving.
template <class CountAt>
std::vector<std::uint64_t> smallest_reaching(std::vector<std::uint64_t> lo, std::vector<std::uint64_t> hi,
                                             const std::vector<std::int64_t>& target, CountAt count_at, MPI_Comm comm) {
  const std::size_t groups = lo.size();
  std::vector<std::uint64_t> mid(groups);
  std::vector<std::int64_t> count(groups);
  for (;;) {
    bool open = false;
    for (std::size_t g = 0; g < groups; ++g) {
      mid[g] = lo[g] + (hi[g] - lo[g]) / 2;
      open = open || lo[g] < hi[g];
    }
    // Every rank holds the same lo and hi, so every rank leaves at the same halving.
    if (!open) return lo;
    count_at(mid, count);
    MPI_Allreduce(MPI_IN_PLACE, count.data(), static_cast<int>(groups), MPI_INT64_T, MPI_SUM, comm);
    for (std::size_t g = 0; g < groups; ++g) {
      if (lo[g] == hi[g]) continue;
      if (count[g] >= target[g])
        hi[g] = mid[g];
      else
        lo[g] = mid[g] + 1;
    }
  }
}

}  // namespace

std::vector<Vec3> element_centroids(const MeshSlice& slice) {
  int size = 1;
  MPI_Comm_size(slice.comm, &size);
  const TouchedNodes touched(slice.hexes.size(), [&slice](std::size_t e) -> const Hex& { return slice.hexes[e]; });
  std::vector<std::vector<std::int64_t>> asks(size);
  for (std::int64_t n : touched.ids()) asks[block_of(n, slice.num_global_nodes, size)].push_back(n);
  std::vector<int> asker;
  const std::vector<std::int64_t> asked = exchange_records(std::move(asks), slice.comm, &asker);
  std::vector<std::vector<Vec3>> replies(size);
  for (std::size_t k = 0; k < asked.size(); ++k)
    replies[asker[k]].push_back(slice.nodes[static_cast<std::size_t>(asked[k] - slice.node_begin)]);
  // Replies come back by home, homes hold increasing blocks of ids and each answers in the
  // order asked: the coordinates line up with touched.ids().
  const std::vector<Vec3> x = exchange_records(std::move(replies), slice.comm);
  std::vector<Vec3> centroids(slice.hexes.size());
  for (std::size_t e = 0; e < slice.hexes.size(); ++e) {
    Vec3 c{0, 0, 0};
    for (std::int64_t n : slice.hexes[e]) {
      const Vec3& p = x[static_cast<std::size_t>(touched.position(n))];
      for (int d = 0; d < 3; ++d) c[d] += p[d];
    }
    for (int d = 0; d < 3; ++d) centroids[e][d] = c[d] / 8;
  }
  return centroids;
}

std::vector<int> rcb_partition(const MeshSlice& slice, int parts) {
  const MPI_Comm comm = slice.comm;
  const std::vector<Vec3> centroid = element_centroids(slice);
  const std::size_t n = centroid.size();
  std::vector<Group> groups{{0, parts}};
  std::vector<int> group(n, 0);
  std::vector<std::uint64_t> key(n);
  while (std::any_of(groups.begin(), groups.end(), [](const Group& g) { return g.parts > 1; })) {
    const std::size_t count = groups.size();
    // Global element counts and centroid boxes: one MIN reduction of (min, -max) per axis.
    std::vector<std::int64_t> members(count, 0);
    std::vector<double> box(6 * count, std::numeric_limits<double>::infinity());
    for (std::size_t e = 0; e < n; ++e) {
      const std::size_t g = static_cast<std::size_t>(group[e]);
      ++members[g];
      for (int d = 0; d < 3; ++d) {
        box[6 * g + d] = std::min(box[6 * g + d], centroid[e][d]);
        box[6 * g + 3 + d] = std::min(box[6 * g + 3 + d], -centroid[e][d]);
      }
    }
    MPI_Allreduce(MPI_IN_PLACE, members.data(), static_cast<int>(count), MPI_INT64_T, MPI_SUM, comm);
    MPI_Allreduce(MPI_IN_PLACE, box.data(), static_cast<int>(box.size()), MPI_DOUBLE, MPI_MIN, comm);
    // Per group: the axis, how many elements go low, and the search range of the cut's key.
    // Only a group that is split with elements on both sides is searched; the others keep
    // lo == hi (a group of one part, or a tiny one whose low side is empty or everything).
    std::vector<int> axis(count, 0);
    std::vector<std::int64_t> low_count(count, 0);
    std::vector<char> split(count, 0);
    std::vector<std::uint64_t> lo(count, 0), hi(count, 0);
    for (std::size_t g = 0; g < count; ++g) {
      const double* b = &box[6 * g];
      for (int d = 1; d < 3; ++d)
        if (-b[3 + d] - b[d] > -b[3 + axis[g]] - b[axis[g]]) axis[g] = d;
      const std::int64_t q = groups[g].parts, q_low = q / 2;
      low_count[g] = (members[g] * q_low + q / 2) / q;
      split[g] = q > 1 && low_count[g] > 0 && low_count[g] < members[g];
      if (split[g]) {
        lo[g] = ordered_bits(b[axis[g]]);
        hi[g] = ordered_bits(-b[3 + axis[g]]);
      }
    }
    for (std::size_t e = 0; e < n; ++e) key[e] = ordered_bits(centroid[e][axis[static_cast<std::size_t>(group[e])]]);
    // The cut key: the smallest K with count(key <= K) >= low_count.
    const std::vector<std::uint64_t> cut = smallest_reaching(
        lo, hi, low_count,
        [&](const std::vector<std::uint64_t>& k, std::vector<std::int64_t>& c) {
          std::fill(c.begin(), c.end(), 0);
          for (std::size_t e = 0; e < n; ++e) c[static_cast<std::size_t>(group[e])] += key[e] <= k[static_cast<std::size_t>(group[e])];
        },
        comm);
    // Of the elements on the cut (key == K), the low side takes those with the smallest ids:
    // as many as low_count leaves after the elements below it.
    std::vector<std::int64_t> below(count, 0);
    std::vector<std::size_t> on_cut;
    for (std::size_t e = 0; e < n; ++e) {
      const std::size_t g = static_cast<std::size_t>(group[e]);
      below[g] += key[e] < cut[g];
      if (split[g] && key[e] == cut[g]) on_cut.push_back(e);
    }
    MPI_Allreduce(MPI_IN_PLACE, below.data(), static_cast<int>(count), MPI_INT64_T, MPI_SUM, comm);
    std::vector<std::int64_t> take(count);
    std::vector<std::uint64_t> id_lo(count, 0), id_hi(count, 0);
    for (std::size_t g = 0; g < count; ++g) {
      take[g] = low_count[g] - below[g];
      if (split[g]) id_hi[g] = static_cast<std::uint64_t>(slice.num_global_elements - 1);
    }
    const std::vector<std::uint64_t> last_id = smallest_reaching(
        id_lo, id_hi, take,
        [&](const std::vector<std::uint64_t>& t, std::vector<std::int64_t>& c) {
          std::fill(c.begin(), c.end(), 0);
          for (std::size_t e : on_cut) {
            const std::size_t g = static_cast<std::size_t>(group[e]);
            c[g] += static_cast<std::uint64_t>(slice.element_begin) + e <= t[g];
          }
        },
        comm);
    // The next level's groups: a split group becomes (low, high), a settled one stays.
    std::vector<Group> next;
    std::vector<int> low_group(count), high_group(count);
    for (std::size_t g = 0; g < count; ++g) {
      low_group[g] = high_group[g] = static_cast<int>(next.size());
      if (groups[g].parts == 1) {
        next.push_back(groups[g]);
        continue;
      }
      const int q_low = groups[g].parts / 2;
      next.push_back({groups[g].first, q_low});
      high_group[g] = static_cast<int>(next.size());
      next.push_back({groups[g].first + q_low, groups[g].parts - q_low});
    }
    for (std::size_t e = 0; e < n; ++e) {
      const std::size_t g = static_cast<std::size_t>(group[e]);
      if (groups[g].parts == 1) {
        group[e] = low_group[g];
        continue;
      }
      const std::uint64_t id = static_cast<std::uint64_t>(slice.element_begin) + e;
      const bool low = split[g] ? key[e] < cut[g] || (key[e] == cut[g] && id <= last_id[g]) : low_count[g] > 0;
      group[e] = low ? low_group[g] : high_group[g];
    }
    groups = std::move(next);
  }
  std::vector<int> part(n);
  for (std::size_t e = 0; e < n; ++e) part[e] = groups[static_cast<std::size_t>(group[e])].first;
  return part;
}

}  // namespace dipc
