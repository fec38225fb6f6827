// What is built on the ranks' collectives (sim/rank_exchange.h).
#include "sim/rank_exchange.h"

#include <gtest/gtest.h>

#include <numeric>
#include <vector>

#include "tests/sim/thread_ranks.h"

namespace dw::sim {
namespace {

// Rank r's records: r * 3 + 1 of them (one rank none), numbered so that their order shows.
std::vector<uint64_t> records_of_rank(int r) {
  std::vector<uint64_t> records(r == 2 ? 0 : size_t(r) * 3 + 1);
  std::iota(records.begin(), records.end(), uint64_t(r) * 1000);
  return records;
}

TEST(AllGatherInto, AppendsEveryRanksRecordsInRankOrderInRoundsOfBoundedSize) {
  for (const int ranks : {1, 2, 4}) {
    std::vector<uint64_t> expected{7, 8};
    for (int r = 0; r < ranks; ++r) {
      const auto theirs = records_of_rank(r);
      expected.insert(expected.end(), theirs.begin(), theirs.end());
    }
    const auto seen = on_ranks(ranks, [&](RankExchange& rank) {
      CountedGathers counted(rank);
      std::vector<uint64_t> into{7, 8};
      const std::vector<uint64_t> mine = records_of_rank(rank.rank());
      // Rounds of two records: the largest rank's ten take five, besides the gather of counts.
      all_gather_into<uint64_t>(counted, mine, into, 5, 2 * sizeof(uint64_t));
      return std::tuple(into, into.capacity(), counted.gathers, counted.largest);
    });
    const size_t most = records_of_rank(ranks - 1).size();
    for (const auto& [into, capacity, gathers, largest] : seen) {
      EXPECT_EQ(into, expected) << ranks << " ranks";
      EXPECT_GE(capacity, expected.size() + 5) << "room for five more";
      EXPECT_EQ(gathers, 1 + (most + 1) / 2) << ranks << " ranks";
      EXPECT_LE(largest, 2 * sizeof(uint64_t)) << "no round carries more than its bytes";
    }
  }
}

}  // namespace
}  // namespace dw::sim
