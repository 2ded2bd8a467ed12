// NaturalOrder: moves node fields (3 values per owned node) and element fields (1 value per
// element) between the partition's numbering and the input mesh's numbering, split over the
// ranks in contiguous blocks (rank r holds input rows [offset, offset + count), counts as equal
// as they can be). Files written from these blocks (output, checkpoints) do not depend on the
// number of ranks or the partition, so a run on any rank count can read or continue them.
#pragma once
#include <petscvec.h>

#include <cstdint>
#include <vector>

#include "partition/distributed_mesh.hpp"

namespace dipc {

class NaturalOrder {
 public:
  NaturalOrder() = default;
  ~NaturalOrder();
  NaturalOrder(const NaturalOrder&) = delete;
  NaturalOrder& operator=(const NaturalOrder&) = delete;

  PetscErrorCode setup(const DistributedMesh& mesh);  // collective

  // This rank's block of the input numbering.
  std::int64_t node_offset() const { return node_offset_; }
  int num_nodes() const { return num_nodes_; }
  std::int64_t element_offset() const { return element_offset_; }
  int num_elements() const { return num_elements_; }

  // Collective. owned: 3 values per owned node (partition order) -> block: 3 per block node.
  PetscErrorCode nodes_to_blocks(const double* owned, std::vector<double>* block);
  // Collective, the reverse: block (3 per block node) -> owned (3 per owned node).
  PetscErrorCode nodes_from_blocks(const std::vector<double>& block, double* owned);
  // Collective. local: 1 value per local element -> block: 1 per block element.
  PetscErrorCode elements_to_blocks(const double* local, std::vector<double>* block);

 private:
  static PetscErrorCode scatter(VecScatter scatter, Vec from, Vec to, const double* in, std::size_t n_in, double* out,
                                std::size_t n_out, ScatterMode mode);

  std::int64_t node_offset_ = 0, element_offset_ = 0;
  int num_nodes_ = 0, num_elements_ = 0;
  Vec owned_nodes_ = nullptr, block_nodes_ = nullptr, local_elements_ = nullptr, block_elements_ = nullptr;
  VecScatter node_scatter_ = nullptr, element_scatter_ = nullptr;
};

}  // namespace dipc
