// Stop signals (issue 13): SIGTERM, SIGINT and SIGUSR1 ask a run to stop at the next step
// boundary with a checkpoint (what a batch system sends before a time limit or pre-emption:
// SLURM's --signal, `scancel --signal`). The handler only records the signal (an async-signal-
// safe store to a volatile sig_atomic_t); the ranks agree on it at step boundaries
// (agree_on_stop, one small MPI_Allreduce), so a signal that reached one rank stops them all.
// A second signal, while the first is pending, ends the process at once with status 128 +
// signo (_exit, async-signal-safe), for a user who does not want to wait for the step.
#pragma once
#include <mpi.h>

namespace dipc {

// Installs the handlers (after PetscInitialize, which installs its own for SIGTERM).
void install_stop_signal_handlers();

// The signal received by this process, 0 if none.
int received_stop_signal();

// Collective: the largest signal number any rank received (0: none), and whether rank 0's
// `checkpoint_due` is set (a wall-clock rule decided on rank 0, so every rank agrees).
struct StopDecision {
  int signal = 0;
  bool checkpoint_due = false;
};
StopDecision agree_on_stop(MPI_Comm comm, bool checkpoint_due_on_rank0);

}  // namespace dipc
