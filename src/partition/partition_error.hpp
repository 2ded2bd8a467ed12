// PartitionError: the exception thrown by the partition layer (invalid input mesh, METIS
// failure, sizes beyond what MPI/METIS index types can hold).
#pragma once
#include <stdexcept>
#include <string>

namespace dipc {

class PartitionError : public std::runtime_error {
 public:
  explicit PartitionError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace dipc
