#include "io/polyfem_common.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/json_document.hpp"
#include "io/scene.hpp"

namespace dipc {
namespace {

namespace fs = std::filesystem;

std::string absolute_path(const std::string& path, const std::string& directory) {
  fs::path p(path);
  if (p.is_relative()) p = fs::path(directory) / p;
  return fs::absolute(p).lexically_normal().string();
}

nlohmann::json merge(const nlohmann::json& document, const std::string& source, const std::string& base_directory,
                     std::vector<std::string>& chain, std::vector<std::string>* merged) {
  if (!document.is_object() || !document.contains("common")) return document;
  const nlohmann::json& name = document["common"];
  if (!name.is_string()) throw SceneError(source + ": common: expected the path of a JSON file");
  nlohmann::json scene = document;
  scene.erase("common");
  if (name.get<std::string>().empty()) return scene;  // PolyFEM reads no file then
  // PolyFEM resolves `common` against the scene's root_path (its file when it has none).
  std::string directory = base_directory;
  if (scene.contains("root_path") && scene["root_path"].is_string())
    directory = polyfem_root_directory(scene["root_path"].get<std::string>(), base_directory);
  const std::string path = absolute_path(name.get<std::string>(), directory);
  const std::string where = source + ": common = \"" + name.get<std::string>() + "\": " + path;
  if (std::find(chain.begin(), chain.end(), path) != chain.end())
    throw SceneError(where + ": includes itself (through its own common)");
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw SceneError(where + ": is a directory, not a JSON file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(where + ": cannot open");
  std::ostringstream text;
  text << in.rdbuf();
  nlohmann::json common = parse_json_document(text.str(), path);
  if (!common.is_object()) throw SceneError(path + ": expected a JSON object (read as the common of " + source + ")");
  if (merged) merged->push_back(path);
  const std::string common_directory = fs::path(path).parent_path().string();
  const bool has_root_path = common.contains("root_path");
  if (has_root_path) {
    if (!common["root_path"].is_string()) throw SceneError(path + ": root_path: expected a path");
    common["root_path"] = absolute_path(common["root_path"].get<std::string>(), common_directory);
  }
  chain.push_back(path);
  common = merge(common, path, has_root_path ? common["root_path"].get<std::string>() : common_directory, chain,
                 merged);
  chain.pop_back();
  // The scene's root_path (its file, in PolyFEM) wins over one that came from a deeper common;
  // the common file's own root_path wins over the scene's (PolyFEM's rule, so that the common
  // file's relative paths stay right).
  if (has_root_path)
    scene["root_path"] = common["root_path"];
  else
    common.erase("root_path");
  nlohmann::json patch;
  if (scene.contains("patch")) {
    patch = scene["patch"];
    scene.erase("patch");
  }
  common.merge_patch(scene);
  if (!patch.is_null()) {
    try {
      common = common.patch(patch);
    } catch (const nlohmann::json::exception& e) {
      throw SceneError(source + ": patch: does not apply to the scene merged with its common file: " + e.what());
    }
  }
  return common;
}

}  // namespace

std::string polyfem_root_directory(const std::string& root_path, const std::string& base_directory) {
  const std::string path = absolute_path(root_path, base_directory);
  std::error_code ec;
  return fs::is_directory(path, ec) ? path : fs::path(path).parent_path().string();
}

nlohmann::json merge_polyfem_common(const nlohmann::json& document, const std::string& source,
                                    const std::string& base_directory, std::vector<std::string>* merged) {
  // base_directory is the scene file's directory (source may be relative to the working one).
  std::vector<std::string> chain{absolute_path(fs::path(source).filename().string(), base_directory)};
  return merge(document, source, base_directory, chain, merged);
}

}  // namespace dipc
