// match_faces (see face_matching.hpp): one all-to-all of face records to the faces' home ranks,
// a linear-time ordering there (by smallest node, then within each node's few faces), and one
// all-to-all of the answers back to the elements' home ranks. A rank's own faces and answers
// (all of them on one rank, most of them with a balanced numbering) skip the records. The
// passes over elements and over face groups run on the host threads (threads/host_threads.hpp),
// each writing what does not depend on the thread count: per-item outputs, counts, or lists
// joined in chunk order.
#include "partition/face_matching.hpp"

#include <algorithm>
#include <array>
#include <string>
#include <utility>

#include "mesh/boundary_faces.hpp"
#include "partition/mpi_exchange.hpp"
#include "threads/host_threads.hpp"

namespace dipc {
namespace {

// A face on its way to its home: its 4 node ids sorted (the key faces are matched by) and
// 6 * element + face, which orders like (element, face).
struct FaceRecord {
  std::array<std::int64_t, 4> nodes;
  std::int64_t element_face;
};

// A face at its home, in the group of its smallest node: the other 3 node ids, sorted, and
// 6 * element + face. Compact (32 bytes) and stored group by group, so that each group's sort
// and the matching read consecutive memory.
struct HomeFace {
  std::int64_t a, b, c;
  std::int64_t element_face;
  bool same_face(const HomeFace& o) const { return a == o.a && b == o.b && c == o.c; }
  bool operator<(const HomeFace& o) const {
    if (a != o.a) return a < o.a;
    if (b != o.b) return b < o.b;
    if (c != o.c) return c < o.c;
    return element_face < o.element_face;
  }
};

// What an element's home learns about one of its faces: `other` is the element across it, or
// -1 when the face is on the boundary.
struct FaceAnswer {
  std::int64_t element_face;
  std::int64_t other;
};

// The face's node ids in increasing order, by a sorting network of branch-free min/max pairs
// (std::sort's call, and the branches' mispredictions on ids in no particular order, cost more
// than the work for 4 values, 3 times per face).
std::array<std::int64_t, 4> sorted_face_nodes(const Hex& hex, int face) {
  const std::array<int, 4> corners = hex_face_nodes(face);
  std::array<std::int64_t, 4> n{hex[corners[0]], hex[corners[1]], hex[corners[2]], hex[corners[3]]};
  auto order = [&n](int i, int j) {
    const std::int64_t low = std::min(n[i], n[j]), high = std::max(n[i], n[j]);
    n[i] = low, n[j] = high;
  };
  order(0, 1), order(2, 3), order(0, 2), order(1, 3), order(1, 2);
  return n;
}

// Calls visit(sorted node ids, 6 * element + face) for every face of the slice's elements
// [begin, end).
template <class Visit>
void for_each_face(const MeshSlice& slice, std::size_t begin, std::size_t end, Visit visit) {
  for (std::size_t e = begin; e < end; ++e) {
    const std::int64_t element = slice.element_begin + static_cast<std::int64_t>(e);
    for (int f = 0; f < kHexFaces; ++f) visit(sorted_face_nodes(slice.hexes[e], f), kHexFaces * element + f);
  }
}

// Where the faces meet: the home rank of a face is that of its smallest node.
struct FaceHomes {
  std::int64_t num_nodes;
  int size, rank;
  int of(const std::array<std::int64_t, 4>& nodes) const { return block_of(nodes[0], num_nodes, size); }
  bool here(const std::array<std::int64_t, 4>& nodes) const { return of(nodes) == rank; }
};

// The face records for the other ranks (to rank r: the result's r-th list; this rank's own
// faces go straight to group_faces, without a record). Counted first, so that every list is
// allocated once.
std::vector<std::vector<FaceRecord>> faces_to_homes(const MeshSlice& slice, const FaceHomes& homes) {
  if (homes.size == 1) return std::vector<std::vector<FaceRecord>>(1);  // every face is at home: no pass to count
  const std::size_t ranks = static_cast<std::size_t>(homes.size);
  // count[c * ranks + r]: the faces of chunk c for rank r, then where chunk c's start in list r.
  std::vector<std::size_t> count(static_cast<std::size_t>(host_threads()) * ranks, 0);
  const int chunks = parallel_chunks(slice.hexes.size(), [&](int c, std::size_t begin, std::size_t end) {
    std::size_t* mine = &count[static_cast<std::size_t>(c) * ranks];
    for_each_face(slice, begin, end, [&](const std::array<std::int64_t, 4>& nodes, std::int64_t) {
      if (!homes.here(nodes)) ++mine[homes.of(nodes)];
    });
  });
  const std::vector<std::size_t> total = chunk_starts(count, chunks, ranks);
  std::vector<std::vector<FaceRecord>> to_home(ranks);
  for (std::size_t r = 0; r < ranks; ++r) to_home[r].resize(total[r]);
  parallel_chunks(slice.hexes.size(), [&](int c, std::size_t begin, std::size_t end) {
    std::size_t* next = &count[static_cast<std::size_t>(c) * ranks];
    for_each_face(slice, begin, end, [&](const std::array<std::int64_t, 4>& nodes, std::int64_t element_face) {
      if (homes.here(nodes)) return;
      const int r = homes.of(nodes);
      to_home[static_cast<std::size_t>(r)][next[r]++] = {nodes, element_face};
    });
  });
  return to_home;
}

// The faces at this home (the slice's own and those `received`) grouped by their smallest
// node, which lies in the home's node block [begin, end): a counting sort, linear in the faces.
// Group n is faces[first[n] .. first[n + 1]), sorted by (nodes, element, face); groups are
// small (a node of a structured hex grid is the corner of 12 faces, each met twice). The order
// is that of a sort of all faces, which took 2.2-3.3 s with std::sort for the 6M faces of a
// 1M-hex cube on one rank.
std::vector<HomeFace> group_faces(const MeshSlice& slice, const FaceHomes& homes,
                                  const std::vector<FaceRecord>& received, std::vector<std::size_t>& first) {
  const std::int64_t begin = block_begin(homes.num_nodes, homes.size, homes.rank);
  const std::int64_t end = block_begin(homes.num_nodes, homes.size, homes.rank + 1);
  auto group_of = [begin](const std::array<std::int64_t, 4>& nodes) {
    return static_cast<std::size_t>(nodes[0] - begin);
  };
  // Counted and placed by atomic additions from the threads: a group's faces land in an order
  // that depends on the threads, which the group's sort then replaces by a total order
  // (element_face is unique).
  first.assign(static_cast<std::size_t>(end - begin) + 1, 0);
  parallel_for(slice.hexes.size(), [&](std::size_t e0, std::size_t e1) {
    for_each_face(slice, e0, e1, [&](const std::array<std::int64_t, 4>& nodes, std::int64_t) {
      if (homes.here(nodes)) atomic_fetch_add(first[group_of(nodes) + 1], std::size_t{1});
    });
  });
  for (const FaceRecord& f : received) ++first[group_of(f.nodes) + 1];
  for (std::size_t n = 1; n < first.size(); ++n) first[n] += first[n - 1];
  std::vector<HomeFace> grouped(first.back());
  std::vector<std::size_t> next(first.begin(), first.end() - 1);
  auto place = [&](const std::array<std::int64_t, 4>& nodes, std::int64_t element_face) {
    grouped[atomic_fetch_add(next[group_of(nodes)], std::size_t{1})] = {nodes[1], nodes[2], nodes[3], element_face};
  };
  parallel_for(slice.hexes.size(), [&](std::size_t e0, std::size_t e1) {
    for_each_face(slice, e0, e1, [&](const std::array<std::int64_t, 4>& nodes, std::int64_t element_face) {
      if (homes.here(nodes)) place(nodes, element_face);
    });
  });
  parallel_for(received.size(), [&](std::size_t i0, std::size_t i1) {
    for (std::size_t i = i0; i < i1; ++i) place(received[i].nodes, received[i].element_face);
  });
  parallel_for(first.size() - 1, [&](std::size_t n0, std::size_t n1) {
    for (std::size_t n = n0; n < n1; ++n)
      if (first[n + 1] - first[n] > 1) std::sort(grouped.begin() + first[n], grouped.begin() + first[n + 1]);
  });
  return grouped;
}

// The answers about the faces at this home: those for this rank's own elements written into
// `across` (across[6 * slice element + face] = the element across the face, -1 on the boundary),
// those for other ranks returned (to rank r: the result's r-th list). `error` names the first
// face (in sorted order) of more than two elements. Takes the received faces by value so that
// they are freed before the answers travel.
std::vector<std::vector<FaceAnswer>> answer_faces(const MeshSlice& slice, const FaceHomes& homes,
                                                  std::vector<FaceRecord> received, std::vector<std::int64_t>& across,
                                                  std::string& error) {
  std::vector<std::size_t> first;
  const std::vector<HomeFace> grouped = group_faces(slice, homes, received, first);
  received = std::vector<FaceRecord>();
  const std::int64_t ne = slice.num_global_elements, own_begin = kHexFaces * slice.element_begin;
  auto element_of = [](const HomeFace& f) { return f.element_face / kHexFaces; };
  // The groups in chunks on the host threads: answers for other ranks in per-chunk lists, joined
  // in chunk order (= group order, as one thread would give them); the error of the lowest
  // chunk that has one (= the first in sorted order).
  const std::size_t groups = first.size() - 1;
  const std::size_t max_chunks = static_cast<std::size_t>(host_threads());
  std::vector<std::vector<std::vector<FaceAnswer>>> chunk_answers(max_chunks);
  std::vector<std::string> chunk_error(max_chunks);
  const int chunks = parallel_chunks(
      groups,
      [&](int c, std::size_t g0, std::size_t g1) {
        std::vector<std::vector<FaceAnswer>>& answers = chunk_answers[static_cast<std::size_t>(c)];
        answers.resize(static_cast<std::size_t>(homes.size));
        std::string& chunk_first_error = chunk_error[static_cast<std::size_t>(c)];
        auto answer = [&](const HomeFace& f, std::int64_t other) {
          const int home = block_of(element_of(f), ne, homes.size);
          if (home == homes.rank)
            across[static_cast<std::size_t>(f.element_face - own_begin)] = other;
          else
            answers[static_cast<std::size_t>(home)].push_back({f.element_face, other});
        };
        for (std::size_t n = g0; n < g1; ++n)
          for (std::size_t i = first[n]; i < first[n + 1];) {
            const HomeFace& a = grouped[i];
            std::size_t j = i + 1;
            while (j < first[n + 1] && grouped[j].same_face(a)) ++j;
            if (j - i == 1) {
              answer(a, -1);
            } else if (j - i == 2) {
              const HomeFace& b = grouped[i + 1];
              answer(a, element_of(b));
              answer(b, element_of(a));
            } else if (chunk_first_error.empty()) {
              chunk_first_error = std::to_string(j - i) + " elements share one face (elements " +
                                  std::to_string(element_of(a)) + ", " + std::to_string(element_of(grouped[i + 1])) +
                                  ", " + std::to_string(element_of(grouped[i + 2])) +
                                  "): the mesh is non-manifold or has overlapping elements";
            }
            i = j;
          }
      },
      1024);
  std::vector<std::vector<FaceAnswer>> answers(static_cast<std::size_t>(homes.size));
  for (int c = 0; c < chunks; ++c) {
    if (error.empty()) error = chunk_error[static_cast<std::size_t>(c)];
    for (std::size_t r = 0; r < answers.size(); ++r) {
      std::vector<FaceAnswer>& part = chunk_answers[static_cast<std::size_t>(c)][r];
      if (answers[r].empty())
        answers[r] = std::move(part);
      else
        answers[r].insert(answers[r].end(), part.begin(), part.end());
    }
  }
  return answers;
}

// The boundary masks and dual graph rows of the slice's elements from `across` (answer_faces).
FaceMatching graph_of(const std::vector<std::int64_t>& across) {
  const std::size_t n = across.size() / kHexFaces;
  FaceMatching m;
  m.boundary_mask.assign(n, 0);
  m.offsets.assign(n + 1, 0);
  parallel_for(n, [&](std::size_t e0, std::size_t e1) {
    for (std::size_t e = e0; e < e1; ++e)
      for (int f = 0; f < kHexFaces; ++f) {
        if (across[kHexFaces * e + f] < 0)
          m.boundary_mask[e] = static_cast<std::uint8_t>(m.boundary_mask[e] | (1u << f));
        else
          ++m.offsets[e + 1];
      }
  });
  for (std::size_t e = 0; e < n; ++e) m.offsets[e + 1] += m.offsets[e];
  m.neighbours.resize(static_cast<std::size_t>(m.offsets[n]));
  parallel_for(n, [&](std::size_t e0, std::size_t e1) {
    for (std::size_t e = e0; e < e1; ++e) {
      const auto row = m.neighbours.begin() + m.offsets[e];
      auto next = row;
      for (int f = 0; f < kHexFaces; ++f)
        if (across[kHexFaces * e + f] >= 0) *next++ = across[kHexFaces * e + f];
      std::sort(row, next);
    }
  });
  return m;
}

}  // namespace

FaceMatching match_faces(const MeshSlice& slice) {
  int rank = 0, size = 1;
  MPI_Comm_rank(slice.comm, &rank);
  MPI_Comm_size(slice.comm, &size);
  const FaceHomes homes{slice.num_global_nodes, size, rank};
  std::vector<FaceRecord> received = exchange_records(faces_to_homes(slice, homes), slice.comm);
  // Every face of a valid mesh gets its answer, so -1 (boundary) is only a default.
  std::vector<std::int64_t> across(kHexFaces * slice.hexes.size(), -1);
  std::string error;
  std::vector<std::vector<FaceAnswer>> answers = answer_faces(slice, homes, std::move(received), across, error);
  agree_on_error(slice.comm, error);
  for (const FaceAnswer& a : exchange_records(std::move(answers), slice.comm))
    across[static_cast<std::size_t>(a.element_face - kHexFaces * slice.element_begin)] = a.other;
  return graph_of(across);
}

}  // namespace dipc
