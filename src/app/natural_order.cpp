// NaturalOrder: partition order <-> blocks of the input numbering (see natural_order.hpp).
#include "app/natural_order.hpp"

#include <algorithm>

namespace dipc {

namespace {

// Rank r's block of `total` rows split over `size` ranks: the first total % size ranks take one
// row more.
void block_of(std::int64_t total, int rank, int size, std::int64_t* offset, int* count) {
  const std::int64_t base = total / size, extra = total % size;
  *count = static_cast<int>(base + (rank < extra ? 1 : 0));
  *offset = rank * base + std::min<std::int64_t>(rank, extra);
}

}  // namespace

NaturalOrder::~NaturalOrder() {
  VecScatterDestroy(&node_scatter_);
  VecScatterDestroy(&element_scatter_);
  VecDestroy(&owned_nodes_);
  VecDestroy(&block_nodes_);
  VecDestroy(&local_elements_);
  VecDestroy(&block_elements_);
}

PetscErrorCode NaturalOrder::setup(const DistributedMesh& mesh) {
  PetscFunctionBeginUser;
  int rank, size;
  MPI_Comm_rank(mesh.comm, &rank);
  MPI_Comm_size(mesh.comm, &size);
  block_of(mesh.num_global_nodes, rank, size, &node_offset_, &num_nodes_);
  block_of(mesh.num_global_elements, rank, size, &element_offset_, &num_elements_);
  PetscCall(VecCreateMPI(mesh.comm, 3 * mesh.num_owned_nodes, PETSC_DETERMINE, &owned_nodes_));
  PetscCall(VecCreateMPI(mesh.comm, 3 * num_nodes_, PETSC_DETERMINE, &block_nodes_));
  PetscCall(VecCreateMPI(mesh.comm, mesh.num_elements(), PETSC_DETERMINE, &local_elements_));
  PetscCall(VecCreateMPI(mesh.comm, num_elements_, PETSC_DETERMINE, &block_elements_));
  // Owned entry i goes to input row node_input_id[i] (3 entries a node: a block index set).
  std::vector<PetscInt> ids(mesh.node_input_id.begin(), mesh.node_input_id.begin() + mesh.num_owned_nodes);
  IS to;
  PetscCall(ISCreateBlock(mesh.comm, 3, static_cast<PetscInt>(ids.size()), ids.data(), PETSC_COPY_VALUES, &to));
  PetscCall(VecScatterCreate(owned_nodes_, nullptr, block_nodes_, to, &node_scatter_));
  PetscCall(ISDestroy(&to));
  std::vector<PetscInt> elements(mesh.element_input_id.begin(), mesh.element_input_id.end());
  PetscCall(
      ISCreateGeneral(mesh.comm, static_cast<PetscInt>(elements.size()), elements.data(), PETSC_COPY_VALUES, &to));
  PetscCall(VecScatterCreate(local_elements_, nullptr, block_elements_, to, &element_scatter_));
  PetscCall(ISDestroy(&to));
  PetscFunctionReturn(0);
}

PetscErrorCode NaturalOrder::scatter(VecScatter scatter, Vec from, Vec to, const double* in, std::size_t n_in,
                                     double* out, std::size_t n_out, ScatterMode mode) {
  PetscFunctionBeginUser;
  PetscScalar* a;
  PetscCall(VecGetArray(from, &a));
  std::copy(in, in + n_in, a);
  PetscCall(VecRestoreArray(from, &a));
  PetscCall(VecScatterBegin(scatter, from, to, INSERT_VALUES, mode));
  PetscCall(VecScatterEnd(scatter, from, to, INSERT_VALUES, mode));
  const PetscScalar* b;
  PetscCall(VecGetArrayRead(to, &b));
  std::copy(b, b + n_out, out);
  PetscCall(VecRestoreArrayRead(to, &b));
  PetscFunctionReturn(0);
}

PetscErrorCode NaturalOrder::nodes_to_blocks(const double* owned, std::vector<double>* block) {
  PetscFunctionBeginUser;
  PetscInt n_owned;
  PetscCall(VecGetLocalSize(owned_nodes_, &n_owned));
  block->resize(3 * static_cast<std::size_t>(num_nodes_));
  PetscCall(scatter(node_scatter_, owned_nodes_, block_nodes_, owned, n_owned, block->data(), block->size(),
                    SCATTER_FORWARD));
  PetscFunctionReturn(0);
}

PetscErrorCode NaturalOrder::nodes_from_blocks(const std::vector<double>& block, double* owned) {
  PetscFunctionBeginUser;
  PetscInt n_owned;
  PetscCall(VecGetLocalSize(owned_nodes_, &n_owned));
  PetscCall(
      scatter(node_scatter_, block_nodes_, owned_nodes_, block.data(), block.size(), owned, n_owned, SCATTER_REVERSE));
  PetscFunctionReturn(0);
}

PetscErrorCode NaturalOrder::elements_to_blocks(const double* local, std::vector<double>* block) {
  PetscFunctionBeginUser;
  PetscInt n_local;
  PetscCall(VecGetLocalSize(local_elements_, &n_local));
  block->resize(static_cast<std::size_t>(num_elements_));
  PetscCall(scatter(element_scatter_, local_elements_, block_elements_, local, n_local, block->data(), block->size(),
                    SCATTER_FORWARD));
  PetscFunctionReturn(0);
}

}  // namespace dipc
