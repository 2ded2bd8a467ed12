// dipc-surface: the boundary surface of a dipc output file at one step, as VTK XML PolyData
// (.vtp) that ParaView and pvbatch open: a few per cent of the .h5's size, so that a big run's
// result can be copied off the machine that computed it and rendered elsewhere.
//
//   dipc-surface OUTPUT.h5 OUT.vtp [--step K|last] [--split-bodies]
//
// The quads are the hex faces of exactly one element, oriented outward, with the cell field
// "body"; the points are the surface's nodes at reference + displacement of step K (default:
// the last written step). --split-bodies writes OUT_<body name>.vtp per body and OUT.vtm, a
// multiblock file naming them (tools/surface_export.hpp). Prints one summary line; exit status
// 1 with "dipc-surface: error: ..." for bad arguments or input, and then no output file is left.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "tools/surface_export.hpp"

namespace {

constexpr const char* kUsage = "usage: dipc-surface OUTPUT.h5 OUT.vtp [--step K|last] [--split-bodies]\n"
                               "  --step K        the written step K (/steps/K); default: the last one\n"
                               "  --split-bodies  OUT_<body>.vtp per body and OUT.vtm naming them\n";

struct Arguments {
  std::string input, output;
  std::int64_t step = -1;  // the last
  bool split_bodies = false;
};

[[noreturn]] void usage_error(const std::string& what) { throw std::invalid_argument(what + "\n" + kUsage); }

Arguments parse(int argc, char** argv) {
  Arguments a;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--step") {
      if (i + 1 >= argc) usage_error("--step needs a value");
      const std::string v = argv[++i];
      char* end = nullptr;
      const long long k = std::strtoll(v.c_str(), &end, 10);
      if (v == "last") {
        a.step = -1;
      } else if (v.empty() || *end != '\0' || k < 0) {
        usage_error("--step: '" + v + "' is neither a step number (0, 1, ...) nor 'last'");
      } else {
        a.step = k;
      }
    } else if (arg == "--split-bodies") {
      a.split_bodies = true;
    } else if (arg == "-h" || arg == "--help") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    } else if (!arg.empty() && arg[0] == '-') {
      usage_error("unknown option " + arg);
    } else {
      positional.push_back(arg);
    }
  }
  if (positional.size() != 2) usage_error("expected an output .h5 file and a .vtp file to write");
  a.input = positional[0];
  a.output = positional[1];
  return a;
}

int run(const Arguments& a) {
  const auto start = std::chrono::steady_clock::now();
  const dipc::SurfaceExport e = dipc::export_surface(a.input, a.output, a.step, a.split_bodies);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string written = e.files.size() == 1
                                  ? e.files[0]
                                  : e.files.back() + " + " + std::to_string(e.files.size() - 1) + " .vtp";
  std::printf("dipc-surface: %s step %lld (t = %.6g): %lld elements, %lld surface quads, %lld surface nodes; "
              "%llu bytes -> %s; %.2f s\n",
              a.input.c_str(), static_cast<long long>(e.step), e.time, static_cast<long long>(e.num_elements),
              static_cast<long long>(e.num_quads), static_cast<long long>(e.num_points),
              static_cast<unsigned long long>(e.bytes), written.c_str(), seconds);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dipc-surface: error: %s\n", e.what());
    return 1;
  }
}
