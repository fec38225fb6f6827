// Which modules each rank and thread steps (sim/block_placement.cpp, docs/design.md §12): blocks as
// large as the threads allow and never more than 4096 modules, every worker with a block; by
// blocks, runs holding as many present modules each; by graph, the blocks' neighbour graph given
// to the partitioner and its answer kept.
#include "sim/block_placement.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "tests/sim/placed_ranks.h"
#include "tests/sim/test_programs.h"

namespace dw::sim {
namespace {

std::unique_ptr<Model> model_of(Lattice lattice) {
  return std::get<std::unique_ptr<Model>>(build_model(std::move(lattice), {}, {}, 1));
}
std::unique_ptr<Model> line(uint32_t n) { return model_of(make_lattice({LatticeKind::Line, {n, 1, 1}})); }

std::vector<uint32_t> own(const BlockPlacement& p) { return {p.own_blocks().begin(), p.own_blocks().end()}; }

TEST(BlockPlacement, OneThreadTakesTheEnsembleInBlocksOf4096) {
  const auto model = line(10000);
  const BlockPlacement p(*model, 1, nullptr, Partition::Auto, false);
  EXPECT_EQ(p.owners().block_shift, 12u);
  ASSERT_EQ(p.blocks(), 3u);
  EXPECT_EQ(p.block_begin(1), 4096u);
  EXPECT_EQ(p.block_begin(3), 10000u);  // the last block is cut short at the module count
  EXPECT_EQ(own(p), (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(p.first_module(), 0u);
  EXPECT_EQ(p.module_window(), 10000u);
  EXPECT_EQ(p.rank(), 0u);
  EXPECT_TRUE(p.holds(0) && p.holds(9999));
  EXPECT_EQ(p.partition(), Partition::Blocks);
  // A small ensemble is one block.
  const auto small = line(100);
  EXPECT_EQ(BlockPlacement(*small, 1, nullptr, Partition::Auto, false).blocks(), 1u);
}

// Blocks as large as they can be with every worker (threads of every rank) taking one at least.
TEST(BlockPlacement, EveryThreadOfEveryRankHasABlock) {
  const auto model = line(100);
  const BlockPlacement threads(*model, 2, nullptr, Partition::Blocks, false);
  EXPECT_EQ(threads.owners().block_shift, 5u);  // 32: 4 blocks for 2 threads, never 64 (2 blocks)
  EXPECT_EQ(threads.blocks(), 4u);
  PlacedRanks second(1, 2);
  const BlockPlacement ranks(*model, 2, &second, Partition::Blocks, false);
  EXPECT_EQ(ranks.owners().block_shift, 4u);  // 16: 7 blocks for 4 workers
  EXPECT_EQ(ranks.blocks(), 7u);
  EXPECT_FALSE(ranks.own_blocks().empty());
}

// The first half of the line is empty: a rank's share counts present modules, so rank 0 takes the
// empty blocks and the first two full ones, rank 1 the last two.
TEST(BlockPlacement, ByBlocksEachRankTakesARunHoldingAsManyPresentModules) {
  Lattice lattice = make_lattice({LatticeKind::Line, {128, 1, 1}});
  leave_empty(lattice, {0, 0, 0}, {63, 0, 0});
  const auto model = model_of(std::move(lattice));
  PlacedRanks first(0, 2), second(1, 2);
  const BlockPlacement zero(*model, 4, &first, Partition::Blocks, false);
  const BlockPlacement one(*model, 4, &second, Partition::Blocks, false);
  ASSERT_EQ(zero.blocks(), 8u);
  EXPECT_EQ(zero.owners().block_rank, (std::vector<uint32_t>{0, 0, 0, 0, 0, 0, 1, 1}));
  EXPECT_EQ(one.owners().block_rank, zero.owners().block_rank);  // alike on every rank
  EXPECT_EQ(own(zero), (std::vector<uint32_t>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(own(one), (std::vector<uint32_t>{6, 7}));
  EXPECT_EQ(one.first_module(), 96u);
  EXPECT_EQ(one.module_window(), 32u);
  EXPECT_EQ(one.rank(), 1u);
  EXPECT_TRUE(one.holds(96));
  EXPECT_FALSE(one.holds(95));
  EXPECT_TRUE(one.owns_block(6));
  EXPECT_FALSE(one.owns_block(5));
  EXPECT_EQ(first.partitions + second.partitions, 0);
}

// A ring of 8 in two blocks of 4: two links join them, (3, 4) and (7, 0), one edge of weight 2;
// each block weighs its 4 modules. The partitioner's answer is the owners, whatever it is: here
// rank 0 takes the second block, whose window then starts at module 4.
TEST(BlockPlacement, ByGraphTheBlocksGraphGoesToThePartitioner) {
  for (const bool with_graph : {true, false}) {  // a physical world's lattice keeps no graph
    const auto model = model_of(make_lattice({LatticeKind::Ring, {8, 1, 1}}, with_graph));
    PlacedRanks first(0, 2, {1, 0});
    const BlockPlacement p(*model, 1, &first, Partition::Auto, true);
    EXPECT_EQ(p.partition(), Partition::Graph);
    EXPECT_EQ(first.partitions, 1);
    EXPECT_EQ(first.first, (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(first.adjacent, (std::vector<uint32_t>{1, 0}));
    EXPECT_EQ(first.edge_weight, (std::vector<uint32_t>{2, 2}));
    EXPECT_EQ(first.vertex_weight, (std::vector<uint32_t>{4, 4}));
    EXPECT_EQ(own(p), (std::vector<uint32_t>{1}));
    EXPECT_EQ(p.first_module(), 4u);
    EXPECT_EQ(p.module_window(), 4u);
    EXPECT_TRUE(p.holds(4));
    EXPECT_FALSE(p.holds(3));
  }
}

TEST(BlockPlacement, AGraphPartitionNeedsAPartitioner) {
  const auto model = line(8);
  PlacedRanks without(0, 2);  // partitions into nothing
  EXPECT_THROW(BlockPlacement(*model, 1, &without, Partition::Graph, false), std::logic_error);
  // One process has nothing to partition: the blocks are all its own, whatever was asked.
  const BlockPlacement alone(*model, 1, nullptr, Partition::Graph, false);
  EXPECT_EQ(alone.partition(), Partition::Graph);
  EXPECT_EQ(own(alone), (std::vector<uint32_t>{0}));
}

}  // namespace
}  // namespace dw::sim
