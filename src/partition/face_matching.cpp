// match_faces (see face_matching.hpp): one all-to-all of face records to the faces' home ranks,
// a linear-time ordering there (by smallest node, then within each node's few faces), and one
// all-to-all of the answers back to the elements' home ranks. A rank's own faces and answers
// (all of them on one rank, most of them with a balanced numbering) skip the records.
#include "partition/face_matching.hpp"

#include <algorithm>
#include <array>
#include <string>
#include <utility>

#include "mesh/boundary_faces.hpp"
#include "partition/mpi_exchange.hpp"

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

// Calls visit(sorted node ids, 6 * element + face) for every face of the slice's elements.
template <class Visit>
void for_each_face(const MeshSlice& slice, Visit visit) {
  for (std::size_t e = 0; e < slice.hexes.size(); ++e) {
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
  std::vector<std::size_t> count(homes.size, 0);
  for_each_face(slice, [&](const std::array<std::int64_t, 4>& nodes, std::int64_t) { ++count[homes.of(nodes)]; });
  count[homes.rank] = 0;
  std::vector<std::vector<FaceRecord>> to_home(homes.size);
  if (std::all_of(count.begin(), count.end(), [](std::size_t c) { return c == 0; })) return to_home;  // all own
  for (int r = 0; r < homes.size; ++r) to_home[r].reserve(count[r]);
  for_each_face(slice, [&](const std::array<std::int64_t, 4>& nodes, std::int64_t element_face) {
    if (!homes.here(nodes)) to_home[homes.of(nodes)].push_back({nodes, element_face});
  });
  return to_home;
}

// The faces at this home (the slice's own and those `received`) grouped by their smallest
// node, which lies in the home's node block [begin, end): a counting sort, linear in the faces.
// Group n is faces[first[n] .. first[n + 1]), sorted by (nodes, element, face); groups are
// small (a node of a structured hex grid is the corner of 12 faces, each met twice). The order
// is that of a sort of all faces, which took 2.2-3.3 s with std::sort for the 6M faces of a
// 1M-hex cube on one rank.
std::vector<HomeFace> group_faces(const MeshSlice& slice, const FaceHomes& homes, const std::vector<FaceRecord>& received,
                                  std::vector<std::size_t>& first) {
  const std::int64_t begin = block_begin(homes.num_nodes, homes.size, homes.rank);
  const std::int64_t end = block_begin(homes.num_nodes, homes.size, homes.rank + 1);
  auto group_of = [begin](const std::array<std::int64_t, 4>& nodes) { return static_cast<std::size_t>(nodes[0] - begin); };
  first.assign(static_cast<std::size_t>(end - begin) + 1, 0);
  for_each_face(slice, [&](const std::array<std::int64_t, 4>& nodes, std::int64_t) {
    if (homes.here(nodes)) ++first[group_of(nodes) + 1];
  });
  for (const FaceRecord& f : received) ++first[group_of(f.nodes) + 1];
  for (std::size_t n = 1; n < first.size(); ++n) first[n] += first[n - 1];
  std::vector<HomeFace> grouped(first.back());
  std::vector<std::size_t> next(first.begin(), first.end() - 1);
  auto place = [&](const std::array<std::int64_t, 4>& nodes, std::int64_t element_face) {
    grouped[next[group_of(nodes)]++] = {nodes[1], nodes[2], nodes[3], element_face};
  };
  for_each_face(slice, [&](const std::array<std::int64_t, 4>& nodes, std::int64_t element_face) {
    if (homes.here(nodes)) place(nodes, element_face);
  });
  for (const FaceRecord& f : received) place(f.nodes, f.element_face);
  for (std::size_t n = 0; n + 1 < first.size(); ++n)
    if (first[n + 1] - first[n] > 1) std::sort(grouped.begin() + first[n], grouped.begin() + first[n + 1]);
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
  std::vector<std::vector<FaceAnswer>> answers(homes.size);
  auto answer = [&](const HomeFace& f, std::int64_t other) {
    const int home = block_of(element_of(f), ne, homes.size);
    if (home == homes.rank)
      across[static_cast<std::size_t>(f.element_face - own_begin)] = other;
    else
      answers[home].push_back({f.element_face, other});
  };
  for (std::size_t n = 0; n + 1 < first.size(); ++n)
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
      } else if (error.empty()) {
        error = std::to_string(j - i) + " elements share one face (elements " + std::to_string(element_of(a)) + ", " +
                std::to_string(element_of(grouped[i + 1])) + ", " + std::to_string(element_of(grouped[i + 2])) +
                "): the mesh is non-manifold or has overlapping elements";
      }
      i = j;
    }
  return answers;
}

// The boundary masks and dual graph rows of the slice's elements from `across` (answer_faces).
FaceMatching graph_of(const std::vector<std::int64_t>& across) {
  const std::size_t n = across.size() / kHexFaces;
  FaceMatching m;
  m.boundary_mask.assign(n, 0);
  m.offsets.assign(n + 1, 0);
  for (std::size_t e = 0; e < n; ++e)
    for (int f = 0; f < kHexFaces; ++f) {
      if (across[kHexFaces * e + f] < 0)
        m.boundary_mask[e] = static_cast<std::uint8_t>(m.boundary_mask[e] | (1u << f));
      else
        ++m.offsets[e + 1];
    }
  for (std::size_t e = 0; e < n; ++e) m.offsets[e + 1] += m.offsets[e];
  m.neighbours.resize(static_cast<std::size_t>(m.offsets[n]));
  for (std::size_t e = 0; e < n; ++e) {
    const auto row = m.neighbours.begin() + m.offsets[e];
    auto next = row;
    for (int f = 0; f < kHexFaces; ++f)
      if (across[kHexFaces * e + f] >= 0) *next++ = across[kHexFaces * e + f];
    std::sort(row, next);
  }
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
