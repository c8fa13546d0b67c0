// Decisions and failures that every MPI rank learns together. A rank that refuses or fails on
// its own (a spec it cannot read, its node's memory, a full disk in its save) and returns would
// leave the others waiting in the next collective call: the job hangs and burns its allocation.
// So every step whose outcome can differ between ranks runs inside agreed(): afterwards either
// every rank goes on, or every rank throws the same error and leaves the collective path at once.
#pragma once

#include <mpi.h>

#include <exception>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

namespace cs {

// A run-time failure (I/O, resources) that every rank throws at the same point. The program
// exits 1 on every rank after rank 0 printed it once; no MPI_Abort is needed.
class CollectiveError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Collective (MPI_COMM_NULL: a process without MPI, mpi/comm.hpp). If `local_failure` is set on any rank, every rank throws the error of the lowest
// failing rank: an InputError as an InputError (exit 2), anything else as a CollectiveError.
// A message from a rank other than 0 is prefixed with that rank and its host, since only rank 0
// prints.
void throw_if_any_failed(MPI_Comm comm, std::exception_ptr local_failure);

// Collective: runs `step` on every rank and returns its result, or throws on every rank as
// throw_if_any_failed does.
template <class Step>
auto agreed(MPI_Comm comm, Step&& step) {
  using Result = std::invoke_result_t<Step>;
  std::exception_ptr failure;
  if constexpr (std::is_void_v<Result>) {
    try {
      std::forward<Step>(step)();
    } catch (...) {
      failure = std::current_exception();
    }
    throw_if_any_failed(comm, failure);
  } else {
    std::optional<Result> result;
    try {
      result.emplace(std::forward<Step>(step)());
    } catch (...) {
      failure = std::current_exception();
    }
    throw_if_any_failed(comm, failure);
    return std::move(*result);
  }
}

// Collective: rank 0's `text` on every rank.
void broadcast(MPI_Comm comm, std::string& text);

}  // namespace cs
