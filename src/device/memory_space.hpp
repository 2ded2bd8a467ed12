// MemorySpace: where an array lives and where the code that reads it runs, the host or the CUDA
// device of the rank. Forms, the contact set and the potential's local views choose by it at run
// time (docs/design.md §4), so it sits in the lowest layer that all of them use.
#pragma once

namespace dipc {

enum class MemorySpace { host, device };

}  // namespace dipc
