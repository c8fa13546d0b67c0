#include "mpi/failure_watch.hpp"

#include "parallel/stop_signal.hpp"

namespace cs {

FailureWatch::FailureWatch(MPI_Comm comm) {
  if (comm == MPI_COMM_NULL) {  // one process without MPI: its own failure is all there is
    over_ = true;
    return;
  }
  MPI_Comm_dup(comm, &comm_);  // its rounds never match another collective by mistake
  start_round();
}

FailureWatch::~FailureWatch() {
  if (comm_ == MPI_COMM_NULL) return;
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized) return;
  // A round still in flight means an exception left the block loop without finish(); that path
  // ends in MPI_Abort (main.cpp), and a communicator with a pending collective cannot be freed.
  if (request_ == MPI_REQUEST_NULL) MPI_Comm_free(&comm_);
}

bool FailureWatch::stop() const {
  return failed_here_ || failed_anywhere_ || stopped_anywhere_ || stop_signal() != 0;
}

void FailureWatch::start_round() {
  contribution_[0] = failed_here_ ? 1 : 0;
  contribution_[1] = working_ ? 1 : 0;
  contribution_[2] = stop_signal();
  MPI_Iallreduce(contribution_, result_, 3, MPI_INT, MPI_MAX, comm_, &request_);
}

bool FailureWatch::round_complete(bool wait) {
  int done = 0;
  if (wait) {
    MPI_Wait(&request_, MPI_STATUS_IGNORE);
    done = 1;
  } else {
    MPI_Test(&request_, &done, MPI_STATUS_IGNORE);
  }
  if (!done) return false;
  if (result_[0] != 0) failed_anywhere_ = true;
  if (result_[2] != 0) stopped_anywhere_ = true;
  over_ = result_[0] != 0 || result_[1] == 0 || result_[2] != 0;
  return true;
}

void FailureWatch::poll() {
  if (over_) return;
  if (round_complete(false) && !over_) start_round();
}

void FailureWatch::finish() {
  working_ = false;
  while (!over_) {
    round_complete(true);
    if (!over_) start_round();
  }
}

}  // namespace cs
