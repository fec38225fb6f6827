#include "sim/mailbox.h"

#include <algorithm>
#include <stdexcept>

namespace dw::sim {

uint64_t MailboxSort::fill(Mailbox& box, const BlockPlacement& placement, uint32_t programs,
                           std::span<const Messages> own, std::span<const Messages> arrived) {
  const uint32_t first = placement.first_module();
  const size_t groups = size_t{placement.module_window()} * programs;
  // The messages to this process's modules: its own (in thread order, which is module order), then
  // those of every other rank (each in module order).
  auto each = [&](auto&& fn) {
    for (const Messages part : own)
      for (const Message m : part)
        if (placement.holds(m.to)) fn(m);
    for (const Messages part : arrived)
      for (const Message m : part) fn(m);
  };
  box.begin.assign(groups + 1, 0);
  std::vector<MessageHeader>& headers = box.messages.headers();
  std::vector<int64_t>& words = box.messages.words();
  words.clear();
  // A stable counting sort of the headers by (receiver, program): senders stay in id order within
  // a group. The words go in the order the messages come.
  uint64_t total = 0;
  size_t word_count = 0;
  each([&](const Message& m) {
    ++box.begin[size_t{m.to - first} * programs + m.program + 1];
    ++total;
    word_count += m.size;
  });
  headers.resize(total);
  if (total == 0) return 0;
  if (word_count > UINT32_MAX) throw std::length_error("more message words in one step than a mailbox indexes");
  words.reserve(word_count);
  for (size_t g = 0; g < groups; ++g) box.begin[g + 1] += box.begin[g];
  counts_.assign(box.begin.begin(), box.begin.end() - 1);
  each([&](const Message& m) {
    headers[counts_[size_t{m.to - first} * programs + m.program]++] = {m.from, m.to, m.program, m.size,
                                                                       static_cast<uint32_t>(words.size())};
    words.insert(words.end(), m.words, m.words + m.size);
  });
  if (!arrived.empty())  // other ranks' senders come after this one's: a group holds a few
    for (size_t g = 0; g < groups; ++g)
      if (box.begin[g + 1] - box.begin[g] > 1)
        std::stable_sort(headers.begin() + box.begin[g], headers.begin() + box.begin[g + 1],
                         [](const MessageHeader& a, const MessageHeader& b) { return a.from < b.from; });
  return total;
}

}  // namespace dw::sim
