// Boundary-face extraction (see boundary_faces.hpp). Faces are bucketed by their smallest
// node id with a counting sort, so the whole pass is linear in the number of elements and
// needs 8 bytes per face code plus 8 bytes per node; a bucket holds only the faces around
// one node (at most a few dozen), where sorting full keys is cheap.
#include "mesh/boundary_faces.hpp"

#include <algorithm>
#include <string>
#include <utility>

#include "mesh/mesh_error.hpp"

namespace dipc {
namespace {

constexpr int kFaceNodes[kHexFaces][4] = {{0, 4, 7, 3}, {1, 2, 6, 5}, {0, 1, 5, 4},
                                          {3, 7, 6, 2}, {0, 3, 2, 1}, {4, 5, 6, 7}};

using FaceKey = std::array<std::int64_t, 4>;

// A face is coded as 6 * element + face, so one int64 identifies it.
std::int64_t face_code(std::int64_t element, int face) { return kHexFaces * element + face; }

FaceKey sorted_face_nodes(const HexMesh& mesh, std::int64_t code) {
  const Hex& hex = mesh.hexes[static_cast<std::size_t>(code / kHexFaces)];
  const int face = static_cast<int>(code % kHexFaces);
  FaceKey key;
  for (int i = 0; i < 4; ++i) key[i] = hex[kFaceNodes[face][i]];
  std::sort(key.begin(), key.end());
  return key;
}

void check_node_ids(const HexMesh& mesh) {
  const auto nn = static_cast<std::int64_t>(mesh.num_nodes());
  for (std::size_t e = 0; e < mesh.num_elements(); ++e) {
    for (int k = 0; k < 8; ++k) {
      const std::int64_t node = mesh.hexes[e][k];
      if (node < 0 || node >= nn) {
        throw MeshError("extract_boundary_faces: element " + std::to_string(e) + " node " + std::to_string(k) +
                        " has id " + std::to_string(node) + ", outside [0, " + std::to_string(nn) + ")");
      }
    }
  }
}

std::string describe_face(std::int64_t code) {
  return "element " + std::to_string(code / kHexFaces) + " face " + std::to_string(code % kHexFaces);
}

}  // namespace

std::array<int, 4> hex_face_nodes(int face) {
  if (face < 0 || face >= kHexFaces) {
    throw MeshError("hex_face_nodes: face " + std::to_string(face) + " outside [0, 6)");
  }
  return {kFaceNodes[face][0], kFaceNodes[face][1], kFaceNodes[face][2], kFaceNodes[face][3]};
}

std::vector<BoundaryFace> extract_boundary_faces(const HexMesh& mesh) {
  check_node_ids(mesh);
  const std::size_t nn = mesh.num_nodes();
  const std::size_t ne = mesh.num_elements();

  auto smallest_node = [&](std::size_t e, int face) {
    const Hex& hex = mesh.hexes[e];
    std::int64_t m = hex[kFaceNodes[face][0]];
    for (int i = 1; i < 4; ++i) m = std::min(m, hex[kFaceNodes[face][i]]);
    return static_cast<std::size_t>(m);
  };

  std::vector<std::int64_t> bucket_begin(nn + 1, 0);
  for (std::size_t e = 0; e < ne; ++e) {
    for (int f = 0; f < kHexFaces; ++f) ++bucket_begin[smallest_node(e, f) + 1];
  }
  for (std::size_t n = 0; n < nn; ++n) bucket_begin[n + 1] += bucket_begin[n];
  std::vector<std::int64_t> codes(static_cast<std::size_t>(bucket_begin[nn]));
  {
    std::vector<std::int64_t> next(bucket_begin.begin(), bucket_begin.end() - 1);
    for (std::size_t e = 0; e < ne; ++e) {
      for (int f = 0; f < kHexFaces; ++f) {
        codes[next[smallest_node(e, f)]++] = face_code(static_cast<std::int64_t>(e), f);
      }
    }
  }

  // Bit f of is_boundary[e] marks face f of element e; the faces are emitted from it at the
  // end so the result comes out sorted by (element, face) without a global sort.
  std::vector<std::uint8_t> is_boundary(ne, 0);
  std::vector<std::pair<FaceKey, std::int64_t>> bucket;
  std::size_t num_boundary = 0;
  for (std::size_t n = 0; n < nn; ++n) {
    const std::int64_t begin = bucket_begin[n];
    const std::int64_t end = bucket_begin[n + 1];
    bucket.clear();
    for (std::int64_t i = begin; i < end; ++i) {
      bucket.emplace_back(sorted_face_nodes(mesh, codes[i]), codes[i]);
    }
    std::sort(bucket.begin(), bucket.end());
    for (std::size_t i = 0; i < bucket.size();) {
      std::size_t j = i + 1;
      while (j < bucket.size() && bucket[j].first == bucket[i].first) ++j;
      if (j - i > 2) {
        throw MeshError("extract_boundary_faces: " + std::to_string(j - i) + " elements share one face (" +
                        describe_face(bucket[i].second) + ", " + describe_face(bucket[i + 1].second) + ", " +
                        describe_face(bucket[i + 2].second) +
                        "): the mesh is non-manifold or has overlapping elements");
      }
      if (j - i == 1) {
        const std::int64_t code = bucket[i].second;
        is_boundary[static_cast<std::size_t>(code / kHexFaces)] |= static_cast<std::uint8_t>(1u << (code % kHexFaces));
        ++num_boundary;
      }
      i = j;
    }
  }

  std::vector<BoundaryFace> faces;
  faces.reserve(num_boundary);
  for (std::size_t e = 0; e < ne; ++e) {
    for (int f = 0; f < kHexFaces; ++f) {
      if (is_boundary[e] & (1u << f)) faces.push_back({static_cast<std::int64_t>(e), f});
    }
  }
  return faces;
}

}  // namespace dipc
