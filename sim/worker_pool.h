// A fixed set of threads that run one function over chunk indices 0..n-1 and wait for all of
// them. Work is split into chunks by module id, never by which thread is free, so results never
// depend on the thread count or on timing. When the system refuses a thread (`ulimit -u`, too
// many threads asked), the pool runs with those it got, on the caller's thread alone if it got
// none, and says so once on stderr: the results are the same, only slower.
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
  // Starts a thread running `body`, or throws std::system_error when the system refuses one (as
  // std::thread does). Tests give one that refuses.
  using ThreadStart = std::function<std::thread(std::function<void()> body)>;
  static std::thread start_thread(std::function<void()> body) { return std::thread(std::move(body)); }

  explicit WorkerPool(unsigned threads, const ThreadStart& start = start_thread);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  // The threads it runs on, the caller's included: the number asked for, or fewer when the system
  // refused some.
  unsigned size() const { return size_; }
  // Runs fn(0) .. fn(size() - 1), each on its own thread (fn(0) on the caller's), and returns
  // when all have finished. An exception in any of them is rethrown here.
  void run(const std::function<void(unsigned)>& fn);

 private:
  void work(unsigned index);
  // Tells the threads started to end, and waits for them.
  void stop();

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
