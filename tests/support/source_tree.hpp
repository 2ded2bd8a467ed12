// Where the tests find their data (scenes/, tests/*/data/, src/): the source tree, located
//   1. by the environment variable DIPC_SOURCE_DIR when it is set (a moved or copied tree), else
//   2. relative to the test binary: CMake compiles in the path from the binary's directory to
//      the source tree (DIPC_SOURCE_FROM_BINARY), so a tree moved together with its build
//      directory inside it still finds its data; no absolute path is compiled in.
#pragma once
#include <unistd.h>

#include <filesystem>
#include <stdexcept>
#include <string>

namespace dipc::test {

inline std::string source_dir() {
  if (const char* dir = std::getenv("DIPC_SOURCE_DIR"); dir && *dir) return dir;
  std::error_code error;
  const std::filesystem::path binary = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) throw std::runtime_error("cannot read /proc/self/exe; set DIPC_SOURCE_DIR to the source tree");
  std::filesystem::path dir = (binary.parent_path() / DIPC_SOURCE_FROM_BINARY).lexically_normal();
  if (!dir.has_filename()) dir = dir.parent_path();  // "a/b/../.." normalises to "a/"
  if (!std::filesystem::exists(dir / "scenes"))
    throw std::runtime_error("no source tree at " + dir.string() + " (found from " + binary.string() +
                             "); set DIPC_SOURCE_DIR to it");
  return dir.string();
}

// source_dir() + "/" + relative, e.g. source_path("scenes/boxes_drop.json").
inline std::string source_path(const std::string& relative) { return source_dir() + "/" + relative; }

}  // namespace dipc::test
