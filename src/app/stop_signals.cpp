// Stop signals (see stop_signals.hpp).
#include "app/stop_signals.hpp"

#include <signal.h>
#include <unistd.h>

namespace dipc {

namespace {

volatile sig_atomic_t g_signal = 0;

extern "C" void on_stop_signal(int signo) {
  if (g_signal != 0) _exit(128 + signo);
  g_signal = signo;
}

}  // namespace

void install_stop_signal_handlers() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  // Restart interrupted system calls: MPI and file I/O go on as if nothing happened.
  action.sa_flags = SA_RESTART;
  for (int signo : {SIGTERM, SIGINT, SIGUSR1}) sigaction(signo, &action, nullptr);
}

int received_stop_signal() { return g_signal; }

StopDecision agree_on_stop(MPI_Comm comm, bool checkpoint_due_on_rank0) {
  int rank;
  MPI_Comm_rank(comm, &rank);
  int local[2] = {static_cast<int>(g_signal), rank == 0 && checkpoint_due_on_rank0 ? 1 : 0}, global[2];
  MPI_Allreduce(local, global, 2, MPI_INT, MPI_MAX, comm);
  return {global[0], global[1] != 0};
}

}  // namespace dipc
