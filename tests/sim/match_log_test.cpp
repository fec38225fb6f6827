#include "sim/match_log.h"

#include <gtest/gtest.h>

#include <sstream>

namespace dw::sim {
namespace {

TEST(MatchLog, SortsByStepThenWatchThenSlotIds) {
  std::ostringstream out;
  MatchLog log({{"late", {"a", "b"}}, {"early", {"x"}}}, &out);
  auto late = log.sink(0), early = log.sink(1);
  const std::vector<watch::ModuleId> l0 = {5, 1, 2, 9, 2, 3};
  late(0, l0, {});
  early(0, std::vector<watch::ModuleId>{7}, {});
  early(1, std::vector<watch::ModuleId>{4, 3}, {});
  log.release(0);
  EXPECT_EQ(out.str(),
            "{\"watch\":\"late\",\"t\":0,\"slots\":{\"a\":2,\"b\":3}}\n"
            "{\"watch\":\"late\",\"t\":0,\"slots\":{\"a\":2,\"b\":9}}\n"
            "{\"watch\":\"late\",\"t\":0,\"slots\":{\"a\":5,\"b\":1}}\n"
            "{\"watch\":\"early\",\"t\":0,\"slots\":{\"x\":7}}\n");
  log.finish();
  EXPECT_NE(
      out.str().find(
          "{\"watch\":\"early\",\"t\":1,\"slots\":{\"x\":3}}\n{\"watch\":\"early\",\"t\":1,\"slots\":{\"x\":4}}\n"),
      std::string::npos);
  EXPECT_EQ(log.count(0), 3u);
  EXPECT_EQ(log.count(1), 3u);
}

TEST(MatchLog, SortsGroupsTooWideToPack) {
  // Three 32-bit ids do not fit in one 64-bit key: the general sort takes over.
  std::ostringstream out;
  MatchLog log({{"w", {"a", "b", "c"}}}, &out);
  const std::vector<watch::ModuleId> ids = {4000000000u, 1, 2, 7, 4000000000u, 3, 7, 9, 1};
  log.sink(0)(0, ids, {});
  log.finish();
  EXPECT_EQ(out.str(),
            "{\"watch\":\"w\",\"t\":0,\"slots\":{\"a\":7,\"b\":9,\"c\":1}}\n"
            "{\"watch\":\"w\",\"t\":0,\"slots\":{\"a\":7,\"b\":4000000000,\"c\":3}}\n"
            "{\"watch\":\"w\",\"t\":0,\"slots\":{\"a\":4000000000,\"b\":1,\"c\":2}}\n");
}

TEST(MatchLog, EscapesNamesAsJson) {
  std::ostringstream out;
  MatchLog log({{"a \"quoted\" name", {"s"}}}, &out);
  log.sink(0)(3, std::vector<watch::ModuleId>{1}, {});
  log.finish();
  EXPECT_EQ(out.str(), "{\"watch\":\"a \\\"quoted\\\" name\",\"t\":3,\"slots\":{\"s\":1}}\n");
}

// A name that is not UTF-8 (a trace's header may hold any bytes) is written with U+FFFD for its
// bad bytes: the log never throws in the middle of a run's outputs (issue 62).
TEST(MatchLog, WritesBytesThatAreNotUtf8AsReplacementCharacters) {
  std::ostringstream out;
  MatchLog log({{"w\xff", {"s\xff"}}}, &out);
  log.sink(0)(3, std::vector<watch::ModuleId>{1}, {});
  log.finish();
  log.write_counted("c\xff", 2);
  EXPECT_EQ(out.str(),
            "{\"watch\":\"w\xef\xbf\xbd\",\"t\":3,\"slots\":{\"s\xef\xbf\xbd\":1}}\n"
            "{\"watch\":\"c\xef\xbf\xbd\",\"counted\":2}\n");
}

TEST(MatchLog, KeepsTheFirstMatchesForSummariesWithoutWriting) {
  MatchLog log({{"w", {"a"}}}, nullptr, 2);
  log.sink(0)(4, std::vector<watch::ModuleId>{9, 3, 5}, {});
  log.finish();
  ASSERT_EQ(log.kept(0).size(), 2u);
  EXPECT_EQ(log.kept(0)[0].ids, (std::vector<watch::ModuleId>{3}));
  EXPECT_EQ(log.kept(0)[1].ids, (std::vector<watch::ModuleId>{5}));
  EXPECT_EQ(log.count(0), 3u);
}

}  // namespace
}  // namespace dw::sim
