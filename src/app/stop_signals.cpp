// Stop signals (see stop_signals.hpp).
#include "app/stop_signals.hpp"

#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <atomic>

namespace dipc {

namespace {

volatile sig_atomic_t g_signal = 0;
// When the signal came (CLOCK_MONOTONIC, ns): a lock-free atomic may be stored to in a signal
// handler, and clock_gettime is async-signal-safe (POSIX).
std::atomic<long long> g_signal_ns{0};
static_assert(std::atomic<long long>::is_always_lock_free, "the signal handler needs a lock-free store");

long long monotonic_ns() {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<long long>(now.tv_sec) * 1000000000LL + now.tv_nsec;
}

extern "C" void on_stop_signal(int signo) {
  if (g_signal != 0) _exit(128 + signo);
  g_signal_ns.store(monotonic_ns(), std::memory_order_relaxed);
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

double seconds_since_stop_signal() {
  if (g_signal == 0) return 0;
  return (monotonic_ns() - g_signal_ns.load(std::memory_order_relaxed)) * 1e-9;
}

int agree_on_signal(MPI_Comm comm) {
  int local = static_cast<int>(g_signal), global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_MAX, comm);
  return global;
}

StopDecision agree_on_stop(MPI_Comm comm, bool checkpoint_due_on_rank0) {
  int rank;
  MPI_Comm_rank(comm, &rank);
  int local[2] = {static_cast<int>(g_signal), rank == 0 && checkpoint_due_on_rank0 ? 1 : 0}, global[2];
  MPI_Allreduce(local, global, 2, MPI_INT, MPI_MAX, comm);
  return {global[0], global[1] != 0};
}

}  // namespace dipc
