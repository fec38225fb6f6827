#include "sim/whole_over_ranks.h"

#include <functional>

namespace dw::sim {
namespace {

// Passes the hash along the blocks in module order: the rank holding a run of blocks continues it
// over that run (`run(h, first, end)`, modules of this rank's window), then gives it to all.
uint64_t pass_hash(RankExchange& ranks, const BlockPlacement& placement, uint64_t h,
                   const std::function<uint64_t(uint64_t, uint32_t, uint32_t)>& run) {
  const std::vector<uint32_t>& block_rank = placement.owners().block_rank;
  const uint32_t first = placement.first_module();
  for (uint32_t b = 0, e = 0; b < placement.blocks(); b = e) {
    for (e = b + 1; e < placement.blocks() && block_rank[e] == block_rank[b];) ++e;
    const bool mine = placement.owns_block(b);
    if (mine) h = run(h, placement.block_begin(b) - first, placement.block_begin(e) - first);
    const Gathered told = ranks.all_gather(mine ? std::as_bytes(std::span(&h, 1)) : std::span<const std::byte>{});
    h = records_of<uint64_t>(told[block_rank[b]])[0];
  }
  return h;
}

}  // namespace

// Each rank gives its blocks' rows in block order, and every rank knows whose each block is: the
// rows of every block, in block order, lie in the gathered parts.
std::vector<std::span<const int64_t>> gather_block_values(RankExchange& ranks, const BlockPlacement& placement,
                                                          uint32_t variables, std::span<const int64_t> values,
                                                          Gathered& parts) {
  const size_t v = variables;
  const uint32_t first = placement.first_module();
  const std::span<const uint32_t> own_blocks = placement.own_blocks();
  std::vector<int64_t> copied;  // unless the blocks are one run (--partition blocks), read in place
  std::span<const int64_t> own = values;
  if (!own_blocks.empty() && own_blocks.back() - own_blocks.front() + 1 != own_blocks.size()) {
    for (uint32_t b : own_blocks)
      copied.insert(copied.end(), values.begin() + static_cast<ptrdiff_t>((placement.block_begin(b) - first) * v),
                    values.begin() + static_cast<ptrdiff_t>((placement.block_begin(b + 1) - first) * v));
    own = copied;
  }
  parts = ranks.all_gather(std::as_bytes(own));
  const std::vector<uint32_t>& block_rank = placement.owners().block_rank;
  std::vector<std::span<const int64_t>> rows;
  std::vector<size_t> read(parts.size(), 0);
  for (uint32_t b = 0; b < placement.blocks(); ++b) {
    const size_t n = (placement.block_begin(b + 1) - placement.block_begin(b)) * v;
    rows.push_back(records_of<int64_t>(parts[block_rank[b]]).subspan(read[block_rank[b]], n));
    read[block_rank[b]] += n;
  }
  return rows;
}

std::vector<int64_t> gather_values(RankExchange& ranks, const BlockPlacement& placement, uint32_t variables,
                                   std::span<const int64_t> values) {
  Gathered parts;
  std::vector<int64_t> whole;
  whole.reserve(size_t{placement.block_begin(placement.blocks())} * variables);
  for (const std::span<const int64_t> rows : gather_block_values(ranks, placement, variables, values, parts))
    whole.insert(whole.end(), rows.begin(), rows.end());
  return whole;
}

// Each rank gives its blocks' lists in block order, each as its length and its ids.
std::shared_ptr<const NeighborGraph> gather_graph(RankExchange& ranks, const BlockPlacement& placement,
                                                  const NeighborGraph& graph) {
  std::vector<uint32_t> own;
  for (uint32_t b : placement.own_blocks())
    for (ModuleId m = placement.block_begin(b); m < placement.block_begin(b + 1); ++m) {
      const std::span<const ModuleId> list = graph.neighbors(m);
      own.push_back(static_cast<uint32_t>(list.size()));
      own.insert(own.end(), list.begin(), list.end());
    }
  const Gathered parts = ranks.all_gather(std::as_bytes(std::span<const uint32_t>(own)));
  auto whole = std::make_shared<NeighborGraph>();
  whole->begin.reserve(size_t{placement.block_begin(placement.blocks())} + 1);
  std::vector<size_t> read(parts.size(), 0);
  for (uint32_t b = 0; b < placement.blocks(); ++b) {
    const uint32_t rank = placement.owners().block_rank[b];
    const std::span<const uint32_t> words = records_of<uint32_t>(parts[rank]);
    for (ModuleId m = placement.block_begin(b); m < placement.block_begin(b + 1); ++m) {
      const uint32_t count = words[read[rank]++];
      whole->ids.insert(whole->ids.end(), words.begin() + ptrdiff_t(read[rank]),
                        words.begin() + ptrdiff_t(read[rank] + count));
      read[rank] += count;
      whole->begin.push_back(static_cast<uint32_t>(whole->ids.size()));
    }
  }
  return whole;
}

// The rest every rank holds; each rank's modules' variables and messages are hashed where they
// are, the hash passed from rank to rank in module order, never put together in one place (a
// million modules' inbox is hundreds of MB). `use` is given the pieces; `messages` is the count
// of the whole inbox.
template <class Use>
auto with_rank_pieces(RankExchange& ranks, const BlockPlacement& placement, const Model& model, const State& state,
                      uint64_t messages, Use use) {
  const size_t v = model.variable_count(), programs = model.program_count();
  const uint32_t first_module = placement.first_module();
  const auto pass = [&](uint64_t h, const std::function<uint64_t(uint64_t, uint32_t, uint32_t)>& run) {
    return pass_hash(ranks, placement, h, run);
  };
  const auto values = [&](uint64_t h) {
    return pass(h, [&](uint64_t h, uint32_t first, uint32_t end) {
      return continue_hash(h, std::span(state.values).subspan(first * v, (end - first) * v));
    });
  };
  // Every rank holds the graph and the bodies whole as yet; each hashes its own modules' all the
  // same, as it will once a rank holds only its own modules' and their neighbours'.
  const auto by_module = [&](const auto* whole) {
    return [&, whole](uint64_t h) {
      return pass(h, [&](uint64_t h, uint32_t first, uint32_t end) {
        return continue_hash(h, *whole, first_module + first, first_module + end);
      });
    };
  };
  const auto inbox = [&](uint64_t h) {
    return pass(h, [&](uint64_t h, uint32_t first, uint32_t end) {
      const std::vector<uint32_t>& begin = state.inbox.begin;  // empty before the first delivery
      if (begin.empty()) return h;
      const uint32_t from = begin[first * programs], to = begin[end * programs];
      return continue_hash(h, state.inbox.messages.all().subspan(from, to - from));
    });
  };
  const uint64_t n = model.module_count();
  return use(HashPieces{n * v, values, state.graph ? n : 0, by_module(state.graph.get()), state.bodies.empty() ? 0 : n,
                        by_module(&state.bodies), messages, inbox});
}

// The in-flight multisets are added up over the ranks, with the inbox's messages.
StateHash hash_over_ranks(RankExchange& ranks, const BlockPlacement& placement, const Model& model,
                          const State& state) {
  std::vector<InFlightDigest> digests;
  for (const WatchState& w : state.watches) digests.push_back(in_flight_digest(w));
  std::vector<uint64_t> sums;
  for (const InFlightDigest& d : digests) sums.insert(sums.end(), {d.sum, d.count});
  sums.push_back(state.inbox.messages.size());
  ranks.sum(sums);
  for (size_t w = 0; w < digests.size(); ++w) digests[w] = {sums[2 * w], sums[2 * w + 1]};
  return with_rank_pieces(ranks, placement, model, state, sums.back(),
                          [&](const HashPieces& pieces) { return hash_state(state, digests, pieces); });
}

uint64_t simulation_hash_over_ranks(RankExchange& ranks, const BlockPlacement& placement, const Model& model,
                                    const State& state) {
  uint64_t messages = state.inbox.messages.size();
  ranks.sum({&messages, 1});
  return with_rank_pieces(ranks, placement, model, state, messages,
                          [&](const HashPieces& pieces) { return simulation_hash(state, pieces); });
}

}  // namespace dw::sim
