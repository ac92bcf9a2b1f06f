// The pieces in which values travel between MPI ranks (ensembles/io/rank_pieces.hpp): at 10^10 orbits over
// 3 ranks each rank holds more values than an int counts, and every piece handed to MPI stays
// below 2^31 while the pieces cover every rank's values once, in order, at their place.
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "ensembles/io/rank_pieces.hpp"

namespace qmaps::ranks {
namespace {

// Each piece within an int and the limit, and the pieces, in order, cover each rank's values
// [0, counts[r]) once, at their place among all the ranks' values.
void expect_covering(const std::vector<std::int64_t>& counts, std::int64_t limit) {
  const auto all = pieces(counts, limit);
  std::int64_t at = 0;
  std::size_t k = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    for (std::int64_t from = 0; from < counts[r]; ++k) {
      ASSERT_LT(k, all.size());
      const Piece& p = all[k];
      EXPECT_EQ(p.rank, static_cast<int>(r));
      EXPECT_EQ(p.from, from);
      EXPECT_EQ(p.at, at + from);
      EXPECT_GE(p.count, 1);
      EXPECT_LE(p.count, limit);
      from += p.count;
      EXPECT_LE(from, counts[r]);
    }
    at += counts[r];
  }
  EXPECT_EQ(k, all.size());
}

TEST(RankPieces, TenToTheTenOrbitsOverThreeRanksTravelInPiecesBelowTwoToThe31) {
  const std::int64_t orbits = 10'000'000'000;
  const std::vector<std::int64_t> counts = {orbits - 2 * (orbits / 3), orbits / 3, orbits / 3};
  ASSERT_GT(counts[0], std::int64_t{1} << 31);
  expect_covering(counts, max_count);
  const auto all = pieces(counts);
  ASSERT_EQ(all.size(), 6u);  // two per rank: 2^31 - 1 values, then the rest
  EXPECT_EQ(all[0].count, max_count);
  EXPECT_EQ(all[1].count, counts[0] - max_count);
  EXPECT_EQ(all[2].at, counts[0]);
  EXPECT_EQ(all.back().at + all.back().count, orbits);
}

TEST(RankPieces, SmallCountsAreOnePiecePerRankAndEmptyRanksNone) {
  const auto all = pieces(std::vector<std::int64_t>{3, 0, 5});
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].rank, 0);
  EXPECT_EQ(all[0].count, 3);
  EXPECT_EQ(all[1].rank, 2);
  EXPECT_EQ(all[1].at, 3);
  EXPECT_EQ(all[1].count, 5);
  expect_covering({7, 1, 0, 12, 4}, 3);
  expect_covering({std::int64_t{1} << 33}, std::int64_t{1} << 28);
  EXPECT_TRUE(pieces(std::vector<std::int64_t>{}).empty());
}

TEST(RankPieces, ALimitOutsideAnIntOrANegativeCountIsRefused) {
  EXPECT_THROW(pieces(std::vector<std::int64_t>{1}, 0), std::invalid_argument);
  EXPECT_THROW(pieces(std::vector<std::int64_t>{1}, max_count + 1), std::invalid_argument);
  EXPECT_THROW(pieces(std::vector<std::int64_t>{-1}), std::invalid_argument);
}

}  // namespace
}  // namespace qmaps::ranks
