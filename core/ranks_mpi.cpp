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

namespace {

// Every rank's `count` values of `type` from `values`, one after another in rank order, on every
// rank; sizes[r] is rank r's count.
template <class T>
std::vector<T> all_of(const T* values, int count, MPI_Datatype type, std::vector<int>& sizes) {
  const int n = ranks::count();
  sizes.assign(static_cast<std::size_t>(n), 0);
  MPI_Allgather(&count, 1, MPI_INT, sizes.data(), 1, MPI_INT, MPI_COMM_WORLD);
  std::vector<int> offsets(static_cast<std::size_t>(n));
  int total = 0;
  for (std::size_t r = 0; r < sizes.size(); ++r) {
    offsets[r] = total;
    total += sizes[r];
  }
  std::vector<T> out(static_cast<std::size_t>(total));
  MPI_Allgatherv(values, count, type, out.data(), sizes.data(), offsets.data(), type,
                 MPI_COMM_WORLD);
  return out;
}

}  // namespace

std::vector<double> gathered(std::span<const double> values) {
  std::vector<int> sizes;
  return all_of(values.data(), static_cast<int>(values.size()), MPI_DOUBLE, sizes);
}

std::vector<std::string> gathered(const std::string& value) {
  std::vector<int> sizes;
  const auto chars = all_of(value.data(), static_cast<int>(value.size()), MPI_CHAR, sizes);
  std::vector<std::string> out;
  std::size_t at = 0;
  for (const int size : sizes) {
    out.emplace_back(chars.data() + at, static_cast<std::size_t>(size));
    at += static_cast<std::size_t>(size);
  }
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
