// The ranks of a run. MPI_COMM_NULL stands for a process that no MPI launcher started: MPI is
// then never initialised (a singleton MPI_Init costs ~0.4 s, more than a small run), the process
// is rank 0 of 1, and every collective below is the identity. With a real communicator these
// are the MPI calls they name.
#pragma once

#include <mpi.h>

namespace cs {

inline bool serial(MPI_Comm comm) { return comm == MPI_COMM_NULL; }

inline int rank_of(MPI_Comm comm) {
  int rank = 0;
  if (!serial(comm)) MPI_Comm_rank(comm, &rank);
  return rank;
}

inline int size_of(MPI_Comm comm) {
  int size = 1;
  if (!serial(comm)) MPI_Comm_size(comm, &size);
  return size;
}

// In place: `data` holds this rank's values and receives the result.
inline void allreduce(MPI_Comm comm, void* data, int count, MPI_Datatype type, MPI_Op op) {
  if (!serial(comm)) MPI_Allreduce(MPI_IN_PLACE, data, count, type, op, comm);
}

inline void bcast(MPI_Comm comm, void* data, int count, MPI_Datatype type, int root) {
  if (!serial(comm)) MPI_Bcast(data, count, type, root, comm);
}

}  // namespace cs
