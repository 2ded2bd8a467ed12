// SceneJsonNode: typed, path-aware access to a scene file's JSON (see scene_json_node.hpp).
#include "io/scene_json_node.hpp"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>

#include "io/scene.hpp"

namespace dipc {

SceneJsonNode::SceneJsonNode(const nlohmann::json& value, std::string path, const std::string& source)
    : value_(&value), path_(std::move(path)), source_(&source) {}

void SceneJsonNode::fail(const std::string& what) const {
  throw SceneError(*source_ + ": " + (path_.empty() ? std::string() : path_ + ": ") + what);
}

void SceneJsonNode::fail_value(const std::string& what) const {
  const std::string shown = path_.empty() ? value_->dump() : path_ + " = " + value_->dump();
  throw SceneError(*source_ + ": " + shown + ": " + what);
}

void SceneJsonNode::fail_type(const std::string& expected) const {
  fail("expected " + expected + ", got " + std::string(value_->type_name()) +
       (value_->is_primitive() && !value_->is_null() ? " " + value_->dump() : std::string()));
}

SceneJsonNode SceneJsonNode::child(const std::string& suffix, const nlohmann::json& value) const {
  return SceneJsonNode(value, path_ + suffix, *source_);
}

void SceneJsonNode::expect_object(const std::vector<std::string>& allowed, const std::string& context) const {
  if (!value_->is_object()) fail_type("an object");
  for (const auto& item : value_->items()) {
    bool known = false;
    for (const std::string& key : allowed) known = known || key == item.key();
    if (known) continue;
    std::string list;
    for (const std::string& key : allowed) list += (list.empty() ? "" : ", ") + key;
    const std::string key_path = path_.empty() ? item.key() : path_ + "." + item.key();
    throw SceneError(*source_ + ": " + key_path + ": unknown key (allowed" + (context.empty() ? "" : " " + context) +
                     ": " + list + ")");
  }
}

std::optional<SceneJsonNode> SceneJsonNode::find(const std::string& key) const {
  if (!value_->is_object()) fail_type("an object");
  const auto it = value_->find(key);
  if (it == value_->end()) return std::nullopt;
  return child(path_.empty() ? key : "." + key, *it);
}

SceneJsonNode SceneJsonNode::required(const std::string& key) const {
  if (auto node = find(key)) return *node;
  const std::string key_path = path_.empty() ? key : path_ + "." + key;
  throw SceneError(*source_ + ": " + key_path + ": required key is missing");
}

std::vector<SceneJsonNode> SceneJsonNode::elements() const {
  if (!value_->is_array()) fail_type("an array");
  std::vector<SceneJsonNode> out;
  out.reserve(value_->size());
  for (std::size_t i = 0; i < value_->size(); ++i) {
    out.push_back(child("[" + std::to_string(i) + "]", (*value_)[i]));
  }
  return out;
}

double SceneJsonNode::number() const {
  if (!value_->is_number()) fail_type("a number");
  const double v = value_->get<double>();
  // The JSON grammar has no NaN or inf, but a huge integer literal converts to a huge double
  // and any future extension could produce non-finite values: check every number.
  if (!std::isfinite(v)) fail("must be a finite number");
  return v;
}

int SceneJsonNode::integer() const {
  if (!value_->is_number_integer()) fail_type("an integer");
  if (value_->is_number_unsigned()) {
    if (value_->get<std::uint64_t>() > static_cast<std::uint64_t>(std::numeric_limits<int>::max())) {
      fail_value("too large (at most " + std::to_string(std::numeric_limits<int>::max()) + ")");
    }
    return static_cast<int>(value_->get<std::uint64_t>());
  }
  const std::int64_t v = value_->get<std::int64_t>();
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) {
    fail_value("out of the range of an int");
  }
  return static_cast<int>(v);
}

bool SceneJsonNode::boolean() const {
  if (!value_->is_boolean()) fail_type("true or false");
  return value_->get<bool>();
}

std::string SceneJsonNode::string() const {
  if (!value_->is_string()) fail_type("a string");
  return value_->get<std::string>();
}

std::array<double, 3> SceneJsonNode::vec3() const {
  if (!value_->is_array()) fail_type("an array of 3 numbers");
  if (value_->size() != 3) fail("expected an array of 3 numbers, got " + std::to_string(value_->size()));
  const std::vector<SceneJsonNode> items = elements();
  return {items[0].number(), items[1].number(), items[2].number()};
}

std::string resolve_mesh_path(const SceneJsonNode& node, const std::string& base_directory) {
  const std::string file = node.string();
  if (file.empty()) node.fail("must not be empty");
  std::filesystem::path path(file);
  if (path.is_relative()) path = std::filesystem::path(base_directory) / path;
  const std::string resolved = std::filesystem::absolute(path).lexically_normal().string();
  std::error_code ec;
  if (std::filesystem::is_directory(resolved, ec)) node.fail(resolved + ": is a directory, not a mesh file");
  return resolved;
}

}  // namespace dipc
