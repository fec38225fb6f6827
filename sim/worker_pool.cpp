#include "sim/worker_pool.h"

#include <iostream>
#include <system_error>

namespace dw::sim {

// A thread the system refuses is no reason to stop: the work is split by module, not by thread,
// so the pool runs on the threads it got. Anything else thrown meanwhile (memory) ends the threads
// started before it goes on: a pool left half made aborted (a joinable thread destroyed) or hung
// (a condition variable destroyed under its waiting threads).
WorkerPool::WorkerPool(unsigned threads, const ThreadStart& start) : size_(threads == 0 ? 1 : threads) {
  threads_.reserve(size_ - 1);  // before any thread starts: keeping one never throws
  try {
    for (unsigned i = 1; i < size_; ++i) threads_.push_back(start([this, i] { work(i); }));
  } catch (const std::system_error& refused) {
    const unsigned asked = size_;
    size_ = static_cast<unsigned>(threads_.size()) + 1;
    std::cerr << "dwatch: warning: the system refused a thread (" << refused.code().message() << "): running on "
              << size_ << " of the " << asked
              << " threads asked for (--threads, `threads`; the results are the same)\n";
  } catch (...) {
    stop();
    throw;
  }
}

WorkerPool::~WorkerPool() { stop(); }

void WorkerPool::stop() {
  {
    std::lock_guard lock(mutex_);
    quit_ = true;
  }
  start_.notify_all();
  for (std::thread& t : threads_) t.join();
  threads_.clear();
}

void WorkerPool::run(const std::function<void(unsigned)>& fn) {
  if (size_ == 1) return fn(0);
  {
    std::lock_guard lock(mutex_);
    job_ = &fn;
    pending_ = size_ - 1;
    error_ = nullptr;
    ++generation_;
  }
  start_.notify_all();
  std::exception_ptr mine;
  try {
    fn(0);
  } catch (...) {
    mine = std::current_exception();
  }
  std::unique_lock lock(mutex_);
  done_.wait(lock, [&] { return pending_ == 0; });
  job_ = nullptr;
  if (mine) std::rethrow_exception(mine);
  if (error_) std::rethrow_exception(error_);
}

void WorkerPool::work(unsigned index) {
  uint64_t seen = 0;
  for (;;) {
    const std::function<void(unsigned)>* job;
    {
      std::unique_lock lock(mutex_);
      start_.wait(lock, [&] { return quit_ || generation_ != seen; });
      if (quit_) return;
      seen = generation_;
      job = job_;
    }
    std::exception_ptr failed;
    try {
      (*job)(index);
    } catch (...) {
      failed = std::current_exception();
    }
    {
      std::lock_guard lock(mutex_);
      if (failed && !error_) error_ = failed;
      if (--pending_ == 0) done_.notify_one();
    }
  }
}

}  // namespace dw::sim
