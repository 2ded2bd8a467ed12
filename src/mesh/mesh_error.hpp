// MeshError: the exception every mesh-layer function (generators, readers, checks) throws
// for a mesh it cannot build or accept. Messages name the source (file path and line, or
// the generator) and the node or element id, so a user can find the problem.
#pragma once
#include <stdexcept>
#include <string>

namespace dipc {

class MeshError : public std::runtime_error {
 public:
  explicit MeshError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace dipc
