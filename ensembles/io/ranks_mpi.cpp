// The ranks of MPI_COMM_WORLD: qmaps-mpi.
#include <mpi.h>

#include <algorithm>
#include <cstdlib>

#include "ensembles/io/rank_pieces.hpp"
#include "ensembles/io/ranks.hpp"

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

// The values of every rank, counts[r] of rank r laid one after another in rank order in `data`
// (each rank's own already in place), on every rank: each rank sends its own, piece by piece.
template <class T>
void share(T* data, std::span<const std::int64_t> counts, MPI_Datatype type) {
  for (const Piece& p : pieces(counts))
    MPI_Bcast(data + p.at, p.count, type, p.rank, MPI_COMM_WORLD);
}

// `count` values of rank `from` at `data`, on every rank.
template <class T>
void share_from(int from, T* data, std::size_t count, MPI_Datatype type) {
  std::vector<std::int64_t> counts(static_cast<std::size_t>(ranks::count()), 0);
  counts[static_cast<std::size_t>(from)] = static_cast<std::int64_t>(count);
  share(data, std::span<const std::int64_t>(counts), type);
}

// Rank `from`'s bytes, on every rank.
std::string broadcast(std::string value, int from) {
  long long size = static_cast<long long>(value.size());
  MPI_Bcast(&size, 1, MPI_LONG_LONG, from, MPI_COMM_WORLD);
  value.resize(static_cast<std::size_t>(size));
  share_from(from, value.data(), value.size(), MPI_CHAR);
  return value;
}

}  // namespace

int rank() { return of(MPI_Comm_rank); }
int count() { return of(MPI_Comm_size); }

void sum(std::span<std::int64_t> values) {
  // In pieces of at most 2^28 values (2 GiB, the most MPI's own buffers then take).
  const std::int64_t size = static_cast<std::int64_t>(values.size());
  for (const Piece& p : pieces(std::span(&size, 1), std::int64_t{1} << 28))
    MPI_Allreduce(MPI_IN_PLACE, values.data() + p.at, p.count, MPI_INT64_T, MPI_SUM,
                  MPI_COMM_WORLD);
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

void from_root(std::span<std::byte> bytes) { share_from(0, bytes.data(), bytes.size(), MPI_BYTE); }

namespace {

// Every rank's values, one after another in rank order, on every rank; sizes[r] is rank r's count.
template <class T>
std::vector<T> all_of(std::span<const T> values, MPI_Datatype type,
                      std::vector<std::int64_t>& sizes) {
  sizes.assign(static_cast<std::size_t>(ranks::count()), 0);
  const auto mine = static_cast<std::int64_t>(values.size());
  MPI_Allgather(&mine, 1, MPI_INT64_T, sizes.data(), 1, MPI_INT64_T, MPI_COMM_WORLD);
  std::int64_t total = 0, at = 0;
  for (std::size_t r = 0; r < sizes.size(); ++r) {
    if (static_cast<int>(r) == rank()) at = total;
    total += sizes[r];
  }
  std::vector<T> out(static_cast<std::size_t>(total));
  std::copy(values.begin(), values.end(), out.begin() + at);
  share(out.data(), std::span<const std::int64_t>(sizes), type);
  return out;
}

}  // namespace

std::vector<double> gathered(std::span<const double> values) {
  std::vector<std::int64_t> sizes;
  return all_of(values, MPI_DOUBLE, sizes);
}

std::vector<std::string> gathered(const std::string& value) {
  std::vector<std::int64_t> sizes;
  const auto chars = all_of(std::span<const char>(value), MPI_CHAR, sizes);
  std::vector<std::string> out;
  std::size_t at = 0;
  for (const std::int64_t size : sizes) {
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

void barrier() { MPI_Barrier(MPI_COMM_WORLD); }

void abort(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);
}

}  // namespace qmaps::ranks
