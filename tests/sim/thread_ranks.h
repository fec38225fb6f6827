// Ranks as threads of one test process (sim::RankExchange without MPI, docs/design.md §12): for
// tests of what runs over ranks, each rank a thread, exchanging through memory.
#pragma once

#include <algorithm>
#include <barrier>
#include <thread>
#include <type_traits>
#include <vector>

#include "sim/rank_exchange.h"

namespace dw::sim {

// Ranks as threads: each call is a meeting of all of them at a barrier, as MPI's collectives are.
class ThreadRanks {
 public:
  explicit ThreadRanks(int n) : n_(n), sync_(n), posted_(size_t(n)), sums_(size_t(n)) {}

  class Rank final : public RankExchange {
   public:
    Rank(ThreadRanks& all, int me) : all_(all), me_(me) {}
    int rank() const override { return me_; }
    int ranks() const override { return all_.n_; }
    // Nothing moves before the finish: every rank meets there.
    void start_exchange(std::vector<std::vector<std::byte>> out) override {
      all_.posted_[size_t(me_)] = std::move(out);
    }
    std::vector<std::vector<std::byte>> finish_exchange() override {
      all_.sync_.arrive_and_wait();
      std::vector<std::vector<std::byte>> in(size_t(all_.n_));
      for (int r = 0; r < all_.n_; ++r)
        if (r != me_) in[size_t(r)] = all_.posted_[size_t(r)][size_t(me_)];
      all_.sync_.arrive_and_wait();
      return in;
    }
    Gathered all_gather(std::span<const std::byte> mine) override {
      all_.posted_[size_t(me_)] = {std::vector<std::byte>(mine.begin(), mine.end())};
      all_.sync_.arrive_and_wait();
      std::vector<uint64_t> sizes;
      for (int r = 0; r < all_.n_; ++r) sizes.push_back(all_.posted_[size_t(r)][0].size());
      Gathered all(sizes);
      for (int r = 0; r < all_.n_; ++r)
        std::copy(all_.posted_[size_t(r)][0].begin(), all_.posted_[size_t(r)][0].end(), all.data(size_t(r)));
      all_.sync_.arrive_and_wait();
      return all;
    }
    void sum(std::span<uint64_t> values) override {
      all_.sums_[size_t(me_)].assign(values.begin(), values.end());
      all_.sync_.arrive_and_wait();
      for (size_t i = 0; i < values.size(); ++i) {
        values[i] = 0;
        for (int r = 0; r < all_.n_; ++r) values[i] += all_.sums_[size_t(r)][i];
      }
      all_.sync_.arrive_and_wait();
    }
    // Blocks dealt round-robin: no rank's modules are one run of ids, its neighbours' never either.
    std::vector<uint32_t> partition_graph(std::span<const uint32_t> first, std::span<const uint32_t>,
                                          std::span<const uint32_t>, std::span<const uint32_t>) override {
      std::vector<uint32_t> parts(first.size() - 1);
      for (size_t b = 0; b < parts.size(); ++b) parts[b] = static_cast<uint32_t>(b % size_t(all_.n_));
      return parts;
    }

   private:
    ThreadRanks& all_;
    int me_;
  };

 private:
  int n_;
  std::barrier<> sync_;
  std::vector<std::vector<std::vector<std::byte>>> posted_;  // [from][to]
  std::vector<std::vector<uint64_t>> sums_;
};

// A rank that counts the gathers it takes part in, the bytes it gave them, and the largest part
// it gave one.
class CountedGathers final : public RankExchange {
 public:
  explicit CountedGathers(RankExchange& rank) : rank_(rank) {}
  int rank() const override { return rank_.rank(); }
  int ranks() const override { return rank_.ranks(); }
  void start_exchange(std::vector<std::vector<std::byte>> out) override { rank_.start_exchange(std::move(out)); }
  std::vector<std::vector<std::byte>> finish_exchange() override { return rank_.finish_exchange(); }
  Gathered all_gather(std::span<const std::byte> mine) override {
    ++gathers;
    gathered += mine.size();
    largest = std::max(largest, mine.size());
    return rank_.all_gather(mine);
  }
  void sum(std::span<uint64_t> values) override { rank_.sum(values); }
  std::vector<uint32_t> partition_graph(std::span<const uint32_t> first, std::span<const uint32_t> adjacent,
                                        std::span<const uint32_t> vertex_weight,
                                        std::span<const uint32_t> edge_weight) override {
    return rank_.partition_graph(first, adjacent, vertex_weight, edge_weight);
  }
  size_t gathers = 0, gathered = 0, largest = 0;

 private:
  RankExchange& rank_;
};

// Runs `fn(rank)` on `n` ranks, each its own thread, and returns what each gave.
template <class Fn>
auto on_ranks(int n, Fn fn) {
  ThreadRanks all(n);
  using Result = std::invoke_result_t<Fn, RankExchange&>;
  std::vector<Result> results(static_cast<size_t>(n));
  std::vector<std::thread> threads;
  for (int r = 0; r < n; ++r)
    threads.emplace_back([&, r] {
      ThreadRanks::Rank rank(all, r);
      results[size_t(r)] = fn(rank);
    });
  for (std::thread& t : threads) t.join();
  return results;
}

}  // namespace dw::sim
