// One rank of several that never meet (sim::RankExchange for tests of what only places modules):
// it knows its rank and their number, partitions a graph as it is told and records what it was
// given; any exchange is a mistake of the code under test.
#pragma once

#include <stdexcept>
#include <vector>

#include "sim/rank_exchange.h"

namespace dw::sim {

class PlacedRanks final : public RankExchange {
 public:
  PlacedRanks(int me, int ranks, std::vector<uint32_t> parts = {}) : me_(me), ranks_(ranks), parts_(std::move(parts)) {}
  int rank() const override { return me_; }
  int ranks() const override { return ranks_; }
  void start_exchange(std::vector<std::vector<std::byte>>) override { never(); }
  std::vector<std::vector<std::byte>> finish_exchange() override { never(); }
  Gathered all_gather(std::span<const std::byte>) override { never(); }
  void sum(std::span<uint64_t>) override { never(); }
  std::vector<uint32_t> partition_graph(std::span<const uint32_t> first, std::span<const uint32_t> adjacent,
                                        std::span<const uint32_t> vertex_weight,
                                        std::span<const uint32_t> edge_weight) override {
    ++partitions;
    this->first.assign(first.begin(), first.end());
    this->adjacent.assign(adjacent.begin(), adjacent.end());
    this->vertex_weight.assign(vertex_weight.begin(), vertex_weight.end());
    this->edge_weight.assign(edge_weight.begin(), edge_weight.end());
    return parts_;
  }

  // The last graph partitioned, and how many were.
  int partitions = 0;
  std::vector<uint32_t> first, adjacent, vertex_weight, edge_weight;

 private:
  [[noreturn]] static void never() { throw std::logic_error("placing modules exchanges nothing between ranks"); }
  int me_, ranks_;
  std::vector<uint32_t> parts_;
};

}  // namespace dw::sim
