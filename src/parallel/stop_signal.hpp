// SIGTERM and SIGINT stop a run cleanly (the command line only: the Python module leaves the
// interpreter its own SIGINT). A batch system's time limit sends SIGTERM, then SIGKILL after a
// grace period (Slurm's KillWait, 30 s by default): on the first signal no thread of any rank
// starts another block, the blocks being computed are finished and saved in the journal, which
// stays for --resume, the temporary output is removed, and the program exits with 128 + the
// signal's number (parallel/sweep.cpp, cli/main.cpp). The handler only records the signal and
// restores the default action of both, so a second one ends the process at once.
#pragma once

namespace cs {

// Installs the handler for SIGTERM and SIGINT.
void install_stop_signal_handler();

// The first stop signal received (SIGTERM, SIGINT), or 0. Thread-safe, lock-free.
int stop_signal();

// "SIGTERM", "SIGINT".
const char* stop_signal_name(int signal);

}  // namespace cs
