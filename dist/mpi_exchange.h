// The ranks of a run over Open MPI (docs/design.md §12): the process's MPI lifetime, and the collective
// calls of sim::RankExchange over MPI_COMM_WORLD.
#pragma once

#include <memory>

#include "sim/rank_exchange.h"

namespace dw::dist {

// MPI for the life of the process, when mpirun started it (Open MPI tells its children so in
// OMPI_COMM_WORLD_SIZE); otherwise nothing, and no MPI library call is made. Only the thread that
// made it calls MPI (MPI_THREAD_FUNNELED): the worker threads of a rank never do.
class MpiProcess {
 public:
  MpiProcess(int& argc, char**& argv);
  ~MpiProcess();
  MpiProcess(const MpiProcess&) = delete;
  MpiProcess& operator=(const MpiProcess&) = delete;

  // The ranks, when there are two or more; null in one process.
  sim::RankExchange* ranks() { return exchange_.get(); }

 private:
  bool initialized_ = false;
  std::unique_ptr<sim::RankExchange> exchange_;
};

}  // namespace dw::dist
