// Errors in collective output: a failure seen by some ranks (rank 0 could not create a
// directory, one rank's HDF5 write failed) must throw on every rank, or the others would
// wait forever in the next collective call.
#pragma once
#include <mpi.h>

#include <string>

namespace dipc {

// Collective over `comm`. `local_error` is empty where this rank succeeded. If any rank
// failed, every rank throws std::runtime_error with the message of the lowest failing rank.
void throw_if_failed_anywhere(MPI_Comm comm, const std::string& local_error);

}  // namespace dipc
