// GhostExchange: halo exchange of nodal fields (bs values per node) between the distributed
// PETSc Vec in partition order (bs * num_owned_nodes rows per rank) and a rank's sequential
// local Vec over its local nodes (owned first, then ghosts; see DistributedMesh), or over
// any longer local node list whose first entries are the rank's owned nodes.
#pragma once
#include <petscvec.h>

#include <cstdint>
#include <string>
#include <vector>

#include "partition/distributed_mesh.hpp"

namespace dipc {

class GhostExchange {
 public:
  GhostExchange() = default;
  ~GhostExchange();  // destroys the VecScatter
  GhostExchange(const GhostExchange&) = delete;
  GhostExchange& operator=(const GhostExchange&) = delete;

  // Builds the scatter for `mesh` with `bs` values per node (collective on mesh.comm).
  // Calling it again replaces the previous scatter. Same as the overload below with the
  // mesh's communicator, owned-node count, local-to-global map and global node count.
  PetscErrorCode setup(const DistributedMesh& mesh, PetscInt bs);

  // Builds the scatter for any local node list (collective on `comm`): the first
  // `num_owned_nodes` entries of `local_to_global` are this rank's owned nodes, which must be
  // its contiguous range of the global numbering (global ids offset, offset + 1, ... where
  // offset is the owned-node count of the lower ranks); every further entry is any global
  // node id in [0, num_global_nodes), so a caller can extend a mesh's local nodes with extra
  // ghosts (e.g. the nodes of another rank's contact primitives). An id listed twice gets
  // its value twice from to_local and adds both entries in add_to_global. Every rank
  // returns an error when any rank's list is invalid or the owned counts do not sum to
  // num_global_nodes.
  PetscErrorCode setup(MPI_Comm comm, int num_owned_nodes, const std::vector<std::int64_t>& local_to_global,
                       std::int64_t num_global_nodes, PetscInt bs);

  // Uses `other`'s scatter (a reference: no second setup, whose index sorting and star forest
  // took 0.14 s per million nodes) for the same node list and block size; a later setup()
  // replaces it here only. `other` must be set up.
  PetscErrorCode share(const GhostExchange& other);

  // Distributed Vec on mesh.comm: bs * num_owned_nodes local rows, block size bs, type from
  // the options database (VecSetFromOptions, so -vec_type works).
  PetscErrorCode create_global_vec(Vec* v) const;
  // Sequential Vec of bs * num_local_nodes entries, block size bs, the sequential type of
  // the same family as the global Vec's type at setup() (mpi -> seq, mpicuda -> seqcuda...).
  PetscErrorCode create_local_vec(Vec* v) const;

  // local <- global at every local node, owned and ghost (INSERT_VALUES, forward scatter).
  PetscErrorCode to_local(Vec global, Vec local) const;
  // global += local summed over every rank holding a node: ghost contributions are added
  // into their owners (ADD_VALUES, reverse scatter). Does not zero `global` first.
  PetscErrorCode add_to_global(Vec local, Vec global) const;

  PetscInt block_size() const { return bs_; }

 private:
  PetscErrorCode check_sizes(Vec global, Vec local) const;

  MPI_Comm comm_ = MPI_COMM_NULL;
  PetscInt bs_ = 0;
  PetscInt num_owned_nodes_ = 0;
  PetscInt num_local_nodes_ = 0;
  PetscInt num_global_nodes_ = 0;
  std::string local_vec_type_;
  VecScatter scatter_ = nullptr;
};

}  // namespace dipc
