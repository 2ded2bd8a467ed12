// Collective consistency checks of a DistributedMesh against the input HexMesh (which every
// rank of the tests builds, although only rank 0's copy is passed to distribute_mesh).
#pragma once
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <set>
#include <vector>

#include "mesh/hex_mesh.hpp"
#include "partition/distributed_mesh.hpp"

namespace dipc::test {

inline int rank_of(MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank;
}

inline int size_of(MPI_Comm comm) {
  int size = 0;
  MPI_Comm_size(comm, &size);
  return size;
}

// distribute_mesh with the mesh on rank 0 only, as the driver calls it.
inline DistributedMesh distribute_from_root(const HexMesh& mesh, MPI_Comm comm) {
  return distribute_mesh(rank_of(comm) == 0 ? mesh : HexMesh{}, comm);
}

template <class T>
std::vector<T> allreduce(std::vector<T> values, MPI_Datatype type, MPI_Op op, MPI_Comm comm) {
  MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), type, op, comm);
  return values;
}

// How many ranks hold each input node as a local (owned or ghost) node.
inline std::vector<std::int64_t> ranks_holding_each_node(const HexMesh& mesh, const DistributedMesh& part) {
  std::vector<std::int64_t> holders(mesh.num_nodes(), 0);
  for (std::int64_t input : part.node_input_id) ++holders.at(input);
  return allreduce(holders, MPI_INT64_T, MPI_SUM, part.comm);
}

inline void expect_consistent_with(const HexMesh& mesh, const DistributedMesh& part) {
  MPI_Comm comm = part.comm;
  const int rank = rank_of(comm);
  const std::int64_t ne = static_cast<std::int64_t>(mesh.num_elements());
  const std::size_t nn = mesh.num_nodes();

  std::vector<char> touched(nn, 0);
  for (const Hex& hex : mesh.hexes) {
    for (std::int64_t node : hex) touched[node] = 1;
  }
  const auto num_touched = std::count(touched.begin(), touched.end(), 1);
  EXPECT_EQ(part.num_global_elements, ne);
  EXPECT_EQ(part.num_global_nodes, num_touched);

  // Elements: each input element on exactly one rank, contiguous increasing ranges.
  std::vector<std::int64_t> element_count(ne, 0);
  for (std::int64_t input : part.element_input_id) ++element_count.at(input);
  element_count = allreduce(element_count, MPI_INT64_T, MPI_SUM, comm);
  for (std::int64_t e = 0; e < ne; ++e) EXPECT_EQ(element_count[e], 1) << "element " << e;
  std::int64_t elements_before = 0;
  std::int64_t my_elements = part.num_elements();
  MPI_Exscan(&my_elements, &elements_before, 1, MPI_INT64_T, MPI_SUM, comm);
  if (rank == 0) elements_before = 0;
  EXPECT_EQ(part.element_offset, elements_before);
  EXPECT_TRUE(std::is_sorted(part.element_input_id.begin(), part.element_input_id.end()));
  ASSERT_EQ(part.element_body.size(), part.elements.size());
  ASSERT_EQ(part.element_input_id.size(), part.elements.size());

  // Owned nodes: contiguous ranges in rank order covering every touched node once.
  ASSERT_EQ(part.coordinates.size(), part.local_to_global.size());
  ASSERT_EQ(part.node_input_id.size(), part.local_to_global.size());
  ASSERT_LE(part.num_owned_nodes, part.num_local_nodes());
  std::int64_t nodes_before = 0;
  std::int64_t my_owned = part.num_owned_nodes;
  MPI_Exscan(&my_owned, &nodes_before, 1, MPI_INT64_T, MPI_SUM, comm);
  if (rank == 0) nodes_before = 0;
  EXPECT_EQ(part.node_offset, nodes_before);
  std::int64_t total_owned = 0;
  MPI_Allreduce(&my_owned, &total_owned, 1, MPI_INT64_T, MPI_SUM, comm);
  EXPECT_EQ(total_owned, part.num_global_nodes);
  std::vector<std::int64_t> owner_count(nn, 0);
  for (int i = 0; i < part.num_owned_nodes; ++i) {
    EXPECT_EQ(part.local_to_global[i], part.node_offset + i);
    ++owner_count.at(part.node_input_id[i]);
  }
  owner_count = allreduce(owner_count, MPI_INT64_T, MPI_SUM, comm);
  for (std::size_t n = 0; n < nn; ++n) EXPECT_EQ(owner_count[n], touched[n]) << "node " << n;
  EXPECT_TRUE(std::is_sorted(part.node_input_id.begin(), part.node_input_id.begin() + part.num_owned_nodes))
      << "owned nodes must be numbered in increasing input id";

  // Ghosts: sorted, owned by a lower rank, and that owner is the lowest rank holding them.
  std::vector<int> lowest_holder(nn, INT_MAX);
  for (std::int64_t input : part.node_input_id) lowest_holder[input] = rank;
  lowest_holder = allreduce(lowest_holder, MPI_INT, MPI_MIN, comm);
  for (int i = 0; i < part.num_local_nodes(); ++i) {
    const int lowest = lowest_holder[part.node_input_id[i]];
    if (i < part.num_owned_nodes) {
      EXPECT_EQ(lowest, rank) << "owned local node " << i;
    } else {
      EXPECT_LT(lowest, rank) << "ghost local node " << i;
      EXPECT_LT(part.local_to_global[i], part.node_offset);
      if (i > part.num_owned_nodes) {
        EXPECT_LT(part.local_to_global[i - 1], part.local_to_global[i]);
      }
    }
  }

  // Global ids agree with the owner's: global id -> input id as published by owners.
  std::vector<std::int64_t> input_of_global(part.num_global_nodes, 0);
  for (int i = 0; i < part.num_owned_nodes; ++i) {
    input_of_global.at(part.local_to_global[i]) = part.node_input_id[i] + 1;
  }
  input_of_global = allreduce(input_of_global, MPI_INT64_T, MPI_SUM, comm);
  for (int i = 0; i < part.num_local_nodes(); ++i) {
    EXPECT_EQ(input_of_global.at(part.local_to_global[i]), part.node_input_id[i] + 1);
    EXPECT_EQ(part.coordinates[i], mesh.nodes.at(part.node_input_id[i])) << "local node " << i;
  }

  // Elements reference the right nodes, and local nodes are exactly the touched ones.
  std::vector<char> used(part.num_local_nodes(), 0);
  for (int e = 0; e < part.num_elements(); ++e) {
    const std::int64_t input = part.element_input_id[e];
    EXPECT_EQ(part.element_body[e], mesh.body.at(input));
    for (int k = 0; k < 8; ++k) {
      const std::int32_t local = part.elements[e][k];
      ASSERT_GE(local, 0);
      ASSERT_LT(local, part.num_local_nodes());
      EXPECT_EQ(part.node_input_id[local], mesh.hexes[input][k]) << "element " << input;
      used[local] = 1;
    }
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << "a local node no local element uses";

  // Node sets: every name everywhere, restricted exactly to local nodes, union == input.
  ASSERT_EQ(part.node_sets.size(), mesh.node_sets.size());
  for (const auto& [name, input_nodes] : mesh.node_sets) {
    ASSERT_EQ(part.node_sets.count(name), 1u) << name;
    const std::vector<std::int32_t>& local_ids = part.node_sets.at(name);
    EXPECT_TRUE(std::adjacent_find(local_ids.begin(), local_ids.end(), [](auto a, auto b) { return a >= b; }) ==
                local_ids.end())
        << name << " must be sorted and unique";
    const std::set<std::int64_t> input_set(input_nodes.begin(), input_nodes.end());
    std::vector<char> in_local_set(part.num_local_nodes(), 0);
    for (std::int32_t local : local_ids) {
      ASSERT_GE(local, 0);
      ASSERT_LT(local, part.num_local_nodes());
      in_local_set[local] = 1;
    }
    std::vector<int> union_flags(nn, 0);
    for (int i = 0; i < part.num_local_nodes(); ++i) {
      const bool member = input_set.count(part.node_input_id[i]) > 0;
      EXPECT_EQ(in_local_set[i] != 0, member) << name << " local node " << i;
      if (in_local_set[i]) union_flags[part.node_input_id[i]] = 1;
    }
    union_flags = allreduce(union_flags, MPI_INT, MPI_MAX, comm);
    for (std::size_t n = 0; n < nn; ++n) {
      const bool expected = touched[n] && input_set.count(static_cast<std::int64_t>(n)) > 0;
      EXPECT_EQ(union_flags[n] != 0, expected) << name << " node " << n;
    }
  }
}

inline void expect_identical(const DistributedMesh& a, const DistributedMesh& b) {
  EXPECT_EQ(a.num_global_nodes, b.num_global_nodes);
  EXPECT_EQ(a.num_global_elements, b.num_global_elements);
  EXPECT_EQ(a.node_offset, b.node_offset);
  EXPECT_EQ(a.num_owned_nodes, b.num_owned_nodes);
  EXPECT_EQ(a.local_to_global, b.local_to_global);
  EXPECT_EQ(a.coordinates, b.coordinates);
  EXPECT_EQ(a.node_input_id, b.node_input_id);
  EXPECT_EQ(a.element_offset, b.element_offset);
  EXPECT_EQ(a.elements, b.elements);
  EXPECT_EQ(a.element_body, b.element_body);
  EXPECT_EQ(a.element_input_id, b.element_input_id);
  EXPECT_EQ(a.node_sets, b.node_sets);
  EXPECT_EQ(a.boundary_face_mask, b.boundary_face_mask);
  const OwnedSurface& sa = a.owned_surface;
  const OwnedSurface& sb = b.owned_surface;
  EXPECT_EQ(sa.num_global_triangles, sb.num_global_triangles);
  EXPECT_EQ(sa.num_global_edges, sb.num_global_edges);
  EXPECT_EQ(sa.num_global_vertices, sb.num_global_vertices);
  EXPECT_EQ(sa.triangle_gid, sb.triangle_gid);
  EXPECT_EQ(sa.edges, sb.edges);
  EXPECT_EQ(sa.edge_gid, sb.edge_gid);
  EXPECT_EQ(sa.edge_body, sb.edge_body);
  EXPECT_EQ(sa.vertices, sb.vertices);
  EXPECT_EQ(sa.vertex_gid, sb.vertex_gid);
  EXPECT_EQ(sa.vertex_body, sb.vertex_body);
}

}  // namespace dipc::test
