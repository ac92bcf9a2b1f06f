#pragma once
// The pieces in which values travel between the ranks (ensembles/io/ranks_mpi.cpp). An MPI count is an
// int (OpenMPI 4 has no MPI-4 large-count calls), while a rank may hold more than 2^31 values
// (10^10 orbits over 3 ranks): every transfer goes as pieces of at most `limit` values, each sent
// by one rank into its place among all the ranks' values, so that no count nor offset handed to
// MPI passes an int. Pure arithmetic, tested without the memory (tests/ranks_test.cpp).
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

namespace qmaps::ranks {

// The largest count one MPI call takes.
inline constexpr std::int64_t max_count = std::numeric_limits<int>::max();

// Rank `rank`'s values [from, from + count) of its own, which go to [at, at + count) of all the
// ranks' values laid one after another in rank order.
struct Piece {
  int rank = 0;
  std::int64_t from = 0;
  std::int64_t at = 0;
  int count = 0;
};

// The pieces of every rank's values, counts[r] of rank r, rank after rank, none longer than
// `limit` (1 <= limit <= max_count); no piece for a rank without values.
inline std::vector<Piece> pieces(std::span<const std::int64_t> counts,
                                 std::int64_t limit = max_count) {
  if (limit < 1 || limit > max_count) throw std::invalid_argument("a piece's limit out of range");
  std::vector<Piece> out;
  std::int64_t at = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    if (counts[r] < 0) throw std::invalid_argument("a rank's count is negative");
    for (std::int64_t from = 0; from < counts[r]; from += limit) {
      const std::int64_t n = counts[r] - from < limit ? counts[r] - from : limit;
      out.push_back({static_cast<int>(r), from, at + from, static_cast<int>(n)});
    }
    at += counts[r];
  }
  return out;
}

}  // namespace qmaps::ranks
