// Stop signals (issue 13): SIGTERM, SIGINT and SIGUSR1 ask a run to stop with a checkpoint
// (what a batch system sends before a time limit or pre-emption: SLURM's --signal, `scancel
// --signal`, and the TERM of `scancel`, a requeue or `mpirun` forwarding its own). The handler
// only records the signal and when it came (async-signal-safe stores); the ranks agree on it
// with one small MPI_Allreduce, so a signal that reached one rank stops them all. They ask at
// step boundaries (agree_on_stop) and, so that a long step does not outlast the time a batch
// system or mpirun grants before SIGKILL (issue 32), at every Newton iteration
// (agree_on_signal): the step in progress is then abandoned and the last completed one is
// checkpointed. A second signal, while the first is pending, ends the process at once with
// status 128 + signo (_exit, async-signal-safe), for a user who does not want to wait.
#pragma once
#include <mpi.h>

namespace dipc {

// Installs the handlers (after PetscInitialize, which installs its own for SIGTERM).
void install_stop_signal_handlers();

// The signal received by this process, 0 if none.
int received_stop_signal();

// Seconds since this process received its stop signal (monotonic clock; 0 without one).
double seconds_since_stop_signal();

// Collective: the largest signal number any rank received (0: none).
int agree_on_signal(MPI_Comm comm);

// Collective: the largest signal number any rank received (0: none), and whether rank 0's
// `checkpoint_due` is set (a wall-clock rule decided on rank 0, so every rank agrees).
struct StopDecision {
  int signal = 0;
  bool checkpoint_due = false;
};
StopDecision agree_on_stop(MPI_Comm comm, bool checkpoint_due_on_rank0);

}  // namespace dipc
