// The boundary surface of a dipc output file at one written step, as VTK XML PolyData: the core
// of dipc-surface, also used by tests. A big run's .h5 holds every element and node per step
// (gigabytes at 20M hexes); its surface is a few per cent of that, small enough to copy off the
// machine that ran it and to render with pvbatch.
//
// The surface is the hex faces that belong to exactly one element (mesh/boundary_faces.hpp:
// matched by their node ids, so glued bodies that share nodes show no face between them), each
// a quad in the element's own corner order, counter-clockwise seen from outside. Its points are
// the surface's nodes only, renumbered in ascending node id, at reference + the step's
// displacement. Input layout: io/xdmf_writer.hpp.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace dipc {

// A quad surface with a body id per quad: the content of one .vtp file.
struct QuadSurface {
  std::vector<std::array<float, 3>> points;        // deformed positions
  std::vector<std::array<std::int32_t, 4>> quads;  // point indices, outward orientation
  std::vector<std::int32_t> body;                  // per quad: its element's body id
};

struct StepSurface {
  std::int64_t num_elements = 0;
  std::int64_t step = 0;                // the step read, k of /steps/<k>
  double time = 0;                      // its "time" attribute
  std::vector<std::string> body_names;  // /mesh/body_names (empty where the file has none)
  QuadSurface surface;
};

// Reads `h5_path` and extracts the surface at /steps/<step>; step < 0 picks the last written
// step. Throws std::runtime_error naming the file and the dataset for a missing or malformed
// input, a missing step, or a mesh without a well-defined boundary (a face of 3 elements).
StepSurface read_step_surface(const std::string& h5_path, std::int64_t step);

// The quads of body `body` and the points they use, renumbered in ascending index.
QuadSurface body_surface(const QuadSurface& surface, std::int32_t body);

// What export_surface wrote.
struct SurfaceExport {
  std::int64_t num_elements = 0, num_quads = 0, num_points = 0, step = 0;
  double time = 0;
  std::vector<std::string> files;  // written paths, the .vtm last
  std::uint64_t bytes = 0;         // all files together
};

// read_step_surface(h5_path, step) written to `vtp_path` (which must end in .vtp). With
// split_bodies, one OUT_<body name>.vtp per body that has elements and OUT.vtm (multiblock,
// one block per body, named by the body) instead, where OUT is vtp_path without ".vtp".
// Every file is written under "<name>.tmp" and renamed only once all are complete, so a failure
// leaves no partial output (and the files of an earlier export untouched). Throws
// std::runtime_error naming the file on failure.
SurfaceExport export_surface(const std::string& h5_path, const std::string& vtp_path, std::int64_t step,
                             bool split_bodies);

}  // namespace dipc
