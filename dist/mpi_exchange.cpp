#include "dist/mpi_exchange.h"

#include <metis.h>
#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <string>

namespace dw::dist {
namespace {

// MPI counts are ints: a buffer goes in pieces of at most this many bytes.
constexpr uint64_t kPiece = uint64_t{1} << 30;

class MpiExchange final : public sim::RankExchange {
 public:
  MpiExchange() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks_);
  }
  int rank() const override { return rank_; }
  int ranks() const override { return ranks_; }

  // The sizes go by a non-blocking all-to-all and the batches by Isend at once; each receive is
  // posted as soon as its size is known (in progress() or in the finish), and every call to
  // progress() lets Open MPI move the bytes on meanwhile.
  void start_exchange(std::vector<std::vector<std::byte>> out) override {
    const size_t n = static_cast<size_t>(ranks_);
    out_ = std::move(out);
    out_sizes_.assign(n, 0);
    in_sizes_.assign(n, 0);
    for (size_t r = 0; r < n; ++r)
      if (int(r) != rank_) out_sizes_[r] = out_[r].size();
    MPI_Ialltoall(out_sizes_.data(), 1, MPI_UINT64_T, in_sizes_.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD, &sizes_);
    requests_.clear();
    // Only the ranks with something to say are sent to or heard from: the neighbouring ones.
    for (size_t r = 0; r < n; ++r)
      for (uint64_t at = 0; at < out_sizes_[r]; at += kPiece) {
        requests_.emplace_back();
        MPI_Isend(out_[r].data() + at, int(std::min(kPiece, out_sizes_[r] - at)), MPI_BYTE, int(r), 0, MPI_COMM_WORLD,
                  &requests_.back());
      }
    receiving_ = false;
  }

  void progress() override {
    if (!receiving_) {
      int sized = 0;
      MPI_Test(&sizes_, &sized, MPI_STATUS_IGNORE);
      if (sized) post_receives();
    }
    int done = 0;
    MPI_Testall(int(requests_.size()), requests_.data(), &done, MPI_STATUSES_IGNORE);
  }

  std::vector<std::vector<std::byte>> finish_exchange() override {
    if (!receiving_) {
      MPI_Wait(&sizes_, MPI_STATUS_IGNORE);
      post_receives();
    }
    MPI_Waitall(int(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE);
    out_.clear();
    return std::move(in_);
  }

  sim::Gathered all_gather(std::span<const std::byte> mine) override {
    const size_t n = static_cast<size_t>(ranks_);
    uint64_t size = mine.size();
    std::vector<uint64_t> sizes(n);
    MPI_Allgather(&size, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD);
    sim::Gathered all(sizes);
    if (all.offset(n) <= uint64_t{INT_MAX}) {  // the usual case: one call, whatever the number of ranks
      std::vector<int> counts(n), at(n);
      for (size_t r = 0; r < n; ++r) counts[r] = int(sizes[r]), at[r] = int(all.offset(r));
      MPI_Allgatherv(mine.data(), int(size), MPI_BYTE, all.data(0), counts.data(), at.data(), MPI_BYTE, MPI_COMM_WORLD);
      return all;
    }
    for (size_t r = 0; r < n; ++r) {  // past 2 GiB in all: each rank's part broadcast in pieces
      if (int(r) == rank_ && size) std::memcpy(all.data(r), mine.data(), size);
      for (uint64_t at = 0; at < sizes[r]; at += kPiece)
        MPI_Bcast(all.data(r) + at, int(std::min(kPiece, sizes[r] - at)), MPI_BYTE, int(r), MPI_COMM_WORLD);
    }
    return all;
  }

  void sum(std::span<uint64_t> values) override {
    MPI_Allreduce(MPI_IN_PLACE, values.data(), int(values.size()), MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
  }

  // METIS's k-way partition, computed on rank 0 (with a fixed seed) and given to all, so that no
  // rank can differ from another by a library's whim.
  std::vector<uint32_t> partition_graph(std::span<const uint32_t> first, std::span<const uint32_t> adjacent,
                                        std::span<const uint32_t> vertex_weight,
                                        std::span<const uint32_t> edge_weight) override {
    std::vector<uint32_t> parts;
    if (rank_ == 0) {
      std::vector<idx_t> xadj(first.begin(), first.end()), adjncy(adjacent.begin(), adjacent.end()),
          vwgt(vertex_weight.begin(), vertex_weight.end()), adjwgt(edge_weight.begin(), edge_weight.end());
      for (idx_t& w : vwgt) w = std::max<idx_t>(w, 1);  // an empty block still weighs something
      idx_t vertices = idx_t(vwgt.size()), constraints = 1, nparts = ranks_, cut = 0;
      std::vector<idx_t> part(vwgt.size(), 0);
      idx_t options[METIS_NOPTIONS];
      METIS_SetDefaultOptions(options);
      options[METIS_OPTION_SEED] = 1;
      if (vertices > nparts &&
          METIS_PartGraphKway(&vertices, &constraints, xadj.data(), adjncy.data(), vwgt.data(), nullptr, adjwgt.data(),
                              &nparts, nullptr, nullptr, options, &cut, part.data()) != METIS_OK)
        part.assign(vwgt.size(), 0);
      if (vertices <= nparts)  // METIS wants more vertices than parts: one block a rank
        for (idx_t v = 0; v < vertices; ++v) part[size_t(v)] = v;
      parts.assign(part.begin(), part.end());
    }
    const sim::Gathered all = all_gather(std::as_bytes(std::span<const uint32_t>(parts)));
    parts.assign(sim::records_of<uint32_t>(all[0]).begin(), sim::records_of<uint32_t>(all[0]).end());
    return parts;
  }

 private:
  void post_receives() {
    const size_t n = static_cast<size_t>(ranks_);
    in_.assign(n, {});
    for (size_t r = 0; r < n; ++r) {
      in_[r].resize(in_sizes_[r]);
      for (uint64_t at = 0; at < in_sizes_[r]; at += kPiece) {
        requests_.emplace_back();
        MPI_Irecv(in_[r].data() + at, int(std::min(kPiece, in_sizes_[r] - at)), MPI_BYTE, int(r), 0, MPI_COMM_WORLD,
                  &requests_.back());
      }
    }
    receiving_ = true;
  }

  int rank_ = 0, ranks_ = 1;
  // The exchange under way: what goes (kept until it has gone), what comes, their sizes, and the
  // requests of both.
  std::vector<std::vector<std::byte>> out_, in_;
  std::vector<uint64_t> out_sizes_, in_sizes_;
  MPI_Request sizes_ = MPI_REQUEST_NULL;
  std::vector<MPI_Request> requests_;
  bool receiving_ = false;  // the sizes have come and the receives are posted
};

}  // namespace

MpiProcess::MpiProcess(int& argc, char**& argv) {
  if (std::getenv("OMPI_COMM_WORLD_SIZE") == nullptr) return;
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  initialized_ = true;
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  if (ranks > 1) exchange_ = std::make_unique<MpiExchange>();
}

MpiProcess::~MpiProcess() {
  exchange_.reset();
  if (initialized_) MPI_Finalize();
}

}  // namespace dw::dist
