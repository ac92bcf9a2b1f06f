#pragma once
// The processes that advance one run and write its one file together: this process alone (qmaps),
// or the ranks of MPI_COMM_WORLD (qmaps-mpi, docs/scaling.md). Rank r of n runs the orbit range
// of shard r + 1 of n. Every call but rank(), count() and root() is collective: every rank makes
// it, in the same order. Alone, each is the identity.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace qmaps::ranks {

int rank();
int count();
inline bool root() { return rank() == 0; }

// The values of every rank added exactly (in place), on every rank.
void sum(std::span<std::int64_t> values);
std::int64_t sum(std::int64_t value);
// The sum over the ranks before this one (an exclusive scan).
std::int64_t before(std::int64_t value);
std::int64_t max(std::int64_t value);
double min(double value);
double max(double value);
// Rank 0's value, on every rank.
std::string from_root(const std::string& value);
// Rank 0's bytes, into `bytes` on every rank (as many on each).
void from_root(std::span<std::byte> bytes);
// Every rank's values, one after another in rank order, on every rank.
std::vector<double> gathered(std::span<const double> values);
std::vector<std::string> gathered(const std::string& value);

// Every rank's outcome of a step that may fail on some ranks alone (a configuration, a path):
// `failure` is this rank's message ("" for none). If any rank failed, every rank returns the
// failure of the lowest one, "rank r: message" where there are several ranks; else "".
struct Failure {
  int code = 0;
  std::string message;
};
Failure first_failure(const Failure& mine);
// The error every rank raises alike after first_failure: each rank ends with it, and none before
// the root has reported it (barrier), so that mpirun, which ends the job as the first rank exits,
// never cuts the report short.
class FailedOnEveryRank : public Error {
 public:
  using Error::Error;
};
// Returns once every rank has called it.
void barrier();

// Ends every rank now with `code`, for a failure inside a collective step (where the other ranks
// cannot be told); alone, exits.
[[noreturn]] void abort(int code);

}  // namespace qmaps::ranks
