// The host side of contact_kernels.hpp shared by CUDA and CPU-only builds: the host pair list
// and the uploads of pair lists and obstacles (plain Array copies).
#include "contact/cuda/contact_kernels.hpp"

#include <algorithm>

#include "contact/obstacle_nodes.hpp"

namespace dipc::device {

void ContactPairList::clear() { kind.clear(), nodes.clear(), weight.clear(), eps_x.clear(), plane.clear(); }

void ContactPairList::add(PairKind pair_kind, const std::int32_t pair_nodes[4], double pair_weight, double pair_eps_x,
                          int pair_plane) {
  kind.push_back(pair_kind);
  nodes.insert(nodes.end(), pair_nodes, pair_nodes + 4);
  weight.push_back(pair_weight);
  eps_x.push_back(pair_eps_x);
  plane.push_back(pair_plane);
}

void ContactPairList::resize(std::size_t n) {
  kind.resize(n), nodes.resize(4 * n), weight.resize(n), eps_x.resize(n), plane.resize(n);
}

void ContactPairList::set(std::size_t i, PairKind pair_kind, const std::int32_t pair_nodes[4], double pair_weight,
                          double pair_eps_x, int pair_plane) {
  kind[i] = pair_kind;
  std::copy(pair_nodes, pair_nodes + 4, nodes.begin() + 4 * static_cast<std::ptrdiff_t>(i));
  weight[i] = pair_weight;
  eps_x[i] = pair_eps_x;
  plane[i] = pair_plane;
}

bool ContactPairList::operator==(const ContactPairList& o) const {
  return kind == o.kind && nodes == o.nodes && weight == o.weight && eps_x == o.eps_x && plane == o.plane;
}

void DeviceContactPairs::upload(const ContactPairList& pairs) {
  count = pairs.size();
  // Slot-major nodes, and the COO offsets of the pairs taken as a Hessian pattern.
  std::vector<std::int32_t> slot_major(4 * count);
  std::vector<std::size_t> offset(count);
  std::vector<std::int32_t> kinds(count);
  hessian_values = 0;
  for (std::size_t i = 0; i < count; ++i) {
    for (int k = 0; k < 4; ++k) slot_major[k * count + i] = pairs.nodes[4 * i + k];
    offset[i] = hessian_values;
    int slots[4];
    const std::size_t n = 3 * static_cast<std::size_t>(
                                  body_slots(&pairs.nodes[4 * i], pair_node_count(pairs.kind[i]), slots));
    kinds[i] = static_cast<std::int32_t>(pairs.kind[i]);
    hessian_values += n * n;
  }
  kind.upload(kinds);
  nodes.upload(slot_major);
  weight.upload(pairs.weight);
  eps_x.upload(pairs.eps_x);
  plane.upload(pairs.plane);
  hessian_offset.upload(offset);
}

void DeviceContactObstacles::upload_planes(const std::vector<double>& points, const std::vector<double>& normals) {
  point.upload(points);
  normal.upload(normals);
}

void DeviceContactObstacles::upload_vertices(const std::vector<double>& start, const std::vector<double>& end) {
  vertex_start.upload(start);
  vertex_end.upload(end);
}

}  // namespace dipc::device
