// The ranks of a run. MPI_COMM_NULL stands for a process that no MPI launcher started: MPI is
// then never initialised (a singleton MPI_Init costs ~0.4 s, more than a small run), the process
// is rank 0 of 1, and every collective below is the identity. With a real communicator these
// are the MPI calls they name.
#pragma once

#include <mpi.h>

#include <vector>

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

// Every rank's values, concatenated in rank order, on every rank (all_ranks) or on rank 0 only
// (the others get nothing back). Counts are ints: at most 2^31 − 1 values in all.
inline std::vector<double> gather(MPI_Comm comm, const std::vector<double>& mine, bool all_ranks) {
  if (serial(comm)) return mine;
  const int ranks = size_of(comm);
  int count = static_cast<int>(mine.size());
  std::vector<int> counts(static_cast<std::size_t>(ranks)), offsets(static_cast<std::size_t>(ranks));
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  int total = 0;
  for (int r = 0; r < ranks; ++r) {
    offsets[static_cast<std::size_t>(r)] = total;
    total += counts[static_cast<std::size_t>(r)];
  }
  std::vector<double> all(all_ranks || rank_of(comm) == 0 ? static_cast<std::size_t>(total) : 0);
  if (all_ranks)
    MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(),
                   MPI_DOUBLE, comm);
  else
    MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(),
                MPI_DOUBLE, 0, comm);
  return all;
}

}  // namespace cs
