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

struct FaceRecord {
  std::array<std::int64_t, 4> nodes;  // sorted: the key faces are matched by
  std::int64_t element;
  std::int64_t face;
  bool operator<(const FaceRecord& o) const {
    if (nodes != o.nodes) return nodes < o.nodes;
    return element < o.element;
  }
  bool same_face(const FaceRecord& o) const { return nodes == o.nodes; }
};

// What an element's home learns about one of its faces: `other` is the element across it, or
// -1 when the face is on the boundary.
struct FaceAnswer {
  std::int64_t element;
  std::int64_t face;
  std::int64_t other;
};

// The faces at this home in the order of a sort by (nodes, element), in linear time: a counting
// sort by the smallest node, which lies in the home's node block [begin, end) for every face sent
// here, then a sort of each group, which holds the few faces whose smallest node that is (a node
// of a structured hex grid is a corner of 12 faces, each met twice). A std::sort of the 48-byte
// records took 2.2-3.3 s for the 6M faces of a 1M-hex cube on one rank, this 0.2-0.4 s.
std::vector<std::size_t> home_face_order(const std::vector<FaceRecord>& faces, std::int64_t begin, std::int64_t end) {
  std::vector<std::size_t> first(static_cast<std::size_t>(end - begin) + 1, 0);
  for (const FaceRecord& f : faces) ++first[static_cast<std::size_t>(f.nodes[0] - begin) + 1];
  for (std::size_t n = 1; n < first.size(); ++n) first[n] += first[n - 1];
  std::vector<std::size_t> order(faces.size());
  {
    std::vector<std::size_t> next(first.begin(), first.end() - 1);
    for (std::size_t i = 0; i < faces.size(); ++i) order[next[static_cast<std::size_t>(faces[i].nodes[0] - begin)]++] = i;
  }
  auto by_key = [&faces](std::size_t a, std::size_t b) { return faces[a] < faces[b]; };
  for (std::size_t n = 0; n + 1 < first.size(); ++n)
    if (first[n + 1] - first[n] > 1) std::sort(order.begin() + first[n], order.begin() + first[n + 1], by_key);
  return order;
}

// The answers for the elements' home ranks (to rank r: answers[r]) about the faces at this home,
// whose smallest nodes lie in [begin, end); `error` names the first face (in sorted order) of
// more than two elements. Takes the faces by value so that they are freed before the answers
// travel.
std::vector<std::vector<FaceAnswer>> answer_faces(std::vector<FaceRecord> faces, std::int64_t begin, std::int64_t end,
                                                  std::int64_t ne, int size, std::string& error) {
  const std::vector<std::size_t> order = home_face_order(faces, begin, end);
  std::vector<std::vector<FaceAnswer>> answers(size);
  for (std::size_t i = 0; i < order.size();) {
    const FaceRecord& a = faces[order[i]];
    std::size_t j = i + 1;
    while (j < order.size() && faces[order[j]].same_face(a)) ++j;
    if (j - i == 1) {
      answers[block_of(a.element, ne, size)].push_back({a.element, a.face, -1});
    } else if (j - i == 2) {
      const FaceRecord& b = faces[order[i + 1]];
      answers[block_of(a.element, ne, size)].push_back({a.element, a.face, b.element});
      answers[block_of(b.element, ne, size)].push_back({b.element, b.face, a.element});
    } else if (error.empty()) {
      error = std::to_string(j - i) + " elements share one face (elements " + std::to_string(a.element) + ", " +
              std::to_string(faces[order[i + 1]].element) + ", " + std::to_string(faces[order[i + 2]].element) +
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
  std::vector<std::vector<FaceRecord>> to_home(size);
  for (std::size_t e = 0; e < slice.hexes.size(); ++e) {
    for (int f = 0; f < kHexFaces; ++f) {
      const std::array<int, 4> corners = hex_face_nodes(f);
      FaceRecord r{};
      for (int i = 0; i < 4; ++i) r.nodes[i] = slice.hexes[e][corners[i]];
      std::sort(r.nodes.begin(), r.nodes.end());
      r.element = slice.element_begin + static_cast<std::int64_t>(e);
      r.face = f;
      to_home[block_of(r.nodes[0], nn, size)].push_back(r);
    }
  }
  std::vector<FaceRecord> faces = exchange_records(to_home, slice.comm);
  to_home = std::vector<std::vector<FaceRecord>>();
  std::string error;
  const std::vector<std::vector<FaceAnswer>> answers =
      answer_faces(std::move(faces), block_begin(nn, size, rank), block_begin(nn, size, rank + 1), ne, size, error);
  agree_on_error(slice.comm, error);
  const std::vector<FaceAnswer> mine = exchange_records(answers, slice.comm);
  FaceMatching m;
  const std::size_t n = slice.hexes.size();
  m.boundary_mask.assign(n, 0);
  m.offsets.assign(n + 1, 0);
  for (const FaceAnswer& a : mine) {
    const auto e = static_cast<std::size_t>(a.element - slice.element_begin);
    if (a.other < 0)
      m.boundary_mask[e] = static_cast<std::uint8_t>(m.boundary_mask[e] | (1u << a.face));
    else
      ++m.offsets[e + 1];
  }
  for (std::size_t e = 0; e < n; ++e) m.offsets[e + 1] += m.offsets[e];
  m.neighbours.resize(static_cast<std::size_t>(m.offsets[n]));
  std::vector<std::int64_t> next(m.offsets.begin(), m.offsets.end() - 1);
  for (const FaceAnswer& a : mine)
    if (a.other >= 0) m.neighbours[next[a.element - slice.element_begin]++] = a.other;
  for (std::size_t e = 0; e < n; ++e) std::sort(m.neighbours.begin() + m.offsets[e], m.neighbours.begin() + m.offsets[e + 1]);
  return m;
}

}  // namespace dipc
