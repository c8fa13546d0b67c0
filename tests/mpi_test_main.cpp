// GoogleTest main for tests that run under mpirun: every rank runs every test, rank 0 alone
// prints. A test that fails on another rank only still fails the run: the exit status is agreed
// across ranks, and rank 0 says so. Set CONTACTSWEEP_TEST_ALL_RANKS=1 to see every rank's report
// when chasing such a failure.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdio>
#include <cstdlib>
#include <string_view>

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);

  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const char* all_ranks = std::getenv("CONTACTSWEEP_TEST_ALL_RANKS");
  const bool quiet = rank != 0 && !(all_ranks != nullptr && std::string_view(all_ranks) == "1");
  if (quiet) {
    ::testing::TestEventListeners& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
    delete listeners.Release(listeners.default_xml_generator());
  }

  const int local_failed = RUN_ALL_TESTS() != 0 ? 1 : 0;
  int failed_ranks = 0;
  MPI_Allreduce(&local_failed, &failed_ranks, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  if (rank == 0 && failed_ranks > local_failed) {
    std::fprintf(stderr,
                 "[  FAILED  ] %d other rank(s) failed; rerun with CONTACTSWEEP_TEST_ALL_RANKS=1\n",
                 failed_ranks - local_failed);
  }
  MPI_Finalize();
  return failed_ranks > 0 ? 1 : 0;
}
