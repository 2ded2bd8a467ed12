// ElementPattern: how an element form describes its Hessian pattern to the matrix assembler,
// as dense 8x8 node blocks per element rather than 576 scalar COO entries per hex
// (node_block_reduction.hpp builds the matrix's entries from it).
#pragma once
#include <cstdint>

#include "assembly/element_loops.hpp"

namespace dipc {

// The Hessian pattern of an element form as dense 8x8 node blocks per element (64 node pairs
// instead of 576 scalar entries): the element's 8 local node ids, the local-to-global node map,
// and where each entry's value lies among the element's values (ElementLayout).
struct ElementPattern {
  int num_elements = 0;
  const std::int32_t* nodes = nullptr;            // 8 local node ids per element
  const std::int64_t* local_to_global = nullptr;  // global node id of each local node
  ElementLayout layout = ElementLayout::elastic;
};

}  // namespace dipc
