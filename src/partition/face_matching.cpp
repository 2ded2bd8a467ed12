// match_faces (see face_matching.hpp): one all-to-all of face records to the faces' home ranks,
// a linear-time ordering there (by smallest node, then within each node's few faces), and one
// all-to-all of the answers back to the elements' home ranks.
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

// The face's node ids in increasing order, by a sorting network (std::sort's call costs more
// than the work for 4 values, 6 times per element).
std::array<std::int64_t, 4> sorted_face_nodes(const Hex& hex, int face) {
  const std::array<int, 4> corners = hex_face_nodes(face);
  std::array<std::int64_t, 4> n{hex[corners[0]], hex[corners[1]], hex[corners[2]], hex[corners[3]]};
  auto order = [&n](int i, int j) {
    if (n[j] < n[i]) std::swap(n[i], n[j]);
  };
  order(0, 1), order(2, 3), order(0, 2), order(1, 3), order(1, 2);
  return n;
}

// The face records for the faces' home ranks (to rank r: the result's r-th list). Counted
// first, so that every list is allocated once.
std::vector<std::vector<FaceRecord>> faces_to_homes(const MeshSlice& slice, int size) {
  const std::int64_t nn = slice.num_global_nodes;
  std::vector<std::size_t> count(size, 0);
  for (const Hex& hex : slice.hexes)
    for (int f = 0; f < kHexFaces; ++f) ++count[block_of(sorted_face_nodes(hex, f)[0], nn, size)];
  std::vector<std::vector<FaceRecord>> to_home(size);
  for (int r = 0; r < size; ++r) to_home[r].reserve(count[r]);
  for (std::size_t e = 0; e < slice.hexes.size(); ++e)
    for (int f = 0; f < kHexFaces; ++f) {
      const std::array<std::int64_t, 4> nodes = sorted_face_nodes(slice.hexes[e], f);
      const std::int64_t element = slice.element_begin + static_cast<std::int64_t>(e);
      to_home[block_of(nodes[0], nn, size)].push_back({nodes, kHexFaces * element + f});
    }
  return to_home;
}

// The faces at this home grouped by their smallest node, which lies in the home's node block
// [begin, end) for every face sent here: a counting sort, linear in the faces. Group n is
// faces[first[n] .. first[n + 1]), sorted by (nodes, element, face); groups are small (a node
// of a structured hex grid is the corner of 12 faces, each met twice). The order is that of a
// sort of all faces, which took 2.2-3.3 s with std::sort for the 6M faces of a 1M-hex cube on
// one rank.
std::vector<HomeFace> group_faces(const std::vector<FaceRecord>& faces, std::int64_t begin, std::int64_t end,
                                  std::vector<std::size_t>& first) {
  first.assign(static_cast<std::size_t>(end - begin) + 1, 0);
  for (const FaceRecord& f : faces) ++first[static_cast<std::size_t>(f.nodes[0] - begin) + 1];
  for (std::size_t n = 1; n < first.size(); ++n) first[n] += first[n - 1];
  std::vector<HomeFace> grouped(faces.size());
  std::vector<std::size_t> next(first.begin(), first.end() - 1);
  for (const FaceRecord& f : faces)
    grouped[next[static_cast<std::size_t>(f.nodes[0] - begin)]++] = {f.nodes[1], f.nodes[2], f.nodes[3], f.element_face};
  for (std::size_t n = 0; n + 1 < first.size(); ++n)
    if (first[n + 1] - first[n] > 1) std::sort(grouped.begin() + first[n], grouped.begin() + first[n + 1]);
  return grouped;
}

// The answers for the elements' home ranks (to rank r: answers[r]) about the faces at this home,
// whose smallest nodes lie in [begin, end); `error` names the first face (in sorted order) of
// more than two elements. Takes the faces by value so that they are freed before the answers
// travel.
std::vector<std::vector<FaceAnswer>> answer_faces(std::vector<FaceRecord> faces, std::int64_t begin, std::int64_t end,
                                                  std::int64_t ne, int size, std::string& error) {
  std::vector<std::size_t> first;
  const std::vector<HomeFace> grouped = group_faces(faces, begin, end, first);
  faces = std::vector<FaceRecord>();
  auto element_of = [](const HomeFace& f) { return f.element_face / kHexFaces; };
  auto home_of = [&](const HomeFace& f) { return block_of(element_of(f), ne, size); };
  std::vector<std::vector<FaceAnswer>> answers(size);
  for (std::size_t n = 0; n + 1 < first.size(); ++n)
    for (std::size_t i = first[n]; i < first[n + 1];) {
      const HomeFace& a = grouped[i];
      std::size_t j = i + 1;
      while (j < first[n + 1] && grouped[j].same_face(a)) ++j;
      if (j - i == 1) {
        answers[home_of(a)].push_back({a.element_face, -1});
      } else if (j - i == 2) {
        const HomeFace& b = grouped[i + 1];
        answers[home_of(a)].push_back({a.element_face, element_of(b)});
        answers[home_of(b)].push_back({b.element_face, element_of(a)});
      } else if (error.empty()) {
        error = std::to_string(j - i) + " elements share one face (elements " + std::to_string(element_of(a)) + ", " +
                std::to_string(element_of(grouped[i + 1])) + ", " + std::to_string(element_of(grouped[i + 2])) +
                "): the mesh is non-manifold or has overlapping elements";
      }
      i = j;
    }
  return answers;
}

}  // namespace

FaceMatching match_faces(const MeshSlice& slice) {
  int rank = 0, size = 1;
  MPI_Comm_rank(slice.comm, &rank);
  MPI_Comm_size(slice.comm, &size);
  const std::int64_t nn = slice.num_global_nodes, ne = slice.num_global_elements;
  std::vector<std::vector<FaceRecord>> to_home = faces_to_homes(slice, size);
  std::vector<FaceRecord> faces = exchange_records(std::move(to_home), slice.comm);
  std::string error;
  std::vector<std::vector<FaceAnswer>> answers =
      answer_faces(std::move(faces), block_begin(nn, size, rank), block_begin(nn, size, rank + 1), ne, size, error);
  agree_on_error(slice.comm, error);
  const std::vector<FaceAnswer> mine = exchange_records(std::move(answers), slice.comm);
  FaceMatching m;
  const std::size_t n = slice.hexes.size();
  m.boundary_mask.assign(n, 0);
  m.offsets.assign(n + 1, 0);
  auto local = [&slice](const FaceAnswer& a) {
    return static_cast<std::size_t>(a.element_face / kHexFaces - slice.element_begin);
  };
  for (const FaceAnswer& a : mine) {
    const std::size_t e = local(a);
    if (a.other < 0)
      m.boundary_mask[e] = static_cast<std::uint8_t>(m.boundary_mask[e] | (1u << (a.element_face % kHexFaces)));
    else
      ++m.offsets[e + 1];
  }
  for (std::size_t e = 0; e < n; ++e) m.offsets[e + 1] += m.offsets[e];
  m.neighbours.resize(static_cast<std::size_t>(m.offsets[n]));
  std::vector<std::int64_t> next(m.offsets.begin(), m.offsets.end() - 1);
  for (const FaceAnswer& a : mine)
    if (a.other >= 0) m.neighbours[next[local(a)]++] = a.other;
  for (std::size_t e = 0; e < n; ++e) std::sort(m.neighbours.begin() + m.offsets[e], m.neighbours.begin() + m.offsets[e + 1]);
  return m;
}

}  // namespace dipc
