#include "core/memory_limit.hpp"

#include <fstream>

#include <sys/resource.h>
#include <unistd.h>

namespace qmaps {

MemoryLimit memory_limit() {
  MemoryLimit limit{static_cast<double>(sysconf(_SC_PHYS_PAGES)) *
                        static_cast<double>(sysconf(_SC_PAGE_SIZE)),
                    "this machine's RAM"};
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY &&
      static_cast<double>(as.rlim_cur) < limit.bytes)
    limit = {static_cast<double>(as.rlim_cur), "the address-space limit (ulimit -v)"};
  std::ifstream cgroup("/sys/fs/cgroup/memory.max");
  double max = 0;
  if (cgroup >> max && max > 0 && max < limit.bytes)  // "max" (no limit) does not parse
    limit = {max, "the cgroup's memory limit (memory.max)"};
  return limit;
}

}  // namespace qmaps
