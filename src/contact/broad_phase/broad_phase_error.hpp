// BroadPhaseError: thrown by the contact broad phase for inputs it cannot search (ids out of
// range, non-finite coordinates, a negative inflation). Messages name the vertex, edge or face.
#pragma once
#include <stdexcept>
#include <string>

namespace dipc::contact {

class BroadPhaseError : public std::runtime_error {
 public:
  explicit BroadPhaseError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace dipc::contact
