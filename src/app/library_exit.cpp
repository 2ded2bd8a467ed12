#include "app/library_exit.hpp"

#include <mpi.h>

#include <cstdio>
#include <cstdlib>

#include "device/device_runtime.hpp"

namespace dipc::library_exit {
namespace {

// What the handler prints; set by the run, read only at exit.
struct State {
  bool registered = false, armed = false;
  int rank = -1;
  long long elements = 0;
  std::string device, phase, xdmf_path;
  std::size_t device_used = 0, device_total = 0;
  std::size_t output_frames = 0;  // 0: no output written
};
State& state() {
  static State s;
  return s;
}

void report() {
  State& s = state();
  if (!s.armed) return;
  s.armed = false;
  std::fflush(stdout);
  std::string memory;
  if (!s.device.empty()) {
    char buf[160];
    std::snprintf(buf, sizeof buf, ", on %s with %.2f of %.2f GiB of device memory in use when it began", s.device.c_str(),
                  s.device_used / 1073741824.0, s.device_total / 1073741824.0);
    memory = buf;
  }
  std::string output = "No output had been written";
  if (s.output_frames > 0)
    output = "The output in " + s.xdmf_path + " stays readable: " + std::to_string(s.output_frames) +
             " complete time frame(s)";
  std::fprintf(stderr,
               "dipc: error: rank %d: a library ended the process (it called exit; its message, if any, is above) "
               "during %s; the rank has %lld elements%s. %s. If the message names the GPU (CUDA, cuSPARSE, out of "
               "memory, insufficient resources), give each GPU fewer elements: run on more GPUs (mpirun -n, one "
               "rank per GPU) or with -dipc_backend cpu\n",
               s.rank, s.phase.c_str(), s.elements, memory.c_str(), output.c_str());
  std::fflush(stderr);
  std::_Exit(1);  // the library may have asked for 0; the remaining exit handlers are skipped
}

}  // namespace

ArmedRun::ArmedRun(long long elements, const std::string& device) {
  State& s = state();
  MPI_Comm_rank(MPI_COMM_WORLD, &s.rank);
  s.elements = elements;
  s.device = device;
  s.output_frames = 0;
  if (!s.registered) s.registered = std::atexit(report) == 0;
  s.armed = true;
  enter("setup");
}

ArmedRun::~ArmedRun() { state().armed = false; }

void enter(const std::string& phase) {
  State& s = state();
  s.phase = phase;
  if (s.device.empty()) return;
  const device::MemoryInfo m = device::memory_info();  // cudaMemGetInfo: microseconds, once a step
  s.device_used = m.total_bytes - m.free_bytes;
  s.device_total = m.total_bytes;
}

void output_complete(const std::string& xdmf_path, std::size_t frames) {
  State& s = state();
  s.xdmf_path = xdmf_path;
  s.output_frames = frames;
}

}  // namespace dipc::library_exit
