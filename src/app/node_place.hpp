// NodePlace: where a rank stands among the ranks that share its node (MPI_COMM_TYPE_SHARED), for
// decisions taken once per node (which GPU a rank takes, which rank reads the node's memory).
#pragma once
#include <mpi.h>

namespace dipc {

struct NodePlace {
  int rank = 0;   // among the ranks of this node, in the order of their ranks in comm
  int ranks = 1;  // ranks on this node
};

// Collective over comm.
NodePlace node_place(MPI_Comm comm);

}  // namespace dipc
