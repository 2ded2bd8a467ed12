// The command line the size-sweep benchmarks share: a comma-separated size list under a
// benchmark's own flag (-sizes, -triangles), -repeat R and -csv PATH.
#pragma once
#include <algorithm>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace dipc::bench {

struct SweepArgs {
  std::vector<long> sizes;
  int repeat = 1;
  std::string csv_path;
};

// Reads argv into *args (whose fields hold the defaults); false on an unknown or incomplete
// argument, for the caller to print its usage.
inline bool parse_sweep_args(int argc, char** argv, const std::string& size_flag, SweepArgs* args) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == size_flag && i + 1 < argc) {
      args->sizes.clear();
      std::stringstream list(argv[++i]);
      std::string item;
      while (std::getline(list, item, ',')) args->sizes.push_back(std::stol(item));
    } else if (a == "-repeat" && i + 1 < argc) {
      args->repeat = std::max(1, std::atoi(argv[++i]));
    } else if (a == "-csv" && i + 1 < argc) {
      args->csv_path = argv[++i];
    } else {
      return false;
    }
  }
  return true;
}

}  // namespace dipc::bench
