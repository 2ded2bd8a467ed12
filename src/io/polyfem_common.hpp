// PolyFEM's `common` key (utils/JSONUtils.cpp, apply_common_params), which its example scenes
// use to share solver, contact and output settings: the scene is a JSON merge patch (RFC 7396:
// objects merge key by key, anything else replaces, null deletes) over the JSON file that
// `common` names, which may itself have a `common`; then the scene's `patch`, a JSON Patch
// (RFC 6902) list, applies to the result.
//  - `common` is a path relative to the scene's root_path when it has one, else to its
//    directory; a nested `common`, relative to its file's root_path, else to its directory.
//  - Relative paths in the result resolve against the scene's directory (PolyFEM sets root_path
//    to the scene file), unless the common file has a root_path: that one, taken relative to
//    the common file, replaces the scene's.
//  - An empty `common` is no file, as in PolyFEM.
#pragma once
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace dipc {

// The directory that PolyFEM's root_path stands for (utils/StringUtils.cpp, resolve_path): the
// path itself, relative to `base_directory`, when it is a directory, else its parent (PolyFEM
// sets root_path to the scene file), as an absolute path.
std::string polyfem_root_directory(const std::string& root_path, const std::string& base_directory);

// The document with its `common` file(s) merged in and `common` and `patch` removed; returned
// unchanged without `common`. `merged` receives the files read, the scene's own first. Throws
// SceneError "<source>: common...: <what>" for a file that cannot be read or parsed, a `common`
// that includes itself, or a `patch` that does not apply.
nlohmann::json merge_polyfem_common(const nlohmann::json& document, const std::string& source,
                                    const std::string& base_directory, std::vector<std::string>* merged);

}  // namespace dipc
