#pragma once
// The memory a run may use: the least of the machine's RAM, what the address-space limit
// (RLIMIT_AS, `ulimit -v`) leaves beside what the process has mapped already, and the cgroup's
// memory.max, where they are set. Sizes are checked against it before anything is allocated.
#include <string>

namespace qmaps {

struct MemoryLimit {
  double bytes;
  std::string what;  // "this machine's RAM", "the address-space limit (ulimit -v)", …
};

MemoryLimit memory_limit();

// Refuses (a usage error) work that needs more than memory_limit(): "<where>: <needs> need about
// X GiB; <the limit> is Y GiB<after>", where `needs` says what needs `bytes` (e.g. "1000
// orbits") and `after` may say how it divides, or what to do.
void check_fits(double bytes, const std::string& where, const std::string& needs,
                const std::string& after = "");

}  // namespace qmaps
