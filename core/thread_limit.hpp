#pragma once
// The OpenMP threads a run may use, checked before any work so that no thread creation fails
// later (libgomp ends the process on one): 1 to max_threads, fewer than the user's process limit
// (RLIMIT_NPROC, `ulimit -u`, which counts threads), and as many as this process can start now,
// each with the stack OpenMP gives its threads (OMP_STACKSIZE, else the system's default): the
// address-space limit and the cgroup's pids.max bound them too.
#include <string>

namespace qmaps {

constexpr int max_threads = 1024;

// The team for a request (0: every core OpenMP offers), or a usage error naming `who` (e.g.
// "--threads 5000") and the limit that refuses it.
int checked_threads(long long requested, const std::string& who);

// The address space a new thread takes beyond the heap it allocates: its stack. (The C library's
// heap arena for a thread is a reserve it does without when the address space is short.)
double bytes_per_thread();

}  // namespace qmaps
