// A fixed set of threads that run one function over chunk indices 0..n-1 and wait for all of
// them. Work is split into chunks by module id, never by which thread is free, so results never
// depend on the thread count or on timing.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace dw::sim {

class WorkerPool {
 public:
  explicit WorkerPool(unsigned threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  unsigned size() const { return size_; }
  // Runs fn(0) .. fn(size() - 1), each on its own thread (fn(0) on the caller's), and returns
  // when all have finished. An exception in any of them is rethrown here.
  void run(const std::function<void(unsigned)>& fn);

 private:
  void work(unsigned index);

  unsigned size_;
  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable start_, done_;
  const std::function<void(unsigned)>* job_ = nullptr;
  uint64_t generation_ = 0;
  unsigned pending_ = 0;
  bool quit_ = false;
  std::exception_ptr error_;
};

}  // namespace dw::sim
