// Preloaded into dipc by library_exit_test.py (LD_PRELOAD): stands in for hypre's
// HYPRE_BoomerAMGSetup and, at the call numbered DIPC_TEST_EXIT_AT_SETUP, does what hypre 2.32
// does on a failed cuSPARSE call (HYPRE_CUSPARSE_CALL): prints one line and calls exit, with the
// status DIPC_TEST_EXIT_STATUS (default 1). Every other call goes to the real function.
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>

typedef int (*amg_setup)(void* solver, void* A, void* b, void* x);

int HYPRE_BoomerAMGSetup(void* solver, void* A, void* b, void* x) {
  static int calls = 0;
  const char* at = getenv("DIPC_TEST_EXIT_AT_SETUP");
  if (at && ++calls >= atoi(at)) {
    const char* status = getenv("DIPC_TEST_EXIT_STATUS");
    printf("CUSPARSE ERROR (code = 11, insufficient resources) at csr_spgemm_device_cusparse.c:148 (simulated)\n");
    exit(status ? atoi(status) : 1);
  }
  amg_setup real = (amg_setup)dlsym(RTLD_NEXT, "HYPRE_BoomerAMGSetup");
  if (!real) {
    fprintf(stderr, "exiting_amg_setup: no HYPRE_BoomerAMGSetup after this library\n");
    abort();
  }
  return real(solver, A, b, x);
}
