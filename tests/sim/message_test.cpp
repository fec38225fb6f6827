// Messages kept compactly (sim/message.cpp): each reads back as it was added, a list taken back
// to its first n drops the words of the rest, and a list holds no more than the words used.
#include "sim/message.h"

#include <gtest/gtest.h>

#include <vector>

namespace dw::sim {
namespace {

std::vector<int64_t> words_of(const Message& m) { return {m.payload().begin(), m.payload().end()}; }

TEST(MessageList, EachMessageReadsBackAsAddedWhateverItsSize) {
  MessageList list;
  list.add(3, 4, 1, std::vector<int64_t>{7});
  list.add(5, 6, 0, std::vector<int64_t>{});
  list.add(8, 9, 2, std::vector<int64_t>{1, -2, 3, INT64_MIN, INT64_MAX, 6, 7, 8});
  ASSERT_EQ(list.size(), 3u);
  EXPECT_EQ(list[0].from, 3u);
  EXPECT_EQ(list[0].to, 4u);
  EXPECT_EQ(list[0].program, 1);
  EXPECT_EQ(words_of(list[0]), (std::vector<int64_t>{7}));
  EXPECT_EQ(list[1].size, 0);
  EXPECT_TRUE(list[1].payload().empty());
  EXPECT_EQ(words_of(list[2]), (std::vector<int64_t>{1, -2, 3, INT64_MIN, INT64_MAX, 6, 7, 8}));
  EXPECT_EQ(list[2][3], INT64_MIN);
  std::vector<ModuleId> senders;
  for (const Message& m : list) senders.push_back(m.from);
  EXPECT_EQ(senders, (std::vector<ModuleId>{3, 5, 8}));
  // A view of a part: the second and third.
  const Messages part = list.all().subspan(1, 2);
  ASSERT_EQ(part.size(), 2u);
  EXPECT_EQ(part.front().from, 5u);
  EXPECT_EQ(words_of(part[1]), words_of(list[2]));
}

// A call run again takes back what it sent (ModuleContext::take_back): the words go too, and what
// is added next reads back whole.
TEST(MessageList, KeepingTheFirstMessagesDropsTheWordsOfTheRest) {
  MessageList list;
  list.add(1, 2, 0, std::vector<int64_t>{10, 11});
  list.add(1, 3, 0, std::vector<int64_t>{20, 21, 22});
  list.add(1, 4, 0, std::vector<int64_t>{30});
  list.keep_first(1);
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list.words().size(), 2u);
  list.add(1, 5, 0, std::vector<int64_t>{40, 41});
  EXPECT_EQ(words_of(list[0]), (std::vector<int64_t>{10, 11}));
  EXPECT_EQ(words_of(list[1]), (std::vector<int64_t>{40, 41}));
  list.keep_first(5);  // more than it holds: nothing changes
  EXPECT_EQ(list.size(), 2u);
  list.keep_first(0);
  EXPECT_TRUE(list.empty());
  EXPECT_TRUE(list.words().empty());
}

// What the compact form is for: a one-word message costs its header and one word, a third of a
// fixed record of eight words.
TEST(MessageList, HoldsOnlyTheWordsUsed) {
  MessageList list;
  list.reserve(1000, 1000);
  for (ModuleId m = 0; m < 1000; ++m) list.add(m, m + 1, 0, std::vector<int64_t>{int64_t(m)});
  EXPECT_EQ(list.words().size(), 1000u);
  EXPECT_EQ(list.bytes(), 1000 * (sizeof(MessageHeader) + sizeof(int64_t)));
  EXPECT_EQ(sizeof(MessageHeader), 16u);
}

}  // namespace
}  // namespace dw::sim
