// GhostExchange (see ghost_exchange.hpp): one VecScatter from the distributed Vec to the
// local Vec, built from a block index set whose block i is local node i's global node id;
// the forward scatter fills owned and ghost values, the reverse scatter with ADD_VALUES sums
// every rank's local contributions into the owners.
#include "partition/ghost_exchange.hpp"

#include <cstdint>
#include <vector>

namespace dipc {

GhostExchange::~GhostExchange() {
  // A destructor cannot propagate an error code; destroying a valid scatter does not fail.
  (void)VecScatterDestroy(&scatter_);
}

namespace {

// What is wrong with one rank's node list. Every rank validates its list and the results are
// combined before any Vec is created, so an invalid list on one rank makes every rank
// return an error instead of leaving the others waiting in a collective call.
enum class NodeListProblem { kNone, kOwnedCount, kTooLong, kOutOfRange, kNotContiguous };

struct NodeListCheck {
  NodeListProblem problem = NodeListProblem::kNone;
  std::int64_t index = 0;     // the offending local node
  std::int64_t global = 0;    // its global id
  std::int64_t expected = 0;  // the owned id it should have (kNotContiguous)
};

NodeListCheck check_node_list(int num_owned_nodes, const std::vector<std::int64_t>& local_to_global,
                              std::int64_t num_global_nodes, std::int64_t owned_offset, PetscInt bs) {
  NodeListCheck check;
  const auto num_local = static_cast<std::int64_t>(local_to_global.size());
  if (num_owned_nodes < 0 || num_owned_nodes > num_local) {
    check.problem = NodeListProblem::kOwnedCount;
    return check;
  }
  if (num_local > PETSC_MAX_INT / bs) {
    check.problem = NodeListProblem::kTooLong;
    return check;
  }
  for (std::int64_t i = 0; i < num_local; ++i) {
    const std::int64_t global = local_to_global[static_cast<std::size_t>(i)];
    if (global < 0 || global >= num_global_nodes) {
      check = {NodeListProblem::kOutOfRange, i, global, 0};
      return check;
    }
    if (i < num_owned_nodes && global != owned_offset + i) {
      check = {NodeListProblem::kNotContiguous, i, global, owned_offset + i};
      return check;
    }
  }
  return check;
}

}  // namespace

PetscErrorCode GhostExchange::setup(const DistributedMesh& mesh, PetscInt bs) {
  PetscFunctionBeginUser;
  PetscCheck(mesh.comm != MPI_COMM_NULL, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
             "GhostExchange::setup: mesh.comm is MPI_COMM_NULL (the mesh was not distributed)");
  PetscCall(setup(mesh.comm, mesh.num_owned_nodes, mesh.local_to_global, mesh.num_global_nodes, bs));
  PetscFunctionReturn(0);
}

PetscErrorCode GhostExchange::setup(MPI_Comm comm, int num_owned_nodes,
                                    const std::vector<std::int64_t>& local_to_global, std::int64_t num_global_nodes,
                                    PetscInt bs) {
  PetscFunctionBeginUser;
  PetscCheck(comm != MPI_COMM_NULL, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
             "GhostExchange::setup: comm is MPI_COMM_NULL");
  PetscCheck(bs >= 1, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "GhostExchange::setup: block size %" PetscInt_FMT " must be at least 1", bs);
  PetscCheck(num_global_nodes >= 0 && num_global_nodes <= PETSC_MAX_INT / bs, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "GhostExchange::setup: %" PetscInt64_FMT " nodes x %" PetscInt_FMT
             " values do not fit PetscInt; configure PETSc with --with-64-bit-indices",
             static_cast<PetscInt64>(num_global_nodes), bs);

  int rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  std::int64_t owned = num_owned_nodes;
  std::int64_t owned_offset = 0;
  PetscCallMPI(MPI_Exscan(&owned, &owned_offset, 1, MPI_INT64_T, MPI_SUM, comm));
  if (rank == 0) owned_offset = 0;  // MPI_Exscan leaves rank 0's result undefined
  const NodeListCheck check = check_node_list(num_owned_nodes, local_to_global, num_global_nodes, owned_offset, bs);
  std::int64_t totals[2] = {check.problem == NodeListProblem::kNone ? 0 : 1, owned};
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, totals, 2, MPI_INT64_T, MPI_SUM, comm));
  PetscCheck(check.problem != NodeListProblem::kOwnedCount, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "GhostExchange::setup: %d owned nodes but %zu local nodes", num_owned_nodes, local_to_global.size());
  PetscCheck(check.problem != NodeListProblem::kTooLong, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "GhostExchange::setup: %zu local nodes x %" PetscInt_FMT " values do not fit PetscInt",
             local_to_global.size(), bs);
  PetscCheck(check.problem != NodeListProblem::kOutOfRange, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "GhostExchange::setup: local node %" PetscInt64_FMT " has global id %" PetscInt64_FMT
             ", outside [0, %" PetscInt64_FMT ")",
             static_cast<PetscInt64>(check.index), static_cast<PetscInt64>(check.global),
             static_cast<PetscInt64>(num_global_nodes));
  PetscCheck(check.problem != NodeListProblem::kNotContiguous, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
             "GhostExchange::setup: owned local node %" PetscInt64_FMT " has global id %" PetscInt64_FMT
             ", expected %" PetscInt64_FMT
             " (owned nodes must be the rank's contiguous range, after the lower ranks' ones)",
             static_cast<PetscInt64>(check.index), static_cast<PetscInt64>(check.global),
             static_cast<PetscInt64>(check.expected));
  PetscCheck(totals[0] == 0, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
             "GhostExchange::setup: the node lists of %" PetscInt64_FMT " rank(s) are invalid",
             static_cast<PetscInt64>(totals[0]));
  PetscCheck(totals[1] == num_global_nodes, comm, PETSC_ERR_ARG_SIZ,
             "GhostExchange::setup: the ranks own %" PetscInt64_FMT " nodes in all, not %" PetscInt64_FMT,
             static_cast<PetscInt64>(totals[1]), static_cast<PetscInt64>(num_global_nodes));

  PetscCall(VecScatterDestroy(&scatter_));
  comm_ = comm;
  bs_ = bs;
  num_owned_nodes_ = num_owned_nodes;
  num_local_nodes_ = static_cast<PetscInt>(local_to_global.size());
  num_global_nodes_ = static_cast<PetscInt>(num_global_nodes);

  Vec global = nullptr;
  Vec local = nullptr;
  PetscCall(create_global_vec(&global));
  // The local Vec follows the family the options chose for the global one, so a CUDA or
  // Kokkos run scatters between device Vecs without host copies.
  VecType global_type = nullptr;
  PetscCall(VecGetType(global, &global_type));
  PetscBool is_mpi = PETSC_FALSE;
  PetscBool is_seq = PETSC_FALSE;
  PetscCall(PetscStrbeginswith(global_type, "mpi", &is_mpi));
  PetscCall(PetscStrbeginswith(global_type, "seq", &is_seq));
  PetscCheck(is_mpi || is_seq, comm_, PETSC_ERR_SUP,
             "GhostExchange::setup: no sequential counterpart known for Vec type %s "
             "(expected mpi* or seq*)",
             global_type);
  local_vec_type_ = is_mpi ? "seq" + std::string(global_type + 3) : std::string(global_type);
  PetscCall(create_local_vec(&local));

  std::vector<PetscInt> global_blocks(local_to_global.begin(), local_to_global.end());
  IS from = nullptr;
  PetscCall(ISCreateBlock(PETSC_COMM_SELF, bs, num_local_nodes_, global_blocks.data(), PETSC_COPY_VALUES, &from));
  PetscCall(VecScatterCreate(global, from, local, nullptr, &scatter_));
  PetscCall(ISDestroy(&from));
  PetscCall(VecDestroy(&local));
  PetscCall(VecDestroy(&global));
  PetscFunctionReturn(0);
}

PetscErrorCode GhostExchange::share(const GhostExchange& other) {
  PetscFunctionBeginUser;
  PetscCheck(other.scatter_, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONGSTATE,
             "GhostExchange::share: the other exchange is not set up");
  if (&other == this) PetscFunctionReturn(0);
  PetscCall(PetscObjectReference(reinterpret_cast<PetscObject>(other.scatter_)));
  PetscCall(VecScatterDestroy(&scatter_));
  scatter_ = other.scatter_;
  comm_ = other.comm_;
  bs_ = other.bs_;
  num_owned_nodes_ = other.num_owned_nodes_;
  num_local_nodes_ = other.num_local_nodes_;
  num_global_nodes_ = other.num_global_nodes_;
  local_vec_type_ = other.local_vec_type_;
  PetscFunctionReturn(0);
}

PetscErrorCode GhostExchange::create_global_vec(Vec* v) const {
  PetscFunctionBeginUser;
  PetscCheck(bs_ >= 1, PETSC_COMM_SELF, PETSC_ERR_ORDER, "GhostExchange::create_global_vec: call setup() first");
  PetscCall(VecCreate(comm_, v));
  PetscCall(VecSetSizes(*v, bs_ * num_owned_nodes_, bs_ * num_global_nodes_));
  PetscCall(VecSetBlockSize(*v, bs_));
  PetscCall(VecSetFromOptions(*v));
  PetscFunctionReturn(0);
}

PetscErrorCode GhostExchange::create_local_vec(Vec* v) const {
  PetscFunctionBeginUser;
  PetscCheck(!local_vec_type_.empty(), PETSC_COMM_SELF, PETSC_ERR_ORDER,
             "GhostExchange::create_local_vec: call setup() first");
  PetscCall(VecCreate(PETSC_COMM_SELF, v));
  PetscCall(VecSetSizes(*v, bs_ * num_local_nodes_, bs_ * num_local_nodes_));
  PetscCall(VecSetBlockSize(*v, bs_));
  PetscCall(VecSetType(*v, local_vec_type_.c_str()));
  PetscFunctionReturn(0);
}

PetscErrorCode GhostExchange::check_sizes(Vec global, Vec local) const {
  PetscFunctionBeginUser;
  PetscCheck(scatter_ != nullptr, PETSC_COMM_SELF, PETSC_ERR_ORDER,
             "GhostExchange: call setup() before exchanging values");
  PetscInt global_rows = 0;
  PetscInt local_size = 0;
  PetscCall(VecGetLocalSize(global, &global_rows));
  PetscCall(VecGetSize(local, &local_size));
  PetscCheck(global_rows == bs_ * num_owned_nodes_, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ,
             "GhostExchange: global Vec has %" PetscInt_FMT " local rows, expected %" PetscInt_FMT " (%" PetscInt_FMT
             " owned nodes x %" PetscInt_FMT ")",
             global_rows, bs_ * num_owned_nodes_, num_owned_nodes_, bs_);
  PetscCheck(local_size == bs_ * num_local_nodes_, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ,
             "GhostExchange: local Vec has %" PetscInt_FMT " entries, expected %" PetscInt_FMT " (%" PetscInt_FMT
             " local nodes x %" PetscInt_FMT ")",
             local_size, bs_ * num_local_nodes_, num_local_nodes_, bs_);
  PetscFunctionReturn(0);
}

PetscErrorCode GhostExchange::to_local(Vec global, Vec local) const {
  PetscFunctionBeginUser;
  PetscCall(check_sizes(global, local));
  PetscCall(VecScatterBegin(scatter_, global, local, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(scatter_, global, local, INSERT_VALUES, SCATTER_FORWARD));
  PetscFunctionReturn(0);
}

PetscErrorCode GhostExchange::add_to_global(Vec local, Vec global) const {
  PetscFunctionBeginUser;
  PetscCall(check_sizes(global, local));
  PetscCall(VecScatterBegin(scatter_, local, global, ADD_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(scatter_, local, global, ADD_VALUES, SCATTER_REVERSE));
  PetscFunctionReturn(0);
}

}  // namespace dipc
