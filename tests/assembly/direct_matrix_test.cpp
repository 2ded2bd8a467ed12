// DirectMatrix against PETSc's COO path on the same entries: every rank gives entries of its own
// rows and of other ranks' rows (some pairs given by several ranks, some rows' diagonals only by
// another rank), with small integer values so that every sum is exact whatever its order. The
// two matrices must hold the same pattern and values, after a second assembly too, and a
// preconditioner must see the new values (the matrix's state moves). The device hypre matrix is
// checked the same way where a GPU and a device hypre are present (the GPU build's
// direct_matrix_gpu_tests), else skipped.
#include <gtest/gtest.h>
#include <petsc/private/petscimpl.h>  // PetscObjectStateGet: the state preconditioners compare
#include <petscksp.h>

#include <algorithm>
#include <cstdlib>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "assembly/direct_matrix.hpp"
#include "assembly/reserved_blocks.hpp"
#include "device/device_runtime.hpp"
#include "threads/host_threads.hpp"

namespace dipc {
namespace {

constexpr PetscInt kRowsPerRank = 60;

struct Entries {
  std::vector<PetscInt> rows, cols;
};

// Entries of a banded pattern around each row plus scattered ones, rows of every rank; rank r
// repeats part of rank r-1's choice so that owners receive the same pair from several ranks.
Entries make_entries(int rank, int size) {
  const PetscInt n = kRowsPerRank * size;
  std::set<std::pair<PetscInt, PetscInt>> pairs;
  for (int source : {rank, rank - 1}) {
    if (source < 0) continue;
    std::mt19937 rng(1000 + source);
    std::uniform_int_distribution<PetscInt> any(0, n - 1), band(-4, 4);
    for (int k = 0; k < 400; ++k) {
      const PetscInt r = source == rank ? any(rng) : any(rng);
      const PetscInt c = std::clamp<PetscInt>(r + band(rng), 0, n - 1);
      if (source == rank || k % 3 == 0) pairs.insert({r, c});
      if (source == rank && k % 7 == 0) pairs.insert({r, any(rng)});
    }
  }
  // Every owned diagonal somewhere: most by the owner, those of every fifth row by the next rank.
  for (PetscInt r = 0; r < n; ++r) {
    const int owner = static_cast<int>(r / kRowsPerRank);
    const bool by_next = r % 5 == 0 && size > 1;
    if ((!by_next && owner == rank) || (by_next && (owner + 1) % size == rank)) pairs.insert({r, r});
  }
  Entries e;
  for (const auto& [r, c] : pairs) e.rows.push_back(r), e.cols.push_back(c);
  // Not sorted: shuffled.
  std::mt19937 shuffle(7 + rank);
  std::vector<std::size_t> order(e.rows.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::shuffle(order.begin(), order.end(), shuffle);
  Entries out;
  for (std::size_t k : order) out.rows.push_back(e.rows[k]), out.cols.push_back(e.cols[k]);
  return out;
}

// Node blocks as the element forms give them, then a list. A chain of hexes along x, four nodes
// per cross-section and five sections per rank (its 60 rows); rank r takes the elements on its
// sections and the one joining them to the next rank's, so that ghost block rows go to their
// owners and rows made of blocks alone have off-diagonal columns; an even rank also takes the
// element joining it to its left neighbour, so that (from 3 ranks) some blocks come from two
// ranks. Even elements are elastic (full blocks), odd ones consistent mass (diagonal blocks
// only), so that some blocks are partial. The list pairs nodes two or more sections apart (in
// no block), in own rows and in the next rank's. The reserve (as contact pairs give it) holds
// node pairs sections apart, in own rows and the next rank's, pairs of an odd element's two
// sections (whose mass blocks hold only the diagonals: the reserve holds the rest, the same
// node pair in both lists) and pairs the elements hold whole (no reserve).
struct BlockCase {
  std::vector<std::int32_t> elastic_nodes, mass_nodes;
  std::vector<std::int64_t> local_to_global;
  NodeBlockReduction blocks;
  Entries extra;
  ReservedBlocks reserve;
  Entries all;  // the blocks' entries in their order, the list, the reserve's: what create() numbers
};

BlockCase make_block_case(int rank, int size, bool with_reserve) {
  constexpr int kSections = kRowsPerRank / 12;
  const int sections = kSections * size, first = std::max(0, kSections * rank - (rank % 2 == 0 ? 1 : 0));
  const int last = std::min(sections - 1, kSections * (rank + 1));  // elements [first, last)
  BlockCase c;
  for (std::int64_t g = 4 * first; g < 4 * (last + 1); ++g) c.local_to_global.push_back(g);
  for (int e = first; e < last; ++e) {
    auto& nodes = e % 2 == 0 ? c.elastic_nodes : c.mass_nodes;
    for (int a = 0; a < 8; ++a) nodes.push_back(4 * (e - first + a / 4) + a % 4);
  }
  const int num_elastic = static_cast<int>(c.elastic_nodes.size() / 8);
  const int num_mass = static_cast<int>(c.mass_nodes.size() / 8);
  c.blocks = NodeBlockReduction::build(
      {{{num_elastic, c.elastic_nodes.data(), c.local_to_global.data(), ElementLayout::elastic}, 0},
       {{num_mass, c.mass_nodes.data(), c.local_to_global.data(), ElementLayout::consistent_mass}, 0}},
      4 * kSections * rank, 4 * kSections * (rank + 1));
  const std::int64_t nodes = 4 * sections;
  for (std::int64_t n = 4 * kSections * rank; n < 4 * kSections * (rank + 2) && n < nodes; n += 3) {
    const std::int64_t m = (n + 13) % nodes;
    if (std::abs(n / 4 - m / 4) < 2) continue;
    c.extra.rows.push_back(static_cast<PetscInt>(3 * n + 1));
    c.extra.cols.push_back(static_cast<PetscInt>(3 * m + 2));
  }
  if (with_reserve) {
    std::vector<ReservedBlocks::NodePair> pairs;
    const std::int64_t own = 4 * kSections * rank;
    for (std::int64_t n = own; n < own + 8 * kSections && n < nodes; n += 2) {
      const std::int64_t m = (n + 9) % nodes;
      if (std::abs(n / 4 - m / 4) >= 2) pairs.push_back({n, m}), pairs.push_back({m, n});
      pairs.push_back({n, n});  // held whole by the elements
    }
    for (int e = first; e < last; ++e)  // odd elements: mass blocks between two sections
      if (e % 2 == 1)
        for (int a = 0; a < 4; ++a) pairs.push_back({4 * e + a, 4 * (e + 1) + (a + 1) % 4});
    std::set<std::pair<PetscInt, PetscInt>> listed;
    for (std::size_t v = 0; v < c.extra.rows.size(); ++v) listed.insert({c.extra.rows[v], c.extra.cols[v]});
    c.reserve.build(
        pairs, c.blocks,
        [&](PetscInt row, PetscInt col) {
          return listed.count({row, col}) > 0;
        },
        c.blocks.num_entries() + c.extra.rows.size());
    if (device::device_count() > 0) c.reserve.upload();
  }
  c.blocks.entries(&c.all.rows, &c.all.cols);
  c.all.rows.insert(c.all.rows.end(), c.extra.rows.begin(), c.extra.rows.end());
  c.all.cols.insert(c.all.cols.end(), c.extra.cols.begin(), c.extra.cols.end());
  c.reserve.entries(&c.all.rows, &c.all.cols);
  return c;
}

std::vector<double> make_values(const Entries& e, int rank, int round) {
  std::vector<double> v(e.rows.size());
  for (std::size_t k = 0; k < v.size(); ++k)
    v[k] = static_cast<double>((e.rows[k] * 7 + e.cols[k] * 3 + rank * 11 + round * 5) % 17 + 1);
  return v;
}

Mat template_matrix(MatType type) {
  Mat J;
  PetscCallAbort(PETSC_COMM_WORLD, MatCreate(PETSC_COMM_WORLD, &J));
  PetscCallAbort(PETSC_COMM_WORLD, MatSetSizes(J, kRowsPerRank, kRowsPerRank, PETSC_DETERMINE, PETSC_DETERMINE));
  PetscCallAbort(PETSC_COMM_WORLD, MatSetBlockSize(J, 3));
  PetscCallAbort(PETSC_COMM_WORLD, MatSetType(J, type));
  return J;
}

// The difference of the two matrices' products with a vector of distinct entries, and their
// numbers of nonzeros (global).
void compare(Mat direct, Mat coo, double* difference, PetscInt* nnz_direct, PetscInt* nnz_coo) {
  Vec x, y, z;
  PetscCallAbort(PETSC_COMM_WORLD, MatCreateVecs(coo, &x, &y));
  PetscCallAbort(PETSC_COMM_WORLD, VecDuplicate(y, &z));
  PetscInt lo, hi;
  PetscCallAbort(PETSC_COMM_WORLD, VecGetOwnershipRange(x, &lo, &hi));
  for (PetscInt i = lo; i < hi; ++i)
    PetscCallAbort(PETSC_COMM_WORLD, VecSetValue(x, i, 1.0 + (i % 13) * 0.125, INSERT_VALUES));
  PetscCallAbort(PETSC_COMM_WORLD, VecAssemblyBegin(x));
  PetscCallAbort(PETSC_COMM_WORLD, VecAssemblyEnd(x));
  Vec xd, zd;
  PetscCallAbort(PETSC_COMM_WORLD, MatCreateVecs(direct, &xd, &zd));
  PetscCallAbort(PETSC_COMM_WORLD, VecCopy(x, xd));
  PetscCallAbort(PETSC_COMM_WORLD, MatMult(direct, xd, zd));
  PetscCallAbort(PETSC_COMM_WORLD, VecCopy(zd, z));
  PetscCallAbort(PETSC_COMM_WORLD, MatMult(coo, x, y));
  PetscCallAbort(PETSC_COMM_WORLD, VecAXPY(z, -1.0, y));
  PetscReal norm;
  PetscCallAbort(PETSC_COMM_WORLD, VecNorm(z, NORM_INFINITY, &norm));
  *difference = norm;
  MatInfo info;
  PetscCallAbort(PETSC_COMM_WORLD, MatGetInfo(coo, MAT_GLOBAL_SUM, &info));
  *nnz_coo = static_cast<PetscInt>(info.nz_used);
  PetscBool hypre;
  PetscCallAbort(PETSC_COMM_WORLD, PetscObjectTypeCompare(reinterpret_cast<PetscObject>(direct), MATHYPRE, &hypre));
  *nnz_direct = *nnz_coo;
  if (!hypre) {
    PetscCallAbort(PETSC_COMM_WORLD, MatGetInfo(direct, MAT_GLOBAL_SUM, &info));
    *nnz_direct = static_cast<PetscInt>(info.nz_used);
  }
  for (Vec* v : {&x, &y, &z, &xd, &zd}) PetscCallAbort(PETSC_COMM_WORLD, VecDestroy(v));
}

// threads > 1: the pattern is built on that many host threads, in chunks of a few rows.
void check_against_coo(MatType type, DirectMatrix::Kind kind, bool values_on_device, bool node_blocks = false,
                       int threads = 1, bool with_reserve = false) {
  struct Threads {  // restores the default, one thread, whatever the test's outcome
    explicit Threads(int n) { set_host_threads(n, n > 1 ? 1 : 0); }
    ~Threads() { set_host_threads(1); }
  } use(threads);
  int rank, size;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  const BlockCase blocks = node_blocks ? make_block_case(rank, size, with_reserve) : BlockCase{};
  if (with_reserve) {
    ASSERT_GT(blocks.reserve.num_entries(), 0u);
  }
  const Entries e = node_blocks ? blocks.all : make_entries(rank, size);
  Mat coo = template_matrix(MATAIJ);
  Entries copy = e;  // PETSc may reorder the lists it is given
  PetscCallAbort(PETSC_COMM_WORLD, MatSetPreallocationCOO(coo, static_cast<PetscCount>(copy.rows.size()),
                                                          copy.rows.data(), copy.cols.data()));
  Mat like = template_matrix(type);
  ASSERT_EQ(DirectMatrix::kind_of(like), kind);
  DirectMatrix direct;
  Mat J;
  if (node_blocks)
    PetscCallAbort(PETSC_COMM_WORLD,
                   direct.create(like, kind, &blocks.blocks, &blocks.reserve, blocks.extra.rows.data(),
                                 blocks.extra.cols.data(), blocks.extra.rows.size(), &J));
  else
    PetscCallAbort(PETSC_COMM_WORLD, direct.create(like, kind, e.rows.data(), e.cols.data(), e.rows.size(), &J));
  PetscCallAbort(PETSC_COMM_WORLD, MatDestroy(&like));
  PetscInt bs;
  PetscCallAbort(PETSC_COMM_WORLD, MatGetBlockSize(J, &bs));
  EXPECT_EQ(bs, 3);
  device::Array<double> d_values("test values");
  PetscObjectState before, after;
  PetscCallAbort(PETSC_COMM_WORLD, PetscObjectStateGet(reinterpret_cast<PetscObject>(J), &before));
  for (int round = 0; round < 2; ++round) {
    const std::vector<double> v = make_values(e, rank, round);
    PetscCallAbort(PETSC_COMM_WORLD, MatSetValuesCOO(coo, v.data(), INSERT_VALUES));
    if (values_on_device) {
      d_values.upload(v);
      PetscCallAbort(PETSC_COMM_WORLD, direct.set_values(J, d_values.data()));
    } else {
      PetscCallAbort(PETSC_COMM_WORLD, direct.set_values(J, v.data()));
    }
    double difference;
    PetscInt nnz_direct, nnz_coo;
    compare(J, coo, &difference, &nnz_direct, &nnz_coo);
    EXPECT_EQ(difference, 0.0) << "round " << round;
    EXPECT_EQ(nnz_direct, nnz_coo);
  }
  PetscCallAbort(PETSC_COMM_WORLD, PetscObjectStateGet(reinterpret_cast<PetscObject>(J), &after));
  EXPECT_GT(after, before) << "a preconditioner would not see the new values";
  PetscCallAbort(PETSC_COMM_WORLD, MatDestroy(&J));
  PetscCallAbort(PETSC_COMM_WORLD, MatDestroy(&coo));
}

TEST(DirectMatrix, HostAijEqualsCooMatrix) { check_against_coo(MATAIJ, DirectMatrix::Kind::host_aij, false); }

// Node blocks, read in place for own rows and expanded for ghost rows, beside a list.
TEST(DirectMatrix, NodeBlocksEqualCooMatrix) { check_against_coo(MATAIJ, DirectMatrix::Kind::host_aij, false, true); }

// The rows in chunks on 3 host threads: the same matrix (rows of blocks alone, rows with list
// entries and received ones fall in different chunks).
TEST(DirectMatrix, NodeBlocksOnThreadsEqualCooMatrix) {
  check_against_coo(MATAIJ, DirectMatrix::Kind::host_aij, false, true, 3);
}

// A reserve beside the node blocks and the list (HessianAssembler's contact entries): its blocks
// merged into the block rows, sent for other ranks' rows, completing partial element blocks.
TEST(DirectMatrix, ReserveEqualsCooMatrix) {
  check_against_coo(MATAIJ, DirectMatrix::Kind::host_aij, false, true, 1, true);
  check_against_coo(MATAIJ, DirectMatrix::Kind::host_aij, false, true, 3, true);
}

TEST(DirectMatrix, ListOnThreadsEqualsCooMatrix) {
  check_against_coo(MATMPIAIJ, DirectMatrix::Kind::host_aij, false, false, 3);
}

TEST(DirectMatrix, MpiAijOnAnyRankCountEqualsCooMatrix) {
  check_against_coo(MATMPIAIJ, DirectMatrix::Kind::host_aij, false);
}

// An older matrix keeps working (its arrays are its own) after a newer one is made, as when
// Newton replaces the matrix on a new contact pattern before destroying the old one.
TEST(DirectMatrix, OlderMatrixOutlivesTheNextCreate) {
  int rank, size;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  const Entries e = make_entries(rank, size);
  DirectMatrix direct;
  Mat like = template_matrix(MATAIJ), first, second;
  PetscCallAbort(PETSC_COMM_WORLD, direct.create(like, DirectMatrix::Kind::host_aij, e.rows.data(), e.cols.data(),
                                                 e.rows.size(), &first));
  const std::vector<double> v = make_values(e, rank, 0);
  PetscCallAbort(PETSC_COMM_WORLD, direct.set_values(first, v.data()));
  PetscCallAbort(PETSC_COMM_WORLD, direct.create(like, DirectMatrix::Kind::host_aij, e.rows.data(), e.cols.data(),
                                                 e.rows.size(), &second));
  PetscCallAbort(PETSC_COMM_WORLD, direct.set_values(second, v.data()));
  double difference;
  PetscInt a, b;
  compare(first, second, &difference, &a, &b);
  EXPECT_EQ(difference, 0.0);
  for (Mat* m : {&like, &first, &second}) PetscCallAbort(PETSC_COMM_WORLD, MatDestroy(m));
}

TEST(DirectMatrix, DeviceHypreEqualsCooMatrix) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  if (!PetscDefined(HAVE_HYPRE_DEVICE)) GTEST_SKIP() << "this PETSc's hypre does not run on the GPU";
  check_against_coo(MATHYPRE, DirectMatrix::Kind::device_hypre, true);
}

TEST(DirectMatrix, DeviceHypreNodeBlocksEqualCooMatrix) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  if (!PetscDefined(HAVE_HYPRE_DEVICE)) GTEST_SKIP() << "this PETSc's hypre does not run on the GPU";
  check_against_coo(MATHYPRE, DirectMatrix::Kind::device_hypre, true, true);
}

TEST(DirectMatrix, DeviceHypreNodeBlocksOnThreadsEqualCooMatrix) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  if (!PetscDefined(HAVE_HYPRE_DEVICE)) GTEST_SKIP() << "this PETSc's hypre does not run on the GPU";
  check_against_coo(MATHYPRE, DirectMatrix::Kind::device_hypre, true, true, 3);
}

TEST(DirectMatrix, DeviceHypreReserveEqualsCooMatrix) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  if (!PetscDefined(HAVE_HYPRE_DEVICE)) GTEST_SKIP() << "this PETSc's hypre does not run on the GPU";
  check_against_coo(MATHYPRE, DirectMatrix::Kind::device_hypre, true, true, 1, true);
  check_against_coo(MATHYPRE, DirectMatrix::Kind::device_hypre, true, true, 3, true);
}

}  // namespace
}  // namespace dipc
