// HessianPattern: what the matrix assembler (hessian_assembler.hpp) asks of a term of the
// Hessian, and nothing else: its entries as a COO list or as element node blocks, the element
// forms' values chunk by chunk, and whether and when the pattern changes.
//
// Every Form is one (forms/form.hpp); the assembler sees only this interface, so that the
// matrix's code does not depend on what a form evaluates, and a term that is not a form could
// hand its entries to the matrix the same way.
#pragma once
#include <petscsys.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "assembly/element_pattern.hpp"

namespace dipc {

// A dense block of a term's Hessian over a few nodes (a contact or friction pair's body nodes):
// its raw values are the (3 count)^2 entries over (node a, component i) x (node b, component j),
// row-major, that is in the order (a, i, b, j).
struct NodeGroup {
  std::array<std::int64_t, 4> node{};  // global node ids, the first `count` used
  int count = 0;
};
// The raw values of a group of `count` nodes.
inline std::size_t node_group_values(int count) { return static_cast<std::size_t>(9 * count * count); }
// The groups' entries as a COO list (global dof ids 3 node + component), in their values' order.
inline void expand_node_groups(const std::vector<NodeGroup>& groups, std::vector<PetscInt>* rows,
                               std::vector<PetscInt>* cols) {
  rows->clear(), cols->clear();
  for (const NodeGroup& g : groups)
    for (int a = 0; a < g.count; ++a)
      for (int i = 0; i < 3; ++i)
        for (int b = 0; b < g.count; ++b)
          for (int j = 0; j < 3; ++j) {
            rows->push_back(static_cast<PetscInt>(3 * g.node[a] + i));
            cols->push_back(static_cast<PetscInt>(3 * g.node[b] + j));
          }
}

class HessianPattern {
 public:
  virtual ~HessianPattern() = default;

  // Global dof indices of this term's Hessian entries, fixed for the life of the pattern (for
  // element forms the expansion of element_pattern(), which the assembler does not ask for).
  // The values are written in this order (Form::hessian). By default the expansion of
  // node_groups(); a term that gives none must override it.
  virtual void coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) {
    std::vector<NodeGroup> groups;
    if (!node_groups(&groups)) throw std::logic_error("a Hessian term gives neither a COO pattern nor node groups");
    expand_node_groups(groups, rows, cols);
  }
  // Element forms (elastic, consistent inertia) also describe their pattern as node blocks and
  // return true: the assembler then builds the matrix from the blocks and never expands
  // coo_pattern() (576 entries per hex, the bulk of the setup's time and memory). Such a
  // pattern must not change (pattern_may_change() false).
  virtual bool element_pattern(ElementPattern* pattern) const { return false; }
  // Element forms: the values of elements [first, first + count) only, as hessian() writes
  // them from element `first` on, so that the matrix sums them chunk by chunk and no array of
  // every element's values (576 per hex) exists. x and values are in the form's memory space
  // (host or device). Returns false if x is not admissible (as Form::value). A form that
  // returns true from element_pattern() must implement it.
  virtual bool element_hessian(const double* x, int first, int count, double* values) { return false; }

  // Called before every Hessian evaluation at x (a host array; x_device the same values on the
  // device where the caller has them there, else nullptr), before pattern_version() is read: a
  // term whose pattern depends on the state (the contact active set) updates it here, on the
  // device where it evaluates there.
  virtual void update_pattern(const double* x, const double* x_device) {}
  // Increases whenever coo_pattern() would return a different pattern.
  virtual long pattern_version() const { return 0; }
  // True for terms whose pattern can change after setup (contact's active set, friction's
  // lagged pairs): without any, the potential never looks for pattern changes, and the matrix
  // made at setup is the only one.
  virtual bool pattern_may_change() const { return false; }
  // Terms whose pattern may change give it as node groups, in coo_pattern()'s order (which is
  // then expand_node_groups() of them), and return true. The assembler maps a changed pattern
  // onto the matrix block by block (16 node blocks per contact pair instead of 144 scalar
  // entries), and never asks such a term for coo_pattern().
  virtual bool node_groups(std::vector<NodeGroup>* groups) const { return false; }
  // Terms whose pattern may change: node blocks, as (global row node, global column node), for
  // which the matrix keeps entries beyond coo_pattern()'s, so that the pattern can change
  // within them without a new matrix (reserved_blocks.hpp). Contact gives its candidate pairs'
  // blocks; repeats are allowed. Asked when the assembler makes a matrix.
  virtual void reserved_blocks(std::vector<std::array<std::int64_t, 2>>* blocks) const {}
};

}  // namespace dipc
