// Delivering a step's program messages (docs/design.md §2, communicate): what the modules sent at
// step t goes into the inboxes they read at t + 1, grouped by receiver and then by program, each
// group in sender order and then in the order sent. That order is fixed by the module ids, never
// by which thread or which rank ran a sender.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "sim/block_placement.h"
#include "sim/message.h"

namespace dw::sim {

// A stable counting sort of message headers by (receiver, program) into a Mailbox, keeping its
// counts from one step to the next.
class MailboxSort {
 public:
  // Fills `box` for the modules this process holds (`placement`: its window, of which over ranks
  // only its own blocks' modules receive) with the messages of `own`, this process's outboxes in
  // module order of their senders (those to another rank's modules are left out: they travel in
  // the batches), then those of `arrived`, what the other ranks sent here (each in module order).
  // With messages from other ranks, each group is put in sender order. Returns how many messages
  // the box holds.
  uint64_t fill(Mailbox& box, const BlockPlacement& placement, uint32_t programs, std::span<const Messages> own,
                std::span<const Messages> arrived);

 private:
  std::vector<uint32_t> counts_;  // per group: where its next header goes
};

}  // namespace dw::sim
