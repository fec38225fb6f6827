// Delivering a step's messages (sim/mailbox.cpp, docs/design.md §2): each inbox groups its messages
// by program, in sender order, a sender's in the order sent, whichever thread or rank ran the
// sender; over ranks, messages to another rank's modules are left to the batches.
#include "sim/mailbox.h"

#include <gtest/gtest.h>

#include "tests/sim/placed_ranks.h"

namespace dw::sim {
namespace {

std::unique_ptr<Model> line(uint32_t n) {
  return std::get<std::unique_ptr<Model>>(build_model(make_lattice({LatticeKind::Line, {n, 1, 1}}), {}, {}, 1));
}

// (sender, first word) of each message of an inbox, in its order.
std::vector<std::pair<ModuleId, int64_t>> read(Messages inbox) {
  std::vector<std::pair<ModuleId, int64_t>> seen;
  for (const Message m : inbox) seen.push_back({m.from, m.size ? m[0] : -1});
  return seen;
}

using Seen = std::vector<std::pair<ModuleId, int64_t>>;

TEST(MailboxSort, GroupsByReceiverAndProgramInSenderOrder) {
  const auto model = line(4);
  const BlockPlacement alone(*model, 2, nullptr, Partition::Blocks, false);
  // Two threads' outboxes, each in its modules' order (0 and 1, then 2 and 3).
  MessageList first, second;
  first.add(0, 2, 1, std::vector<int64_t>{10});
  first.add(0, 1, 0, std::vector<int64_t>{11, 12});
  first.add(0, 1, 0, std::vector<int64_t>{17});
  first.add(1, 2, 0, std::vector<int64_t>{13});
  second.add(2, 1, 0, std::vector<int64_t>{14});
  second.add(3, 2, 1, std::vector<int64_t>{15});
  second.add(3, 2, 0, std::vector<int64_t>{});
  const std::vector<Messages> own{first.all(), second.all()};
  Mailbox box;
  MailboxSort sort;
  EXPECT_EQ(sort.fill(box, alone, 2, own, {}), 7u);
  EXPECT_EQ(box.begin.size(), 4u * 2 + 1);
  EXPECT_TRUE(box.of(0, 0, 2).empty());
  EXPECT_EQ(read(box.of(1, 0, 2)), (Seen{{0, 11}, {0, 17}, {2, 14}}));
  EXPECT_TRUE(box.of(1, 1, 2).empty());
  EXPECT_EQ(read(box.of(2, 0, 2)), (Seen{{1, 13}, {3, -1}}));
  EXPECT_EQ(read(box.of(2, 1, 2)), (Seen{{0, 10}, {3, 15}}));
  // Each message keeps its own words, wherever its header went.
  const Message two = box.of(1, 0, 2)[0];
  EXPECT_EQ(std::vector<int64_t>(two.payload().begin(), two.payload().end()), (std::vector<int64_t>{11, 12}));
  // A step with nothing sent leaves every inbox empty.
  EXPECT_EQ(sort.fill(box, alone, 2, {}, {}), 0u);
  EXPECT_EQ(box.begin, std::vector<uint32_t>(9, 0));
  EXPECT_TRUE(box.messages.empty());
}

// Rank 0 of two holds the second block (modules 8..15), rank 1 the first: a message from rank 1's
// module 7 comes in after rank 0's own, and goes before them in the inbox. Rank 0's message to
// module 7 is rank 1's to deliver.
TEST(MailboxSort, OverRanksMessagesFromOtherRanksTakeTheirSendersPlace) {
  const auto model = line(16);
  PlacedRanks zero(0, 2, {1, 0});
  const BlockPlacement p(*model, 1, &zero, Partition::Graph, false);
  ASSERT_EQ(p.first_module(), 8u);
  MessageList sent, arrived;
  sent.add(8, 7, 0, std::vector<int64_t>{1});
  sent.add(9, 8, 0, std::vector<int64_t>{2});
  arrived.add(7, 8, 0, std::vector<int64_t>{3});
  const std::vector<Messages> own{sent.all()}, from_ranks{Messages{}, arrived.all()};
  Mailbox box;
  MailboxSort sort;
  EXPECT_EQ(sort.fill(box, p, 1, own, from_ranks), 2u);
  EXPECT_EQ(box.begin.size(), 8u + 1);
  EXPECT_EQ(read(box.of(0, 0, 1)), (Seen{{7, 3}, {9, 2}}));  // module 8's inbox
  EXPECT_EQ(box.messages.size(), 2u);
}

}  // namespace
}  // namespace dw::sim
