#include "mpi/agreement.hpp"

#include <unistd.h>

#include <algorithm>
#include <climits>
#include <cstdint>

#include "model/run_spec.hpp"
#include "mpi/comm.hpp"

namespace cs {
namespace {

enum class Kind : int { input = 2, runtime = 1 };

std::string host_name() {
  char name[HOST_NAME_MAX + 1] = {};
  return ::gethostname(name, sizeof name) == 0 ? std::string(name) : std::string("?");
}

}  // namespace

void broadcast(MPI_Comm comm, std::string& text) {
  if (serial(comm)) return;
  auto length = static_cast<std::int64_t>(text.size());
  MPI_Bcast(&length, 1, MPI_INT64_T, 0, comm);
  text.resize(static_cast<std::size_t>(length));
  // Counts are int: send long texts in pieces.
  for (std::int64_t done = 0; done < length;) {
    const int piece = static_cast<int>(std::min<std::int64_t>(length - done, INT_MAX / 2));
    MPI_Bcast(text.data() + done, piece, MPI_CHAR, 0, comm);
    done += piece;
  }
}

void throw_if_any_failed(MPI_Comm comm, std::exception_ptr local_failure) {
  const int rank = rank_of(comm), size = size_of(comm);
  int first_failed = local_failure ? rank : size;
  allreduce(comm, &first_failed, 1, MPI_INT, MPI_MIN);
  if (first_failed == size) return;

  int kind = static_cast<int>(Kind::runtime);
  std::string message;
  if (rank == first_failed) {
    try {
      std::rethrow_exception(local_failure);
    } catch (const InputError& e) {
      kind = static_cast<int>(Kind::input);
      message = e.what();
    } catch (const std::exception& e) {
      message = e.what();
    } catch (...) {
      message = "unknown failure";
    }
    if (rank != 0) message = "rank " + std::to_string(rank) + " (" + host_name() + "): " + message;
  }
  bcast(comm, &kind, 1, MPI_INT, first_failed);
  auto length = static_cast<int>(message.size());
  bcast(comm, &length, 1, MPI_INT, first_failed);
  message.resize(static_cast<std::size_t>(length));
  bcast(comm, message.data(), length, MPI_CHAR, first_failed);
  if (kind == static_cast<int>(Kind::input)) throw InputError(message);
  throw CollectiveError(message);
}

}  // namespace cs
