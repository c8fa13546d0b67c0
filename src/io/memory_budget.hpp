// How much memory a run may use: the smallest of the memory the machine has free, the cgroup
// limit the job runs under (Slurm and containers set one; the free memory of a big shared node
// says nothing about it) and CONTACTSWEEP_MEMORY_LIMIT when set. Runs that need more are refused
// before anything is allocated (spec_parser.cpp for the grid's coordinates, sweep.cpp for the
// results).
#pragma once

namespace cs {

// Bytes. CONTACTSWEEP_MEMORY_LIMIT is a whole number of bytes with an optional binary suffix
// K, M, G or T (e.g. 8G); a malformed value is an InputError naming it.
double memory_budget_bytes();

}  // namespace cs
