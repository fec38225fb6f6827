// The whole of what the ranks of a run hold in parts (docs/design.md §12), put together on every
// rank: each is a collective call. Each rank holds its own blocks' variables and inboxes (and, for
// a world that shares its graph, their neighbour lists); every rank knows whose each block is
// (BlockPlacement), so the parts are laid out block by block in module order.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "sim/block_placement.h"
#include "sim/model.h"
#include "sim/neighbor_graph.h"
#include "sim/rank_exchange.h"
#include "sim/state.h"

namespace dw::sim {

// Every block's rows of `variables` values per module, in block order, read where they lie in
// `parts` (which the call fills): `values` are this rank's window of them.
std::vector<std::span<const int64_t>> gather_block_values(RankExchange& ranks, const BlockPlacement& placement,
                                                          uint32_t variables, std::span<const int64_t> values,
                                                          Gathered& parts);
// The variables of every module (model order), from this rank's window of them.
std::vector<int64_t> gather_values(RankExchange& ranks, const BlockPlacement& placement, uint32_t variables,
                                   std::span<const int64_t> values);
// N(m, t) of every module, from `graph`, which holds this rank's modules' lists.
std::shared_ptr<const NeighborGraph> gather_graph(RankExchange& ranks, const BlockPlacement& placement,
                                                  const NeighborGraph& graph);
// The hash of the whole state as one process would hold it (hash_state), from this rank's part,
// never put together in one place.
StateHash hash_over_ranks(RankExchange& ranks, const BlockPlacement& placement, const Model& model, const State& state);
// Its simulation part alone (simulation_hash), what the run hash chains after every step.
uint64_t simulation_hash_over_ranks(RankExchange& ranks, const BlockPlacement& placement, const Model& model,
                                    const State& state);

}  // namespace dw::sim
