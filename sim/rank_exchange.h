// The seam to the other processes (ranks) of one run (docs/design.md §12). Each rank runs the whole
// session and steps its own part of the modules; what crosses between the parts (program
// messages, PatternMatchers, matches, statistics, a failure) goes through these few collective
// calls, which every rank makes in the same order. `dist/` implements them with Open MPI; `sim/`
// knows no MPI.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace dw::sim {

// Every rank's part of an all-gather, in rank order, in one buffer: (*this)[r] is rank r's. Each
// part starts 16-byte aligned, so that it can be read as records in place (records_of).
class Gathered {
 public:
  Gathered() = default;
  explicit Gathered(std::span<const uint64_t> sizes) {
    size_t at = 0;
    for (uint64_t size : sizes) {
      offsets_.push_back(at);
      at += (size + 15) & ~uint64_t{15};
    }
    offsets_.push_back(at);
    bytes_ = std::make_unique_for_overwrite<std::byte[]>(at + 16);
    for (size_t r = 0; r < sizes.size(); ++r) parts_.emplace_back(data(r), sizes[r]);
  }
  size_t size() const { return parts_.size(); }
  std::span<const std::byte> operator[](size_t r) const { return parts_[r]; }
  auto begin() const { return parts_.begin(); }
  auto end() const { return parts_.end(); }
  // Where rank r's part goes, and its offset in the buffer.
  std::byte* data(size_t r) { return aligned() + offsets_[r]; }
  size_t offset(size_t r) const { return offsets_[r]; }

 private:
  std::byte* aligned() const {
    return reinterpret_cast<std::byte*>((reinterpret_cast<uintptr_t>(bytes_.get()) + 15) & ~uintptr_t{15});
  }
  std::unique_ptr<std::byte[]> bytes_;
  std::vector<size_t> offsets_;  // [ranks + 1]
  std::vector<std::span<const std::byte>> parts_;
};

class RankExchange {
 public:
  virtual ~RankExchange() = default;

  virtual int rank() const = 0;
  virtual int ranks() const = 0;

  // An all-to-all that overlaps work: start_exchange starts sending out[r] to rank r (out[rank()]
  // is not sent) and returns at once; the bytes move while this rank works on, as long as it
  // calls progress() now and then; finish_exchange waits for what each rank sent here and returns
  // it, in rank order (empty for this rank). A rank that has nothing for another sends it nothing
  // but its size. One exchange at a time, and no other call between its start and its finish but
  // progress().
  virtual void start_exchange(std::vector<std::vector<std::byte>> out) = 0;
  virtual void progress() {}
  virtual std::vector<std::vector<std::byte>> finish_exchange() = 0;
  // Every rank's `mine`, in rank order, on every rank.
  virtual Gathered all_gather(std::span<const std::byte> mine) = 0;
  // Sums `values` element-wise over the ranks, in place, on every rank.
  virtual void sum(std::span<uint64_t> values) = 0;

  // Parts of a graph for the ranks (Partition::Graph): the rank of each vertex, the same on
  // every rank, keeping the summed weights of the vertices near equal and of the edges cut small.
  // The graph is in CSR form (the edges of v are adjacent[first[v] .. first[v + 1])), given alike
  // on every rank. Empty when this exchange has no graph partitioner.
  virtual std::vector<uint32_t> partition_graph(std::span<const uint32_t> first, std::span<const uint32_t> adjacent,
                                                std::span<const uint32_t> vertex_weight,
                                                std::span<const uint32_t> edge_weight) {
    (void)first, (void)adjacent, (void)vertex_weight, (void)edge_weight;
    return {};
  }
};

// Which rank owns each module (docs/design.md §12): the modules in blocks of 2^block_shift
// consecutive ids, each block one rank's (BlockPlacement, sim/block_placement.h); alike on every rank.
struct ModuleOwners {
  std::vector<uint32_t> block_rank;  // per block
  uint32_t block_shift = 0;
  uint32_t rank_of(uint32_t module) const { return block_rank[module >> block_shift]; }
};

// How the modules are shared among ranks, in blocks of consecutive ids (docs/design.md §12).
enum class Partition {
  Auto,    // Blocks for a static lattice, Graph for a world whose links move (World::moves)
  Blocks,  // runs of consecutive blocks, each rank's holding about as many modules: slabs of a lattice
  Graph,   // a k-way partition of the blocks' neighbour graph (METIS): for what ids do not lay out
};
// The names `--partition` takes, by Partition value.
inline constexpr std::array<std::string_view, 3> kPartitionNames{"auto", "blocks", "metis"};
inline std::string_view partition_name(Partition p) { return kPartitionNames[static_cast<size_t>(p)]; }
// The Partition a name (one of kPartitionNames) stands for.
inline Partition partition_named(std::string_view name) {
  return static_cast<Partition>(std::find(kPartitionNames.begin(), kPartitionNames.end(), name) -
                                kPartitionNames.begin());
}

// Whether `yes` holds on any rank: a decision every rank takes alike (a collective call); in one
// process (no ranks), `yes`.
inline bool any_rank(RankExchange* ranks, bool yes) {
  if (ranks == nullptr) return yes;
  uint64_t count = yes;
  ranks->sum({&count, 1});
  return count != 0;
}

// Plain records in and out of the byte buffers the exchange carries.
template <class T>
void append_records(std::vector<std::byte>& to, std::span<const T> records) {
  const auto* bytes = reinterpret_cast<const std::byte*>(records.data());
  to.insert(to.end(), bytes, bytes + records.size_bytes());
}
template <class T>
std::span<const T> records_of(std::span<const std::byte> bytes) {
  return {reinterpret_cast<const T*>(bytes.data()), bytes.size() / sizeof(T)};
}

// Every rank's `mine` in rank order, appended to `into` on every rank (a collective call), with
// room reserved for `room` records more. Gathered in rounds of at most `round_bytes` from each
// rank and laid down at once, so what is gathered is never held twice (a single gather of
// millions of records would hold them beside their copy).
template <class T>
void all_gather_into(RankExchange& ranks, std::span<const T> mine, std::vector<T>& into, size_t room = 0,
                     size_t round_bytes = size_t{1} << 20) {
  static_assert(std::is_trivially_copyable_v<T>);
  const uint64_t count = mine.size();
  std::vector<uint64_t> first;  // where each rank's records go in `into`
  uint64_t at = into.size(), most = 0;
  for (const auto& part : ranks.all_gather(std::as_bytes(std::span(&count, 1)))) {
    const uint64_t theirs = records_of<uint64_t>(part)[0];
    first.push_back(at);
    at += theirs;
    most = std::max(most, theirs);
  }
  into.reserve(at + room);
  into.resize(at);
  const size_t per_round = std::max<size_t>(1, round_bytes / sizeof(T));
  for (uint64_t done = 0; done < most; done += per_round) {
    const std::span<const T> piece =
        done < count ? mine.subspan(done, std::min<uint64_t>(per_round, count - done)) : std::span<const T>{};
    const Gathered parts = ranks.all_gather(std::as_bytes(piece));
    for (size_t r = 0; r < parts.size(); ++r) {
      const std::span<const T> theirs = records_of<T>(parts[r]);
      std::copy(theirs.begin(), theirs.end(), into.begin() + static_cast<ptrdiff_t>(first[r] + done));
    }
  }
}

// `values` summed element-wise over the ranks, in place, on every rank (a collective call); in one
// process they are the sums already.
inline void sum_over_ranks(RankExchange* ranks, std::span<uint64_t> values) {
  if (ranks != nullptr) ranks->sum(values);
}
inline uint64_t sum_over_ranks(RankExchange* ranks, uint64_t value) {
  sum_over_ranks(ranks, std::span(&value, 1));
  return value;
}

// Every rank's `records`, in rank order, in place of this rank's, on every rank (a collective
// call); in one process they are all of them already.
template <class T>
void gather_over_ranks(RankExchange* ranks, std::vector<T>& records) {
  static_assert(std::is_trivially_copyable_v<T>);
  if (ranks == nullptr) return;
  std::vector<T> all;
  for (const auto& part : ranks->all_gather(std::as_bytes(std::span<const T>(records))))
    all.insert(all.end(), records_of<T>(part).begin(), records_of<T>(part).end());
  records = std::move(all);
}

// The largest of every rank's `value` (a collective call); in one process, `value`.
template <class T>
T max_over_ranks(RankExchange* ranks, T value) {
  if (ranks == nullptr) return value;
  T largest = value;
  for (const auto& part : ranks->all_gather(std::as_bytes(std::span(&value, 1))))
    largest = std::max(largest, records_of<T>(part)[0]);
  return largest;
}

}  // namespace dw::sim
