// The ranks of MPI_COMM_WORLD: qmaps-mpi.
#include <mpi.h>

#include <algorithm>
#include <cstdlib>

#include "core/ranks.hpp"

namespace qmaps::ranks {
namespace {

int of(int (*query)(MPI_Comm, int*)) {
  int value = 0;
  query(MPI_COMM_WORLD, &value);
  return value;
}

template <class T>
T reduced(T value, MPI_Datatype type, MPI_Op op) {
  T out{};
  MPI_Allreduce(&value, &out, 1, type, op, MPI_COMM_WORLD);
  return out;
}

// Rank `from`'s bytes, on every rank.
std::string broadcast(std::string value, int from) {
  long long size = static_cast<long long>(value.size());
  MPI_Bcast(&size, 1, MPI_LONG_LONG, from, MPI_COMM_WORLD);
  value.resize(static_cast<std::size_t>(size));
  MPI_Bcast(value.data(), static_cast<int>(size), MPI_CHAR, from, MPI_COMM_WORLD);
  return value;
}

}  // namespace

int rank() { return of(MPI_Comm_rank); }
int count() { return of(MPI_Comm_size); }

void sum(std::span<std::int64_t> values) {
  // In pieces of at most 2^28 values: MPI counts are ints.
  for (std::size_t at = 0; at < values.size(); at += std::size_t{1} << 28) {
    const auto n = static_cast<int>(std::min<std::size_t>(values.size() - at, std::size_t{1} << 28));
    MPI_Allreduce(MPI_IN_PLACE, values.data() + at, n, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  }
}

std::int64_t sum(std::int64_t value) { return reduced(value, MPI_INT64_T, MPI_SUM); }

std::int64_t before(std::int64_t value) {
  std::int64_t out = 0;
  MPI_Exscan(&value, &out, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  return rank() == 0 ? 0 : out;  // rank 0's is undefined
}

std::int64_t max(std::int64_t value) { return reduced(value, MPI_INT64_T, MPI_MAX); }
double min(double value) { return reduced(value, MPI_DOUBLE, MPI_MIN); }
double max(double value) { return reduced(value, MPI_DOUBLE, MPI_MAX); }

std::string from_root(const std::string& value) { return broadcast(value, 0); }

void from_root(std::span<std::byte> bytes) {
  MPI_Bcast(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, 0, MPI_COMM_WORLD);
}

std::vector<double> gathered(std::span<const double> values) {
  const int n = count();
  const int mine = static_cast<int>(values.size());
  std::vector<int> sizes(static_cast<std::size_t>(n)), offsets(static_cast<std::size_t>(n));
  MPI_Allgather(&mine, 1, MPI_INT, sizes.data(), 1, MPI_INT, MPI_COMM_WORLD);
  int total = 0;
  for (int r = 0; r < n; ++r) {
    offsets[static_cast<std::size_t>(r)] = total;
    total += sizes[static_cast<std::size_t>(r)];
  }
  std::vector<double> out(static_cast<std::size_t>(total));
  MPI_Allgatherv(values.data(), mine, MPI_DOUBLE, out.data(), sizes.data(), offsets.data(),
                 MPI_DOUBLE, MPI_COMM_WORLD);
  return out;
}

std::vector<std::string> gathered(const std::string& value) {
  std::vector<std::string> out;
  for (int r = 0; r < count(); ++r) out.push_back(broadcast(value, r));
  return out;
}

Failure first_failure(const Failure& mine) {
  const int failing = reduced(mine.code != 0 ? rank() : count(), MPI_INT, MPI_MIN);
  if (failing == count()) return {};
  Failure first;
  first.code = mine.code;
  MPI_Bcast(&first.code, 1, MPI_INT, failing, MPI_COMM_WORLD);
  first.message = "rank " + std::to_string(failing) + ": " + broadcast(mine.message, failing);
  return first;
}

void abort(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);
}

}  // namespace qmaps::ranks
