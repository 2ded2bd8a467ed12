// XDMF 3 text for dipc's output: a temporal collection with one uniform hexahedral grid per
// written step, all heavy data in the companion HDF5 file (layout in xdmf_writer.hpp).
// Kept apart from the writer so the text can be checked without MPI or HDF5.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace dipc {

struct XdmfLayout {
  std::string h5_file_name;  // relative to the .xmf (same directory), e.g. "dipc.h5"
  std::int64_t num_nodes = 0;
  std::int64_t num_elements = 0;
};

// Step k of `step_times` refers to the HDF5 group /steps/k.
std::string xdmf_document(const XdmfLayout& layout, const std::vector<double>& step_times);

}  // namespace dipc
