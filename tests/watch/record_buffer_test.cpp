#include "watch/record_buffer.h"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

namespace dw::watch {
namespace {

// A record of `bytes` whose header says so, its words after the header numbered from `first`.
std::vector<uint32_t> record(uint32_t bytes, uint32_t first) {
  std::vector<uint32_t> r(bytes / 4 + kCopyChunk);  // with the room copy_ids reads past the end
  r[0] = bytes << 8;
  for (uint32_t i = 1; i < bytes / 4; ++i) r[i] = first + i;
  return r;
}

TEST(RecordBuffer, ARecordReachesEachOfItsReceiversInOrder) {
  RecordBuffer buffer;
  const std::vector<uint32_t> a = record(12, 100), b = record(20, 200);
  const std::vector<uint32_t> to_a{7, 3, 9, 0, 0, 0, 0}, to_b{5, 0, 0, 0, 0};
  buffer.append({to_a.data(), 3}, reinterpret_cast<const std::byte*>(a.data()), 12);
  buffer.append({to_b.data(), 1}, reinterpret_cast<const std::byte*>(b.data()), 20);
  EXPECT_EQ(buffer.size(), (4 + 3 * 4 + 12) + (4 + 4 + 20)) << "each PatternMatcher is held once";

  std::vector<std::pair<uint32_t, uint32_t>> seen;  // receiver, the record's second word
  buffer.visit([&](uint32_t to, const std::byte* pm, uint32_t bytes) {
    uint32_t second;
    std::memcpy(&second, pm + 4, 4);
    seen.emplace_back(to, second);
    EXPECT_EQ(bytes, to == 5 ? 20u : 12u);
  });
  EXPECT_EQ(seen, (std::vector<std::pair<uint32_t, uint32_t>>{{7, 101}, {3, 101}, {9, 101}, {5, 201}}));

  std::vector<uint32_t> hinted, firsts;
  buffer.for_each([&](std::span<const uint32_t> to, const std::byte*) { firsts.push_back(to.front()); },
                  [&](uint32_t next) { hinted.push_back(next); });
  EXPECT_EQ(firsts, (std::vector<uint32_t>{7, 5}));
  EXPECT_EQ(hinted, (std::vector<uint32_t>{5})) << "the next record's first receiver, ahead of it";

  const RecordBuffer copy = buffer;  // a snapshot
  size_t receivers = 0;
  copy.visit([&](uint32_t, const std::byte*, uint32_t) { ++receivers; });
  EXPECT_EQ(receivers, 4u);
  buffer.clear();
  EXPECT_TRUE(buffer.empty());
}

}  // namespace
}  // namespace dw::watch
