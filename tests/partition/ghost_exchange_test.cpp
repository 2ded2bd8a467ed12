// GhostExchange under MPI (1, 2 and 3 ranks): Vec layouts, to_local fills owned and ghost
// values from the owners, add_to_global sums every holder's contribution into the owner,
// the same over a local node list extended with extra ghosts (setup's second overload),
// and mismatched Vecs or invalid node lists are rejected with an error code on every rank.
#include <gtest/gtest.h>
#include <petscvec.h>

#include <algorithm>
#include <utility>
#include <vector>

#include "box_mesh.hpp"
#include "distributed_mesh_checks.hpp"
#include "partition/ghost_exchange.hpp"

namespace dipc {
namespace {

#define ASSERT_PETSC(call) ASSERT_EQ(static_cast<int>(call), 0)

// A nodal field value that differs for every (global node, component).
double field(std::int64_t global_node, PetscInt component) {
  return 10.0 * static_cast<double>(global_node) + static_cast<double>(component) + 0.25;
}

class GhostExchangeTest : public ::testing::TestWithParam<PetscInt> {};

TEST_P(GhostExchangeTest, VecLayoutsFollowTheMesh) {
  const PetscInt bs = GetParam();
  const DistributedMesh part = test::distribute_from_root(test::two_body_mesh(), PETSC_COMM_WORLD);
  GhostExchange exchange;
  ASSERT_PETSC(exchange.setup(part, bs));
  Vec global = nullptr;
  Vec local = nullptr;
  ASSERT_PETSC(exchange.create_global_vec(&global));
  ASSERT_PETSC(exchange.create_local_vec(&local));

  PetscInt size = 0;
  PetscInt block = 0;
  PetscInt begin = 0;
  PetscInt end = 0;
  ASSERT_PETSC(VecGetSize(global, &size));
  ASSERT_PETSC(VecGetBlockSize(global, &block));
  ASSERT_PETSC(VecGetOwnershipRange(global, &begin, &end));
  EXPECT_EQ(size, bs * part.num_global_nodes);
  EXPECT_EQ(block, bs);
  EXPECT_EQ(begin, bs * part.node_offset);
  EXPECT_EQ(end - begin, bs * part.num_owned_nodes);

  MPI_Comm local_comm = MPI_COMM_NULL;
  ASSERT_PETSC(PetscObjectGetComm(reinterpret_cast<PetscObject>(local), &local_comm));
  EXPECT_EQ(test::size_of(local_comm), 1);
  ASSERT_PETSC(VecGetSize(local, &size));
  ASSERT_PETSC(VecGetBlockSize(local, &block));
  EXPECT_EQ(size, bs * part.num_local_nodes());
  EXPECT_EQ(block, bs);
  ASSERT_PETSC(VecDestroy(&local));
  ASSERT_PETSC(VecDestroy(&global));
}

// Fills the global Vec with field() at every owned node, scatters it to the local Vec (preset
// to -1) and expects field() of its global id at every local node, owned and ghost.
void expect_to_local_gives_owner_values(const GhostExchange& exchange, const DistributedMesh& part, PetscInt bs) {
  Vec global = nullptr;
  Vec local = nullptr;
  ASSERT_PETSC(exchange.create_global_vec(&global));
  ASSERT_PETSC(exchange.create_local_vec(&local));

  PetscScalar* values = nullptr;
  ASSERT_PETSC(VecGetArray(global, &values));
  for (int i = 0; i < part.num_owned_nodes; ++i) {
    for (PetscInt c = 0; c < bs; ++c) values[bs * i + c] = field(part.node_offset + i, c);
  }
  ASSERT_PETSC(VecRestoreArray(global, &values));
  ASSERT_PETSC(VecSet(local, -1.0));
  ASSERT_PETSC(exchange.to_local(global, local));

  const PetscScalar* received = nullptr;
  ASSERT_PETSC(VecGetArrayRead(local, &received));
  for (int i = 0; i < part.num_local_nodes(); ++i) {
    for (PetscInt c = 0; c < bs; ++c) {
      EXPECT_EQ(received[bs * i + c], field(part.local_to_global[i], c))
          << "local node " << i << (i < part.num_owned_nodes ? " (owned)" : " (ghost)");
    }
  }
  ASSERT_PETSC(VecRestoreArrayRead(local, &received));
  ASSERT_PETSC(VecDestroy(&local));
  ASSERT_PETSC(VecDestroy(&global));
}

TEST_P(GhostExchangeTest, ToLocalGivesEveryLocalNodeItsOwnersValue) {
  const PetscInt bs = GetParam();
  const DistributedMesh part = test::distribute_from_root(test::two_body_mesh(), PETSC_COMM_WORLD);
  GhostExchange exchange;
  ASSERT_PETSC(exchange.setup(part, bs));
  expect_to_local_gives_owner_values(exchange, part, bs);
}

// An exchange that shares another's scatter moves the same values, and keeps working after the
// other is gone (it holds a reference) or set up again for another block size.
TEST_P(GhostExchangeTest, SharedExchangeOutlivesItsSource) {
  const PetscInt bs = GetParam();
  const DistributedMesh part = test::distribute_from_root(test::two_body_mesh(), PETSC_COMM_WORLD);
  GhostExchange shared;
  {
    GhostExchange source;
    ASSERT_PETSC(source.setup(part, bs));
    ASSERT_PETSC(shared.share(source));
    ASSERT_PETSC(source.setup(part, bs + 1));
  }
  EXPECT_EQ(shared.block_size(), bs);
  expect_to_local_gives_owner_values(shared, part, bs);
  GhostExchange unset;
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  EXPECT_NE(shared.share(unset), 0);
  PetscPopErrorHandler();
}

TEST_P(GhostExchangeTest, AddToGlobalSumsOverRanksHoldingTheNode) {
  const PetscInt bs = GetParam();
  const HexMesh mesh = test::structured_box(6, 4, 3);
  const DistributedMesh part = test::distribute_from_root(mesh, PETSC_COMM_WORLD);
  const std::vector<std::int64_t> holders = test::ranks_holding_each_node(mesh, part);
  GhostExchange exchange;
  ASSERT_PETSC(exchange.setup(part, bs));
  Vec global = nullptr;
  Vec local = nullptr;
  ASSERT_PETSC(exchange.create_global_vec(&global));
  ASSERT_PETSC(exchange.create_local_vec(&local));
  ASSERT_PETSC(VecSet(global, 0.0));
  ASSERT_PETSC(VecSet(local, 1.0));
  ASSERT_PETSC(exchange.add_to_global(local, global));

  const PetscScalar* sums = nullptr;
  std::int64_t most_holders = 0;
  ASSERT_PETSC(VecGetArrayRead(global, &sums));
  for (int i = 0; i < part.num_owned_nodes; ++i) {
    const std::int64_t expected = holders[part.node_input_id[i]];
    most_holders = std::max(most_holders, expected);
    for (PetscInt c = 0; c < bs; ++c) {
      EXPECT_EQ(sums[bs * i + c], static_cast<PetscScalar>(expected)) << "owned node " << i;
    }
  }
  ASSERT_PETSC(VecRestoreArrayRead(global, &sums));
  MPI_Allreduce(MPI_IN_PLACE, &most_holders, 1, MPI_INT64_T, MPI_MAX, PETSC_COMM_WORLD);
  // Ghosts exist as soon as the box is cut, so some sum must exceed 1.
  const int num_ranks = test::size_of(PETSC_COMM_WORLD);
  EXPECT_LE(most_holders, num_ranks);
  if (num_ranks > 1) {
    EXPECT_GE(most_holders, 2);
  }
  ASSERT_PETSC(VecDestroy(&local));
  ASSERT_PETSC(VecDestroy(&global));
}

TEST_P(GhostExchangeTest, MismatchedVecIsAnError) {
  const PetscInt bs = GetParam();
  const DistributedMesh part = test::distribute_from_root(test::structured_box(6, 4, 3), PETSC_COMM_WORLD);
  GhostExchange exchange;
  Vec global = nullptr;
  Vec wrong_local = nullptr;
  ASSERT_PETSC(VecCreateSeq(PETSC_COMM_SELF, bs * part.num_local_nodes() + 1, &wrong_local));
  ASSERT_PETSC(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  EXPECT_NE(static_cast<int>(exchange.create_global_vec(&global)), 0) << "before setup()";
  EXPECT_NE(static_cast<int>(exchange.setup(part, 0)), 0) << "block size 0";
  ASSERT_PETSC(PetscPopErrorHandler());

  ASSERT_PETSC(exchange.setup(part, bs));
  ASSERT_PETSC(exchange.create_global_vec(&global));
  ASSERT_PETSC(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  EXPECT_NE(static_cast<int>(exchange.to_local(global, wrong_local)), 0);
  EXPECT_NE(static_cast<int>(exchange.add_to_global(wrong_local, global)), 0);
  ASSERT_PETSC(PetscPopErrorHandler());
  ASSERT_PETSC(VecDestroy(&wrong_local));
  ASSERT_PETSC(VecDestroy(&global));
}

TEST_P(GhostExchangeTest, ExtraGhostNodesRoundTrip) {
  // The mesh's local nodes extended with nodes the rank does not hold (different ones on
  // each rank) and with a repeated owned node and a repeated ghost, as the contact code
  // extends them with the nodes of other ranks' surface primitives.
  const PetscInt bs = GetParam();
  MPI_Comm comm = PETSC_COMM_WORLD;
  const int rank = test::rank_of(comm);
  const DistributedMesh part = test::distribute_from_root(test::two_body_mesh(), comm);
  std::vector<std::int64_t> nodes = part.local_to_global;
  std::vector<char> held(part.num_global_nodes, 0);
  for (std::int64_t g : nodes) held[g] = 1;
  for (std::int64_t g = 0; g < part.num_global_nodes; ++g) {
    if (!held[g] && (g + rank) % 3 == 0) nodes.push_back(g);
  }
  if (part.num_owned_nodes > 0) nodes.push_back(part.local_to_global[0]);
  if (part.num_ghost_nodes() > 0) nodes.push_back(part.local_to_global[part.num_owned_nodes]);
  std::int64_t extra = static_cast<std::int64_t>(nodes.size()) - part.num_local_nodes();
  MPI_Allreduce(MPI_IN_PLACE, &extra, 1, MPI_INT64_T, MPI_SUM, comm);
  ASSERT_GT(extra, test::size_of(comm) > 1 ? 2 : 0);

  GhostExchange exchange;
  ASSERT_PETSC(exchange.setup(comm, part.num_owned_nodes, nodes, part.num_global_nodes, bs));
  Vec global = nullptr;
  Vec local = nullptr;
  ASSERT_PETSC(exchange.create_global_vec(&global));
  ASSERT_PETSC(exchange.create_local_vec(&local));
  PetscInt size = 0;
  ASSERT_PETSC(VecGetSize(local, &size));
  ASSERT_EQ(size, bs * static_cast<PetscInt>(nodes.size()));
  ASSERT_PETSC(VecGetLocalSize(global, &size));
  ASSERT_EQ(size, bs * part.num_owned_nodes);

  PetscScalar* values = nullptr;
  ASSERT_PETSC(VecGetArray(global, &values));
  for (int i = 0; i < part.num_owned_nodes; ++i) {
    for (PetscInt c = 0; c < bs; ++c) values[bs * i + c] = field(part.node_offset + i, c);
  }
  ASSERT_PETSC(VecRestoreArray(global, &values));
  ASSERT_PETSC(VecSet(local, -1.0));
  ASSERT_PETSC(exchange.to_local(global, local));
  const PetscScalar* received = nullptr;
  ASSERT_PETSC(VecGetArrayRead(local, &received));
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    for (PetscInt c = 0; c < bs; ++c) {
      EXPECT_EQ(received[bs * i + c], field(nodes[i], c)) << "local entry " << i;
    }
  }
  ASSERT_PETSC(VecRestoreArrayRead(local, &received));

  // Every listed entry adds 1 into its owner: the sum is how often the node is listed.
  std::vector<std::int64_t> listed(part.num_global_nodes, 0);
  for (std::int64_t g : nodes) ++listed[g];
  listed = test::allreduce(listed, MPI_INT64_T, MPI_SUM, comm);
  ASSERT_PETSC(VecSet(global, 0.0));
  ASSERT_PETSC(VecSet(local, 1.0));
  ASSERT_PETSC(exchange.add_to_global(local, global));
  const PetscScalar* sums = nullptr;
  ASSERT_PETSC(VecGetArrayRead(global, &sums));
  for (int i = 0; i < part.num_owned_nodes; ++i) {
    for (PetscInt c = 0; c < bs; ++c) {
      EXPECT_EQ(sums[bs * i + c], static_cast<PetscScalar>(listed[part.node_offset + i])) << "owned node " << i;
    }
  }
  ASSERT_PETSC(VecRestoreArrayRead(global, &sums));
  ASSERT_PETSC(VecDestroy(&local));
  ASSERT_PETSC(VecDestroy(&global));
}

TEST_P(GhostExchangeTest, InvalidNodeListIsAnErrorOnEveryRank) {
  const PetscInt bs = GetParam();
  MPI_Comm comm = PETSC_COMM_WORLD;
  const int rank = test::rank_of(comm);
  const int last = test::size_of(comm) - 1;
  const DistributedMesh part = test::distribute_from_root(test::structured_box(6, 4, 3), comm);
  const std::int64_t n = part.num_global_nodes;
  ASSERT_GE(part.num_owned_nodes, 2);
  GhostExchange exchange;
  ASSERT_PETSC(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));

  std::vector<std::int64_t> out_of_range = part.local_to_global;
  if (rank == last) out_of_range.push_back(n);
  EXPECT_NE(static_cast<int>(exchange.setup(comm, part.num_owned_nodes, out_of_range, n, bs)), 0)
      << "a global id outside [0, n) on the last rank";

  std::vector<std::int64_t> swapped = part.local_to_global;
  if (rank == 0) std::swap(swapped[0], swapped[1]);
  EXPECT_NE(static_cast<int>(exchange.setup(comm, part.num_owned_nodes, swapped, n, bs)), 0)
      << "owned nodes out of order on rank 0";

  const int too_many = rank == last ? part.num_local_nodes() + 1 : part.num_owned_nodes;
  EXPECT_NE(static_cast<int>(exchange.setup(comm, too_many, part.local_to_global, n, bs)), 0)
      << "more owned nodes than listed nodes on the last rank";

  // Rank 0 declares its last owned node a ghost: locally valid, but the owned counts no
  // longer add up to the global count.
  const int fewer = rank == 0 ? part.num_owned_nodes - 1 : part.num_owned_nodes;
  EXPECT_NE(static_cast<int>(exchange.setup(comm, fewer, part.local_to_global, n, bs)), 0)
      << "owned counts that do not sum to the global node count";
  ASSERT_PETSC(PetscPopErrorHandler());

  // Nobody was left waiting in a collective: a valid setup still works everywhere.
  ASSERT_PETSC(exchange.setup(comm, part.num_owned_nodes, part.local_to_global, n, bs));
}

INSTANTIATE_TEST_SUITE_P(BlockSizes, GhostExchangeTest, ::testing::Values(1, 3));

}  // namespace
}  // namespace dipc
