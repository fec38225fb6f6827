// Which modules this process steps, and in what pieces its threads take them (docs/design.md §12):
// the modules in blocks of consecutive ids, each block one rank's (ModuleOwners), the blocks of this
// rank and the window of module ids its state holds. In one process every block is its own.
//
// Blocks are at most 4096 modules (a power of two). A neighbour list that crosses a block boundary
// is sent as one record per block, so blocks are as large as the threads allow: one thread takes
// the ensemble as one block (up to 4096), and several (over all ranks) take at least one block
// each, never so large that one is left without.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "sim/model.h"
#include "sim/rank_exchange.h"

namespace dw::sim {

class BlockPlacement {
 public:
  // Blocks for `threads` threads in each process of `ranks` (this one alone when null), shared
  // among the ranks by `partition`: Auto takes Graph for a world whose links move (`world_moves`),
  // Blocks otherwise. Over ranks a collective call when the partition is by graph.
  BlockPlacement(const Model& model, unsigned threads, RankExchange* ranks, Partition partition, bool world_moves);

  uint32_t blocks() const { return blocks_; }
  // A block's first module; block_begin(blocks()) is the module count.
  uint32_t block_begin(uint32_t block) const {
    return static_cast<uint32_t>(std::min<uint64_t>(uint64_t{block} << owners_.block_shift, module_count_));
  }
  // The rank that steps each block, alike on every rank.
  const ModuleOwners& owners() const { return owners_; }
  // This rank's blocks, ascending; thread t takes the t-th of equal runs.
  std::span<const uint32_t> own_blocks() const { return own_blocks_; }
  // The modules whose variables, inboxes and agents this process's states hold: [first, first +
  // window), from its first block to its last (other ranks' blocks may lie between).
  uint32_t first_module() const { return first_; }
  uint32_t module_window() const { return window_; }
  // How the blocks were shared (Auto decided).
  Partition partition() const { return partition_; }
  // This process's rank: 0 in one process.
  uint32_t rank() const { return me_; }
  // Whether this process steps module m (< the module count), and so alone holds its variables,
  // its inbox and its agent: every module in one process.
  bool holds(ModuleId m) const { return alone_ || owners_.rank_of(m) == me_; }
  // Whether a block is this rank's.
  bool owns_block(uint32_t block) const { return owners_.block_rank[block] == me_; }

 private:
  const uint32_t module_count_;
  const bool alone_;
  const uint32_t me_;
  uint32_t blocks_ = 0;
  ModuleOwners owners_;
  std::vector<uint32_t> own_blocks_;
  uint32_t first_ = 0, window_ = 0;
  Partition partition_ = Partition::Blocks;
};

}  // namespace dw::sim
