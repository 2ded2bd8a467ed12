// main() for tests that run under mpiexec: initialises PETSc (and MPI), runs the GoogleTest
// suite on every rank, and fails on every rank if any rank failed. Only rank 0 prints the
// GoogleTest report, so the CTest log stays readable.
//
// PETSc's options database is one global: a test that sets options and then fails an ASSERT
// (or throws) before clearing them would change every later test. A listener puts the database
// back as it was before each test and each test suite, whatever happened in between.
#include <gtest/gtest.h>
#include <petscsys.h>

#include <string>
#include <vector>

namespace {

class RestorePetscOptions : public ::testing::EmptyTestEventListener {
 public:
  void OnTestSuiteStart(const ::testing::TestSuite&) override { save(); }
  void OnTestStart(const ::testing::TestInfo&) override { save(); }
  void OnTestEnd(const ::testing::TestInfo&) override { restore(); }
  void OnTestSuiteEnd(const ::testing::TestSuite&) override { restore(); }

 private:
  // A failing PETSc call here is a defect of PETSc's database, not of a test: abort.
  static std::string all_options() {
    char* all = nullptr;
    PetscCallAbort(PETSC_COMM_SELF, PetscOptionsGetAll(nullptr, &all));
    const std::string text = all ? all : "";
    PetscCallAbort(PETSC_COMM_SELF, PetscFree(all));
    return text;
  }
  void save() { saved_.push_back(all_options()); }
  void restore() {
    if (saved_.empty()) return;
    const std::string options = saved_.back();
    saved_.pop_back();
    if (options == all_options()) return;
    PetscCallAbort(PETSC_COMM_SELF, PetscOptionsClear(nullptr));
    PetscCallAbort(PETSC_COMM_SELF, PetscOptionsInsertString(nullptr, options.c_str()));
  }
  std::vector<std::string> saved_;
};

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
  if (rank != 0) delete listeners.Release(listeners.default_result_printer());
  listeners.Append(new RestorePetscOptions);
  int failed = RUN_ALL_TESTS() != 0 ? 1 : 0;
  int any_failed = 0;
  MPI_Allreduce(&failed, &any_failed, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  if (any_failed && rank == 0 && !failed) std::fprintf(stderr, "a test failed on another rank\n");
  PetscFinalize();
  return any_failed;
}
