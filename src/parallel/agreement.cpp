#include "parallel/agreement.hpp"

#include <unistd.h>

#include <algorithm>
#include <climits>
#include <cstdint>

#include "io/run_spec.hpp"

namespace cs {
namespace {

enum class Kind : int { input = 2, runtime = 1 };

std::string host_name() {
  char name[HOST_NAME_MAX + 1] = {};
  return ::gethostname(name, sizeof name) == 0 ? std::string(name) : std::string("?");
}

}  // namespace

void broadcast(MPI_Comm comm, std::string& text) {
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
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  int first_failed = local_failure ? rank : size;
  MPI_Allreduce(MPI_IN_PLACE, &first_failed, 1, MPI_INT, MPI_MIN, comm);
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
  MPI_Bcast(&kind, 1, MPI_INT, first_failed, comm);
  auto length = static_cast<int>(message.size());
  MPI_Bcast(&length, 1, MPI_INT, first_failed, comm);
  message.resize(static_cast<std::size_t>(length));
  MPI_Bcast(message.data(), length, MPI_CHAR, first_failed, comm);
  if (kind == static_cast<int>(Kind::input)) throw InputError(message);
  throw CollectiveError(message);
}

}  // namespace cs
