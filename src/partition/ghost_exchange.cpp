// GhostExchange (see ghost_exchange.hpp): one VecScatter from the distributed Vec to the
// local Vec, built from a block index set whose block i is local node i's global node id;
// the forward scatter fills owned and ghost values, the reverse scatter with ADD_VALUES sums
// every rank's local contributions into the owners.
#include "partition/ghost_exchange.hpp"

#include <vector>

namespace dipc {

GhostExchange::~GhostExchange() {
  // A destructor cannot propagate an error code; destroying a valid scatter does not fail.
  (void)VecScatterDestroy(&scatter_);
}

PetscErrorCode GhostExchange::setup(const DistributedMesh& mesh, PetscInt bs) {
  PetscFunctionBeginUser;
  PetscCheck(mesh.comm != MPI_COMM_NULL, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
             "GhostExchange::setup: mesh.comm is MPI_COMM_NULL (the mesh was not distributed)");
  PetscCheck(bs >= 1, mesh.comm, PETSC_ERR_ARG_OUTOFRANGE,
             "GhostExchange::setup: block size %" PetscInt_FMT " must be at least 1", bs);
  PetscCheck(mesh.num_global_nodes <= PETSC_MAX_INT / bs, mesh.comm, PETSC_ERR_ARG_OUTOFRANGE,
             "GhostExchange::setup: %" PetscInt64_FMT " nodes x %" PetscInt_FMT
             " values exceed PetscInt; configure PETSc with --with-64-bit-indices",
             static_cast<PetscInt64>(mesh.num_global_nodes), bs);
  PetscCheck(mesh.num_owned_nodes <= mesh.num_local_nodes(), PETSC_COMM_SELF,
             PETSC_ERR_ARG_CORRUPT,
             "GhostExchange::setup: %d owned nodes but only %d local nodes", mesh.num_owned_nodes,
             mesh.num_local_nodes());
  PetscCall(VecScatterDestroy(&scatter_));
  comm_ = mesh.comm;
  bs_ = bs;
  num_owned_nodes_ = mesh.num_owned_nodes;
  num_local_nodes_ = mesh.num_local_nodes();
  num_global_nodes_ = static_cast<PetscInt>(mesh.num_global_nodes);

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

  std::vector<PetscInt> global_blocks(mesh.local_to_global.begin(), mesh.local_to_global.end());
  IS from = nullptr;
  PetscCall(ISCreateBlock(PETSC_COMM_SELF, bs, num_local_nodes_, global_blocks.data(),
                          PETSC_COPY_VALUES, &from));
  PetscCall(VecScatterCreate(global, from, local, nullptr, &scatter_));
  PetscCall(ISDestroy(&from));
  PetscCall(VecDestroy(&local));
  PetscCall(VecDestroy(&global));
  PetscFunctionReturn(0);
}

PetscErrorCode GhostExchange::create_global_vec(Vec* v) const {
  PetscFunctionBeginUser;
  PetscCheck(bs_ >= 1, PETSC_COMM_SELF, PETSC_ERR_ORDER,
             "GhostExchange::create_global_vec: call setup() first");
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
             "GhostExchange: global Vec has %" PetscInt_FMT " local rows, expected %" PetscInt_FMT
             " (%" PetscInt_FMT " owned nodes x %" PetscInt_FMT ")",
             global_rows, bs_ * num_owned_nodes_, num_owned_nodes_, bs_);
  PetscCheck(local_size == bs_ * num_local_nodes_, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ,
             "GhostExchange: local Vec has %" PetscInt_FMT " entries, expected %" PetscInt_FMT
             " (%" PetscInt_FMT " local nodes x %" PetscInt_FMT ")",
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
