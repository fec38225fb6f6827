#include "sim/rank_stepping.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>

namespace dw::sim {

RankStepping::RankStepping(RankExchange& ranks, const BlockPlacement& placement, unsigned threads)
    : ranks_(ranks), placement_(placement), border_messages_(threads) {}

void RankStepping::split_blocks(const State& state, const WatchHosting& hosting) {
  std::vector<WatchHosting::SendingGraph> graphs{{state.graph, {state.graph->begin.data(), state.graph->ids.data()}}};
  for (WatchHosting::SendingGraph& g : hosting.sending_graphs(state)) graphs.push_back(std::move(g));
  const std::span<const uint32_t> own_blocks = placement_.own_blocks();
  std::vector<Border> kept;
  for (const WatchHosting::SendingGraph& graph : graphs) {
    auto same = [&](const Border& b) { return b.graph == graph.owner; };
    if (std::ranges::any_of(kept, same)) continue;
    if (auto known = std::ranges::find_if(borders_, same); known != borders_.end()) {
      kept.push_back(std::move(*known));
      continue;
    }
    Border& b = kept.emplace_back(Border{graph.owner, std::vector<uint8_t>(own_blocks.size(), 0)});
    const watch::AgentHistory::StepGraph& g = graph.graph;
    for (size_t i = 0; i < own_blocks.size(); ++i)
      for (uint32_t m = placement_.block_begin(own_blocks[i]);
           m < placement_.block_begin(own_blocks[i] + 1) && !b.crosses[i]; ++m)
        for (uint32_t e = g.begin[m]; e < g.begin[m + 1]; ++e)
          if (!placement_.holds(g.ids[e])) {
            b.crosses[i] = 1;
            break;
          }
  }
  borders_ = std::move(kept);
  border_blocks_.clear();
  interior_blocks_.clear();
  for (size_t i = 0; i < own_blocks.size(); ++i) {
    const bool border = std::ranges::any_of(borders_, [&](const Border& b) { return b.crosses[i] != 0; });
    (border ? border_blocks_ : interior_blocks_).push_back(own_blocks[i]);
  }
}

void RankStepping::start_exchange(std::span<const Messages> sent, WatchHosting& hosting) {
  ranks_.start_exchange(batches_for_ranks(sent, hosting));
  exchanging_ = true;
}

void RankStepping::finish_exchange(const WatchHosting& hosting) {
  exchanging_ = false;
  arrived_ = ranks_.finish_exchange();
  open_batches(hosting);
}

// What the border blocks sent to other ranks' modules, one batch per rank: the program messages
// (their count, then the records), then for each watch whose agents run, its lanes to that rank's
// blocks (their bytes, then each as block, bytes, records). The lanes are emptied: their
// PatternMatchers are in flight in the batch. A rank with nothing for another sends it nothing.
std::vector<std::vector<std::byte>> RankStepping::batches_for_ranks(std::span<const Messages> sent,
                                                                    WatchHosting& hosting) {
  const std::vector<uint32_t>& block_rank = placement_.owners().block_rank;
  std::vector<std::vector<std::byte>> out(static_cast<size_t>(ranks_.ranks()));
  auto put = [](std::vector<std::byte>& to, uint64_t value) {
    append_records(to, std::span<const uint64_t>(&value, 1));
  };
  auto patch = [](std::vector<std::byte>& to, size_t at, uint64_t value) {
    std::memcpy(to.data() + at, &value, sizeof value);
  };
  // The messages: their count, their headers (each header's `first` counting in this batch's
  // words), the count of the words and the words.
  std::vector<MessageList> going(out.size());
  for (const Messages thread : sent)
    for (const Message m : thread)
      if (const uint32_t r = placement_.owners().rank_of(m.to); r != placement_.rank()) going[r].add(m);
  for (size_t r = 0; r < out.size(); ++r) {
    put(out[r], going[r].size());
    append_records(out[r], std::as_const(going[r]).headers());
    put(out[r], going[r].words().size());
    append_records(out[r], std::span<const int64_t>(going[r].words()));
  }
  const uint32_t blocks = placement_.blocks();
  for (uint32_t w : hosting.agent_watches()) {
    const std::span<watch::RecordBuffer> lanes = hosting.lanes(w);
    const size_t threads = lanes.size() / blocks;
    std::vector<size_t> head(out.size());
    for (size_t r = 0; r < out.size(); ++r) head[r] = out[r].size(), put(out[r], 0);
    for (size_t thread = 0; thread < threads; ++thread)
      for (uint32_t block = 0; block < blocks; ++block) {
        watch::RecordBuffer& lane = lanes[thread * blocks + block];
        if (lane.empty() || placement_.owns_block(block)) continue;
        std::vector<std::byte>& to = out[block_rank[block]];
        put(to, block);
        put(to, lane.size());
        to.insert(to.end(), lane.data(), lane.data() + lane.size());
        lane.clear();
      }
    for (size_t r = 0; r < out.size(); ++r) patch(out[r], head[r], out[r].size() - head[r] - sizeof(uint64_t));
  }
  const size_t headers = sizeof(uint64_t) * (2 + hosting.agent_watches().size());  // all a batch of nothing holds
  for (std::vector<std::byte>& to : out) {
    if (to.size() == headers) to.clear();
    bytes_sent_ += to.size();
  }
  return out;
}

// The batches that arrived (batches_for_ranks), opened in place: the messages by rank, and each
// watch's lanes, each as the block it goes to and its records.
void RankStepping::open_batches(const WatchHosting& hosting) {
  arrived_messages_.assign(arrived_.size(), {});
  arrived_lanes_.assign(hosting.size(), {});
  for (size_t r = 0; r < arrived_.size(); ++r) {
    const std::span<const std::byte> part = arrived_[r];
    if (part.empty()) continue;
    size_t at = 0;
    auto take = [&] {
      uint64_t value;
      std::memcpy(&value, part.data() + at, sizeof value);
      at += sizeof value;
      return value;
    };
    const uint64_t count = take();
    const std::span<const MessageHeader> headers =
        records_of<MessageHeader>(part.subspan(at, count * sizeof(MessageHeader)));
    at += count * sizeof(MessageHeader);
    const uint64_t words = take();
    arrived_messages_[r] = Messages(headers, records_of<int64_t>(part.subspan(at, words * sizeof(int64_t))).data());
    at += words * sizeof(int64_t);
    for (uint32_t w : hosting.agent_watches()) {
      const uint64_t bytes = take();
      const std::span<const std::byte> lanes = part.subspan(at, bytes);
      for (size_t i = 0; i < lanes.size();) {
        uint64_t head[2];  // block, bytes
        std::memcpy(head, lanes.data() + i, sizeof head);
        arrived_lanes_[w].push_back({static_cast<uint32_t>(head[0]), lanes.subspan(i + sizeof head, head[1])});
        i += sizeof head + head[1];
      }
      at += lanes.size();
    }
  }
}

void RankStepping::check_interior_messages(std::span<const Messages> sent) const {
  for (size_t thread = 0; thread < sent.size(); ++thread)
    for (size_t i = border_messages_[thread]; i < sent[thread].size(); ++i)
      if (!placement_.holds(sent[thread][i].to))
        throw std::logic_error("a block taken for interior sent to another rank: its message would be lost");
}

// Each failing rank says (step, module, message); the lowest module's is the one, as one process
// reports it (each thread's outbox keeps its lowest module's).
ProgramError RankStepping::agreed_failure(const Outbox* failed) {
  std::vector<std::byte> said;
  if (failed) {
    const int64_t where[2] = {failed->error_step, failed->error_module};
    append_records(said, std::span<const int64_t>(where));
    append_records(said, std::span(failed->error.data(), failed->error.size()));
  }
  const Gathered all = ranks_.all_gather(said);
  int64_t where[2] = {0, INT64_MAX};
  std::string message;
  for (const std::span<const std::byte> part : all) {
    if (part.empty()) continue;
    int64_t at[2];
    std::memcpy(at, part.data(), sizeof at);
    if (at[1] >= where[1]) continue;
    std::memcpy(where, at, sizeof where);
    message.assign(reinterpret_cast<const char*>(part.data()) + sizeof at, part.size() - sizeof at);
  }
  return ProgramError(message, static_cast<ModuleId>(where[1]), where[0]);
}

// The world is stepped whole on every rank, so every rank needs all of them, in module order, as
// one process has them (in thread order).
void RankStepping::gather_actuations(std::vector<Actuation>& actuations, size_t before) {
  std::vector<std::byte> mine;
  append_records(mine, std::span<const Actuation>(actuations).subspan(before));
  actuations.resize(before);
  for (const auto& part : ranks_.all_gather(mine))
    actuations.insert(actuations.end(), records_of<Actuation>(part).begin(), records_of<Actuation>(part).end());
  std::stable_sort(actuations.begin() + static_cast<ptrdiff_t>(before), actuations.end(),
                   [](const Actuation& a, const Actuation& b) { return a.module < b.module; });
}

}  // namespace dw::sim
