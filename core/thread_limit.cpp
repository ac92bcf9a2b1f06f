#include "core/thread_limit.hpp"

#include <omp.h>
#include <pthread.h>
#include <sys/resource.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <latch>
#include <mutex>
#include <utility>
#include <vector>

#include "core/error.hpp"

namespace qmaps {
namespace {

// The stack libgomp gives its threads: OMP_STACKSIZE (or GOMP_STACKSIZE), a size with an optional
// B, K, M or G (K when none); 0 when unset or not a size (libgomp then takes the default too).
std::size_t omp_stack_size() {
  const char* text = std::getenv("OMP_STACKSIZE");
  if (!text) text = std::getenv("GOMP_STACKSIZE");
  if (!text) return 0;
  char* end = nullptr;
  const unsigned long long n = std::strtoull(text, &end, 10);
  if (end == text) return 0;
  while (*end == ' ') ++end;
  std::size_t unit = 1024;
  switch (*end) {
    case 'b': case 'B': unit = 1, ++end; break;
    case 'k': case 'K': unit = 1024, ++end; break;
    case 'm': case 'M': unit = 1024 * 1024, ++end; break;
    case 'g': case 'G': unit = 1024 * 1024 * 1024, ++end; break;
    default: break;
  }
  while (*end == ' ') ++end;
  return *end == '\0' ? static_cast<std::size_t>(n) * unit : 0;
}

// The threads, beside this one, that could be started and held together now (at most `wanted`),
// and the error of the first that could not (0 if none failed).
std::pair<int, int> startable_threads(int wanted) {
  pthread_attr_t attr;
  pthread_getattr_default_np(&attr);
  if (const std::size_t stack = omp_stack_size(); stack > 0) pthread_attr_setstacksize(&attr, stack);
  std::latch gate(1);
  std::vector<pthread_t> started;
  int failure = 0;
  for (int k = 0; k < wanted && failure == 0; ++k) {
    pthread_t t;
    failure = pthread_create(
        &t, &attr,
        [](void* g) -> void* {
          static_cast<std::latch*>(g)->wait();
          return nullptr;
        },
        &gate);
    if (failure == 0) started.push_back(t);
  }
  gate.count_down();
  for (pthread_t t : started) pthread_join(t, nullptr);
  pthread_attr_destroy(&attr);
  return {static_cast<int>(started.size()), failure};
}

}  // namespace

int checked_threads(long long requested, const std::string& who) {
  if (requested < 0 || requested > max_threads)
    throw usage_error(who + ": the threads must be 1 to " + std::to_string(max_threads) +
                      " (0 or none: every core)");
  const int team = requested > 0 ? static_cast<int>(requested) : omp_get_max_threads();
  rlimit nproc{};
  if (getrlimit(RLIMIT_NPROC, &nproc) == 0 && nproc.rlim_cur != RLIM_INFINITY &&
      static_cast<unsigned long long>(team) > nproc.rlim_cur)
    throw usage_error(who + ": " + std::to_string(team) + " threads pass the limit of " +
                      std::to_string(nproc.rlim_cur) +
                      " processes and threads of this user (ulimit -u); use fewer threads");
  // A team once started is not probed again (a sweep checks each point's run): only a larger one.
  static std::mutex mutex;
  static int proven = 1;
  const std::lock_guard lock(mutex);
  if (team <= proven) return team;
  const auto [started, failure] = startable_threads(team - 1);
  if (failure == 0) proven = team;
  if (failure != 0)
    throw usage_error(who + ": " + std::to_string(team) + " threads cannot be started: only " +
                      std::to_string(started + 1) + " could (" + std::strerror(failure) +
                      "; the limits on processes (ulimit -u), on memory (ulimit -v) or the "
                      "cgroup's pids.max); use fewer threads");
  return team;
}

double bytes_per_thread() {
  pthread_attr_t attr;
  std::size_t stack = 8 << 20;
  if (pthread_getattr_default_np(&attr) == 0) {
    pthread_attr_getstacksize(&attr, &stack);
    pthread_attr_destroy(&attr);
  }
  if (const std::size_t omp = omp_stack_size(); omp > 0) stack = omp;
  return static_cast<double>(stack);
}

}  // namespace qmaps
