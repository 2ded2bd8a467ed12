// SceneJsonNode: one value of a parsed scene file together with its key path
// ("boundary_conditions.dirichlet[1].velocity[2]"), so every check the scene parser makes
// can say where the offending value is. Typed accessors reject wrong types and non-finite
// numbers; failures throw SceneError "<source>: <key path>: <what>".
#pragma once
#include <nlohmann/json.hpp>

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace dipc {

class SceneJsonNode {
 public:
  // `value` and `source` must outlive the node and every node derived from it.
  SceneJsonNode(const nlohmann::json& value, std::string path, const std::string& source);

  const nlohmann::json& json() const { return *value_; }
  const std::string& path() const { return path_; }

  // "<source>: <path>: <what>"
  [[noreturn]] void fail(const std::string& what) const;
  // "<source>: <path> = <value as JSON>: <what>", for values that have the right type but
  // are out of range.
  [[noreturn]] void fail_value(const std::string& what) const;

  // Requires an object whose keys all appear in `allowed`; the message for an unknown key
  // lists them (after `context`, e.g. "for type \"fixed\"", when given).
  void expect_object(const std::vector<std::string>& allowed, const std::string& context = "") const;
  // Child of an object: `find` returns nothing when absent, `required` fails.
  std::optional<SceneJsonNode> find(const std::string& key) const;
  SceneJsonNode required(const std::string& key) const;
  // Elements of an array (fails when this is not an array).
  std::vector<SceneJsonNode> elements() const;

  double number() const;  // any finite JSON number
  int integer() const;    // a JSON integer that fits in an int
  bool boolean() const;
  std::string string() const;
  std::array<double, 3> vec3() const;  // array of exactly 3 finite numbers

 private:
  SceneJsonNode child(const std::string& suffix, const nlohmann::json& value) const;
  [[noreturn]] void fail_type(const std::string& expected) const;

  const nlohmann::json* value_;
  std::string path_;
  const std::string* source_;
};

// The mesh file that `node` (a string) names. Paths are relative to the scene file, as a user
// writing the scene expects, and returned absolute so that later stages do not depend on the
// working directory. Fails on an empty path and on a directory, which the mesh readers would
// otherwise take for an empty or unreadable file and report without the key.
std::string resolve_mesh_path(const SceneJsonNode& node, const std::string& base_directory);

}  // namespace dipc
