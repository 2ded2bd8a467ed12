// HessianAssembler: the Hessian as a distributed PETSc matrix, its pattern made from the terms'
// patterns (HessianPattern) and its values summed from the raw values the terms write.
//
// The matrix is made at setup and again when a term's pattern (the contact active set)
// changes, never per iteration otherwise. Its entries: the element forms' node blocks, the
// fixed COO terms' entries that no block holds, and those of the terms whose pattern changes
// (ReservedBlocks: their current pattern's blocks and, with -dipc_pattern_remap candidates,
// their candidate pairs'). Either way the changing terms' node blocks (16 per contact pair) are
// looked up among the matrix's (TargetPart: on the host threads, or on the device where the
// values are summed there, and their values then sorted by entry there). With -dipc_pattern_remap fit or
// candidates, a pattern that fits the matrix's entries only remaps those terms' values, keeping
// the matrix (the Newton solver still sets the preconditioner up afresh); fit is the default
// (docs/performance.md, "Two and four GPUs"), and a kept matrix does not outlive its time step
// (require_exact_pattern). The fixed part is made once (again only when the owned Dirichlet
// dofs change). The terms (the potential's forms) write their raw
// values into one array made of parts, each with its own reduction into the matrix's entries:
//   element part   the element forms' values (elastic, consistent mass), element by element in
//                  their layouts, first, so that their offsets stay put; summed into the
//                  distinct node blocks (ElementBlockPart, built once: their patterns never
//                  change, and are never expanded to 576 scalar entries per hex), the matrix's
//                  first entries; where the element forms run where the matrix is, they are
//                  computed and summed element chunk by chunk and the raw arrays leave them out;
//   fixed part     the COO terms whose pattern never changes (the lumped mass) in their order,
//                  then the owned Dirichlet diagonal (in the pattern only: the elimination sets
//                  its value); summed over their small lists (CooPart) onto the blocks, or onto
//                  entries of their own after the blocks';
//   changing part  the terms whose pattern changes (contact, friction), last, so that a new
//                  active set resizes only it; given as node groups (a pair's body nodes) and
//                  added value by value (TargetPart) onto the blocks, the fixed part's entries
//                  or the reserve, whose entries are found node block by node block.
// Entries after the blocks are zeroed before the parts add onto them; the Dirichlet
// elimination (DirichletElimination) then sets the prescribed rows and columns. PETSc is given
// only the distinct entries: through MatSetValuesCOO, or written straight into the matrix's
// arrays for the types DirectMatrix serves.
//
// Values are summed where the matrix lives: on the device for a device matrix
// (device_matrix.hpp) when device terms exist, else on the host. A term writes its raw values
// in its own memory space (values_for), and they cross to the other space once where needed.
#pragma once
#include <petscmat.h>

#include <cstdint>
#include <string>
#include <vector>

#include "assembly/block_entries.hpp"
#include "assembly/coo_part.hpp"
#include "assembly/direct_matrix.hpp"
#include "assembly/dirichlet_elimination.hpp"
#include "assembly/element_block_part.hpp"
#include "assembly/hessian_pattern.hpp"
#include "assembly/large_page_vector.hpp"
#include "assembly/reserved_blocks.hpp"
#include "assembly/target_part.hpp"
#include "device/device_runtime.hpp"
#include "device/memory_space.hpp"

namespace dipc {

class HessianAssembler {
 public:
  // A term of the Hessian: its pattern, the memory space it writes its values in, and its name
  // (for messages).
  // What a changed pattern does (-dipc_pattern_remap): off, a new matrix; fit, the matrix is
  // kept where the pattern fits its entries; candidates, as fit, with the terms' reserved_blocks()
  // in every new matrix.
  enum class Remap { off, fit, candidates };
  struct Term {
    HessianPattern* pattern = nullptr;
    MemorySpace space = MemorySpace::host;
    std::string name;
  };
  // The rank's dofs: it owns the nodes [node_offset, node_offset + num_owned_nodes). The
  // caller's local nodes' global ids and Dirichlet flags (3 per local node) are read at every
  // pattern rebuild (they grow when terms reach nodes of other ranks), so they must outlive
  // the assembler.
  struct Dofs {
    MPI_Comm comm = MPI_COMM_NULL;
    std::int64_t node_offset = 0;
    int num_owned_nodes = 0;
    const std::vector<std::int64_t>* local_to_global = nullptr;
    const std::vector<char>* prescribed = nullptr;
  };

  HessianAssembler() = default;
  HessianAssembler(const HessianAssembler&) = delete;
  HessianAssembler& operator=(const HessianAssembler&) = delete;

  // Reads -dipc_direct_matrix and -dipc_pattern_remap. The pattern is built by create_matrix().
  PetscErrorCode setup(const Dofs& dofs, std::vector<Term> terms);
  // A matrix with the combined pattern preallocated (type from -mat_type, default aij). The
  // assembler keeps a reference to re-preallocate it when a pattern changes.
  PetscErrorCode create_matrix(Mat* J);
  // The matrix of the last create_matrix(), or null after forget_matrix().
  Mat matrix() const { return J_; }
  // The caller replaces the matrix: the next create_matrix() rebuilds the pattern.
  void forget_matrix() { J_ = nullptr; }

  // Collective. Lets the terms fix their patterns at x (host array; x_device the same on the
  // device, or nullptr: HessianPattern::update_pattern). Where a pattern changed
  // and the matrix holds all its entries, the term's values are mapped onto them (unless
  // -dipc_pattern_remap is off); *new_matrix on every rank when a pattern changed and was not
  // mapped, and then rebuild_pattern() (or a new matrix) must follow before the next assembly.
  PetscErrorCode update_patterns(const double* x, const double* x_device, bool* new_matrix);
  // The next update_patterns() keeps the matrix only where its entries are exactly those it was
  // made with and no pattern changed since (no remap, no change), else asks for a new matrix. At
  // the start of a time step, so that a step's matrices depend on its state, not on the steps
  // before: a run restarted from a checkpoint then makes the same matrices as the run that went
  // on (with -dipc_pattern_remap fit a kept matrix holds the entries of pairs no longer active).
  void require_exact_pattern() { exact_next_ = true; }
  // Collective. The matrix in use takes the terms' current pattern (its handle stays).
  PetscErrorCode rebuild_pattern() { return rebuild_pattern(false); }

  // One assembly: begin_values(); per term either add_element_chunks() (where
  // sums_element_chunks()) or its values written into values_for() followed by
  // values_written(); then insert_values().
  PetscErrorCode begin_values();
  bool sums_element_chunks(std::size_t t) const { return elements_.chunked() && element_map_[t] >= 0; }
  // Element term t's values at x (host array), computed and summed chunk by chunk; false if
  // the term rejects x.
  bool add_element_chunks(std::size_t t, const double* x);
  // Where term t writes its raw values (coo_pattern() order), in its memory space.
  double* values_for(std::size_t t);
  // After term t wrote into values_for(t): its values go where the matrix sums them.
  void values_written(std::size_t t);
  // Collective. The raw values summed into the matrix's entries, eliminated, and set into it.
  PetscErrorCode insert_values();

  // Raw Hessian values per assembly (576 per hex for the elastic form), the Dirichlet diagonal
  // included.
  std::size_t num_raw_entries() const { return num_raw_entries_; }
  // The matrix's entries on this rank, and those of them reserved for changing patterns.
  std::size_t num_entries() const { return num_unique_; }
  std::size_t num_reserved_entries() const { return reserve_.num_entries(); }
  // Pattern changes that fitted the matrix (no new matrix), since setup.
  long remaps() const { return remaps_; }

 private:
  // template_matrix: J_ is create_matrix()'s unpreallocated matrix (a direct matrix replaces
  // it), else the matrix in use (a direct matrix takes over its contents).
  PetscErrorCode rebuild_pattern(bool template_matrix);
  // The element terms' node blocks and their place in the raw values (once).
  PetscErrorCode build_element_part();
  // The fixed COO terms' lists and the Dirichlet diagonal, their place in the raw values, and
  // the entries of theirs that no block holds (fixed_extra_rows_, fixed_extra_cols_).
  PetscErrorCode build_fixed_part();
  // The changing terms' node groups, their place in the raw values; their versions taken.
  PetscErrorCode gather_changing_part(std::vector<NodeGroup>* groups);
  // The reserve for the changing terms: their current groups' blocks, and reserved_blocks()'
  // with -dipc_pattern_remap candidates.
  void build_reserve(const std::vector<NodeGroup>& groups);
  // The changing part's values' place among the matrix's entries; *fits false where an entry
  // has none. A trial (the matrix kept if the pattern fits) stops at the first such entry.
  PetscErrorCode map_changing_part(const std::vector<NodeGroup>& groups, bool trial, bool* fits);
  // The raw value arrays sized for the parts, the maps on the device where values are summed there.
  void size_raw_values();
  // Where the matrix keeps a node block's entries: element blocks, reserve, fixed extras.
  BlockEntries block_entries() const;
  // The same on the device, for a device matrix whose parts are there (the reserve's only
  // with_reserve); false otherwise (the host looks the blocks up).
  bool device_entry_index(device::BlockEntryIndex* index, bool with_reserve) const;
  bool changing(std::size_t t) const { return terms_[t].pattern->pattern_may_change(); }
  // The matrix J_ from the entries: the blocks', the fixed part's extra ones, the reserve's.
  PetscErrorCode make_matrix(bool template_matrix);
  // The raw values summed into the matrix's entries, eliminated; returns them (device memory
  // for a device matrix).
  double* sum_values();
  // The raw arrays (host and device) leave the element part out when it is summed chunk by chunk.
  std::size_t raw_offset() const { return elements_.chunked() ? num_element_raw_ : 0; }
  bool pattern_changed() const;

  Dofs dofs_;
  std::vector<Term> terms_;
  std::vector<long> pattern_versions_;
  bool any_device_ = false;            // terms that write on the device
  bool direct_matrix_allowed_ = true;  // -dipc_direct_matrix, read at setup
  Remap remap_ = Remap::fit;           // -dipc_pattern_remap, read at setup
  Mat J_ = nullptr;                    // not owned
  bool device_matrix_ = false;         // values are summed on the device (device terms and matrix)
  // Each term's values in the raw array: start and count; element terms first.
  std::vector<std::size_t> term_begin_, term_size_;
  std::vector<int> element_map_;         // per term: its index among the node blocks' forms, or -1
  std::size_t num_element_raw_ = 0;      // raw values of the element part (the array's start)
  std::size_t dirichlet_raw_begin_ = 0;  // the Dirichlet diagonal's raw values
  std::size_t changing_raw_begin_ = 0;   // the changing part's raw values, to the end
  std::size_t num_raw_entries_ = 0;      // element, fixed (with the Dirichlet diagonal), changing part
  // The raw values on the host: only for a host matrix. With a device matrix the host keeps
  // neither these nor the maps (but the changing part's targets, whose array the next pattern
  // reuses), only the block of the largest host term (friction) in host_block_. d_values_
  // holds them wherever device terms exist. Both leave the element part out when it is summed
  // chunk by chunk (they then start at the COO part: raw_offset()).
  LargePageVector<PetscScalar> values_;
  std::vector<PetscScalar> host_block_;
  device::Array<double> d_values_{"Hessian COO values"};
  ElementBlockPart elements_;
  CooPart fixed_;
  bool fixed_built_ = false;            // fixed_ and fixed_extra_* hold the fixed part
  bool fixed_on_device_ = false;        // ... for a device matrix (its maps are on the device)
  std::vector<char> fixed_prescribed_;  // ... made with these owned Dirichlet flags
  TargetPart changing_;
  // The changing terms' node groups at the last pattern change, and one term's: kept, with
  // their capacity, from change to change (tens of MB on contact-rich steps, faulted in afresh
  // at every change otherwise).
  std::vector<NodeGroup> groups_, term_groups_;
  // The fixed part's entries that no block holds (entries from blocks.num_entries() on), by row
  // then column; the reserve's follow them.
  std::vector<PetscInt> fixed_extra_rows_, fixed_extra_cols_;
  device::Array<std::int64_t> d_extra_rows_{"fixed extra rows"}, d_extra_cols_{"fixed extra columns"};  // device matrix
  ReservedBlocks reserve_;
  long remaps_ = 0;
  bool awaiting_rebuild_ = false;  // update_patterns() asked for a new matrix, not yet made
  bool matrix_exact_ = true;       // no pattern remapped onto the matrix since it was made
  bool exact_next_ = false;        // require_exact_pattern() before the next update_patterns()
  DirichletElimination dirichlet_;
  std::size_t num_unique_ = 0;  // the matrix's entries on this rank
  LargePageVector<PetscScalar> unique_values_;
  device::Array<double> d_unique_values_{"Hessian unique COO values"};
  DirectMatrix direct_;  // the matrix made from the entries, unless direct_kind_ is coo
  DirectMatrix::Kind direct_kind_ = DirectMatrix::Kind::coo;
};

}  // namespace dipc
