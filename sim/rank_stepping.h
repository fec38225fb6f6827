// Stepping over ranks (docs/design.md §12): what crosses between the ranks as a step runs. A rank
// runs first its blocks that may send to another rank (the border blocks); their program messages
// and PatternMatchers go to the other ranks in one batch per rank, and travel while the interior
// blocks run; then what the other ranks sent is opened, for the inboxes (MailboxSort) and the
// agents (WatchHosting). A program's failure and the actuations for the world, which every rank
// keeps whole, are agreed on by all.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "sim/actuation.h"
#include "sim/block_placement.h"
#include "sim/host_program.h"
#include "sim/message.h"
#include "sim/rank_exchange.h"
#include "sim/state.h"
#include "sim/watch_hosting.h"

namespace dw::sim {

class RankStepping {
 public:
  // `ranks` and `placement` must outlive it; `threads` are this rank's.
  RankStepping(RankExchange& ranks, const BlockPlacement& placement, unsigned threads);

  // This step's own blocks that may send to another rank, and the others (interior). A block may
  // send to another rank when one of its modules has a neighbour there: in N(m, t), along which
  // the programs send, or in N(m, t - E+) of a watch whose agents run, along which they send
  // (DistributedAgents::fill_and_spread). Worked out once per graph: a static lattice's once for
  // the run.
  void split_blocks(const State& state, const WatchHosting& hosting);
  std::span<const uint32_t> border_blocks() const { return border_blocks_; }
  std::span<const uint32_t> interior_blocks() const { return interior_blocks_; }
  // How many messages thread t had sent when its border blocks were done: those after them, the
  // interior blocks', must all be to this rank's modules.
  void set_border_messages(unsigned thread, size_t count) { border_messages_[thread] = count; }

  // Sends the batches of what the border blocks sent to other ranks' modules (batches_for_ranks):
  // the threads' messages `sent` and the lanes of `hosting`'s agent watches, which are emptied.
  void start_exchange(std::span<const Messages> sent, WatchHosting& hosting);
  // Lets the exchange on while the interior blocks run (thread 0 only: the one that calls MPI).
  void progress(unsigned thread) {
    if (exchanging_ && thread == 0) ranks_.progress();
  }
  // Waits for what the other ranks sent here, and opens it for `watches` watchpoints.
  void finish_exchange(const WatchHosting& hosting);
  // What arrived: the program messages, by rank; the PatternMatchers, per watch.
  std::span<const Messages> arrived_messages() const { return arrived_messages_; }
  std::span<const std::vector<ArrivedLane>> arrived_lanes() const { return arrived_lanes_; }
  // Throws when an interior block sent to another rank's module (the message would be lost).
  void check_interior_messages(std::span<const Messages> sent) const;

  // The lowest module's failure of every rank's (`failed`: this rank's, or null), as every rank
  // throws it when any rank failed (a collective call).
  ProgramError agreed_failure(const Outbox* failed);
  // Every rank's actuations of the step (those of `actuations` from `before` on, this rank's), in
  // module order, in their place (a collective call).
  void gather_actuations(std::vector<Actuation>& actuations, size_t before);

  // Bytes this rank has sent to the others: program messages and PatternMatchers.
  uint64_t bytes_sent() const { return bytes_sent_; }

 private:
  std::vector<std::vector<std::byte>> batches_for_ranks(std::span<const Messages> sent, WatchHosting& hosting);
  void open_batches(const WatchHosting& hosting);

  RankExchange& ranks_;
  const BlockPlacement& placement_;
  std::vector<uint32_t> border_blocks_, interior_blocks_;
  // Per graph sent along (the programs' N(m, t), each agent watch's N(m, t - E+)): per own block,
  // whether a module of it has a neighbour on another rank. Keeping the graph keeps its identity
  // unique.
  struct Border {
    std::shared_ptr<const void> graph;
    std::vector<uint8_t> crosses;
  };
  std::vector<Border> borders_;
  bool exchanging_ = false;
  std::vector<size_t> border_messages_;                  // per thread: its outbox's messages from border blocks
  std::vector<std::vector<std::byte>> arrived_;          // this step's batches from the other ranks
  std::vector<Messages> arrived_messages_;               // per rank
  std::vector<std::vector<ArrivedLane>> arrived_lanes_;  // per watch
  uint64_t bytes_sent_ = 0;
};

}  // namespace dw::sim
