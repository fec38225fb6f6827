#include "sim/block_placement.h"

#include <stdexcept>
#include <utility>

namespace dw::sim {
namespace {

// The blocks' neighbour graph at step 0 (the lattice's) in CSR form, as RankExchange::partition_graph
// takes it: an edge per two blocks with modules linked, weighted by how many links join them.
struct BlockGraph {
  std::vector<uint32_t> first, adjacent, link_weight;
};

BlockGraph block_graph(const Lattice& lattice, uint32_t blocks, uint32_t block_shift) {
  // The links between blocks, as sorted (block, block) pairs: equal pairs make one edge's weight.
  // A physical world's lattice keeps no graph: its cells give the links (no graph of a million
  // is made on every rank only to be read once).
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  const auto link = [&](ModuleId m, ModuleId n) {
    const uint32_t a = m >> block_shift, b = n >> block_shift;
    if (a != b) pairs.push_back({a, b}), pairs.push_back({b, a});
  };
  if (const NeighborGraph* g = lattice.graph.get()) {
    for (ModuleId m = 0; m < g->module_count(); ++m)
      for (ModuleId n : g->neighbors(m))
        if (m < n) link(m, n);
  } else {
    for_lattice_pairs(lattice.spec, lattice.occupied, link);
  }
  std::sort(pairs.begin(), pairs.end());
  BlockGraph graph;
  graph.first.assign(blocks + 1, 0);
  for (size_t i = 0; i < pairs.size(); ++i) {
    if (i > 0 && pairs[i] == pairs[i - 1]) {
      ++graph.link_weight.back();
      continue;
    }
    graph.adjacent.push_back(pairs[i].second);
    graph.link_weight.push_back(1);
    ++graph.first[pairs[i].first + 1];
  }
  for (uint32_t b = 0; b < blocks; ++b) graph.first[b + 1] += graph.first[b];
  return graph;
}

// Runs of consecutive blocks, each rank's holding about as many present modules as the others (on
// a lattice, whose ids run x, y, z: a slab). A block goes to the rank whose share its middle
// module falls in.
std::vector<uint32_t> blocks_in_runs(std::span<const uint32_t> weight, uint32_t rank_count) {
  uint64_t total = 0, seen = 0;
  for (uint32_t w : weight) total += w;
  std::vector<uint32_t> rank(weight.size(), 0);
  for (size_t b = 0; b < weight.size(); ++b) {
    const uint64_t middle = 2 * seen + weight[b];
    rank[b] =
        total == 0 ? 0 : static_cast<uint32_t>(std::min<uint64_t>(rank_count - 1, middle * rank_count / (2 * total)));
    seen += weight[b];
  }
  return rank;
}

}  // namespace

// Which rank steps each block. By blocks: runs of consecutive blocks (blocks_in_runs). By graph:
// the blocks' neighbour graph (block_graph), weighted by present modules and by links between
// blocks, cut k-way by the exchange's partitioner (METIS, dist/mpi_exchange.cpp).
BlockPlacement::BlockPlacement(const Model& model, unsigned threads, RankExchange* ranks, Partition partition,
                               bool world_moves)
    : module_count_(model.module_count()),
      alone_(ranks == nullptr),
      me_(ranks ? static_cast<uint32_t>(ranks->rank()) : 0) {
  const uint32_t m = module_count_;
  const uint32_t rank_count = ranks ? static_cast<uint32_t>(ranks->ranks()) : 1;
  const uint32_t workers = threads * rank_count;
  const uint32_t per_thread = std::max(1u, m / workers);
  if (workers == 1)
    while (owners_.block_shift < 12 && (1u << owners_.block_shift) < per_thread) ++owners_.block_shift;
  else
    while (owners_.block_shift < 12 && (2u << owners_.block_shift) <= per_thread) ++owners_.block_shift;
  blocks_ = (m >> owners_.block_shift) + ((m & ((1u << owners_.block_shift) - 1)) != 0);

  const std::vector<uint8_t>& occupied = model.lattice.occupied;
  std::vector<uint32_t> weight(blocks_, 0);
  for (uint32_t i = 0; i < m; ++i) weight[i >> owners_.block_shift] += i < occupied.size() ? occupied[i] : 1;
  if (partition == Partition::Auto) partition = world_moves ? Partition::Graph : Partition::Blocks;
  partition_ = partition;
  if (partition == Partition::Graph && rank_count > 1) {
    const BlockGraph graph = block_graph(model.lattice, blocks_, owners_.block_shift);
    owners_.block_rank = ranks->partition_graph(graph.first, graph.adjacent, weight, graph.link_weight);
    if (owners_.block_rank.size() != blocks_) throw std::logic_error("the rank exchange has no graph partitioner");
  } else {
    owners_.block_rank = blocks_in_runs(weight, rank_count);
  }
  for (uint32_t b = 0; b < blocks_; ++b)
    if (owners_.block_rank[b] == me_) own_blocks_.push_back(b);
  first_ = own_blocks_.empty() ? 0 : block_begin(own_blocks_.front());
  window_ = own_blocks_.empty() ? 0 : block_begin(own_blocks_.back() + 1) - first_;
}

}  // namespace dw::sim
