// Lets every rank learn, between blocks, that some rank has failed, without making ranks wait
// for each other while all is well. A failed save (a full disk) must stop the whole job at once:
// going on would compute for hours and then throw everything that cannot be saved away.
//
// A stop signal (SIGTERM, SIGINT: parallel/stop_signal.hpp) reaches every rank the same way: a
// batch system may signal some ranks later than others, or only some, and no rank may go on
// computing, or wait in a collective, for a run that is being stopped.
//
// Protocol: rounds of non-blocking all-reduces over (failed, still working, stop signal). A rank
// starts the next round as soon as the previous one is complete, checking after every block it
// finishes (main thread only: MPI is initialised MPI_THREAD_FUNNELED); a rank whose work is done
// keeps taking part until a round says that every rank is done, that one failed or that one
// received a stop signal. Every rank sees the same sequence of round results, so all stop after
// the same round.
#pragma once

#include <mpi.h>

#include <atomic>

namespace cs {

class FailureWatch {
 public:
  explicit FailureWatch(MPI_Comm comm);
  ~FailureWatch();
  FailureWatch(const FailureWatch&) = delete;
  FailureWatch& operator=(const FailureWatch&) = delete;

  // Thread-safe: this rank failed.
  void report_failure() { failed_here_ = true; }

  // Thread-safe: whether work should stop (this rank or, as far as known, another one failed or
  // received a stop signal).
  bool stop() const;

  // Main thread only, between blocks: completes a finished round and starts the next.
  void poll();

  // Main thread only, collective: this rank's work is over (done, or stopped); returns once all
  // ranks are done or one has failed.
  void finish();

 private:
  void start_round();
  bool round_complete(bool wait);  // true once the round's result is in
  MPI_Comm comm_ = MPI_COMM_NULL;
  MPI_Request request_ = MPI_REQUEST_NULL;
  int contribution_[3] = {0, 0, 0};  // failed here, still working, stop signal here
  int result_[3] = {0, 0, 0};
  bool working_ = true;
  bool over_ = false;  // a round said: all done, someone failed, or someone received a signal
  std::atomic<bool> failed_here_{false};
  std::atomic<bool> failed_anywhere_{false};
  std::atomic<bool> stopped_anywhere_{false};
};

}  // namespace cs
