#include "core/memory_limit.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>

#include <sys/resource.h>
#include <unistd.h>

#include "core/error.hpp"

namespace qmaps {
namespace {

// The address space this process has mapped now (/proc/self/statm's first field, in pages).
double mapped_bytes() {
  std::ifstream statm("/proc/self/statm");
  double pages = 0;
  statm >> pages;
  return pages * static_cast<double>(sysconf(_SC_PAGE_SIZE));
}

std::string gib(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", bytes / (1 << 30));
  return text;
}

}  // namespace

MemoryLimit memory_limit() {
  MemoryLimit limit{static_cast<double>(sysconf(_SC_PHYS_PAGES)) *
                        static_cast<double>(sysconf(_SC_PAGE_SIZE)),
                    "this machine's RAM"};
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
    // What the process has mapped already (its libraries, its heap) counts against the limit.
    const double mapped = mapped_bytes(), left = static_cast<double>(as.rlim_cur) - mapped;
    if (left < limit.bytes)
      limit = {std::max(left, 0.0),
               "the address-space limit (ulimit -v) of " + gib(static_cast<double>(as.rlim_cur)) +
                   " GiB, less the " + gib(mapped) + " GiB this process has mapped,"};
  }
  std::ifstream cgroup("/sys/fs/cgroup/memory.max");
  double max = 0;
  if (cgroup >> max && max > 0 && max < limit.bytes)  // "max" (no limit) does not parse
    limit = {max, "the cgroup's memory limit (memory.max)"};
  return limit;
}

void check_fits(double bytes, const std::string& where, const std::string& needs,
                const std::string& after) {
  const MemoryLimit have = memory_limit();
  if (bytes <= have.bytes) return;
  char text[200];
  std::snprintf(text, sizeof text, " need about %.3g GiB; %s is %.3g GiB", bytes / (1 << 30),
                have.what.c_str(), have.bytes / (1 << 30));
  throw usage_error(where + ": " + needs + text + after);
}

}  // namespace qmaps
