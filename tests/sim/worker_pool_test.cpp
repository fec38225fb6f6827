// The worker pool when the system refuses threads (`ulimit -u`): it runs on the threads it got,
// or on the caller's alone, and says so once; never an abort (a joinable thread destroyed) nor a
// hang (a condition variable destroyed under its waiting threads), as a pool whose constructor
// threw left it.
#include "sim/worker_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cerrno>
#include <new>
#include <system_error>
#include <vector>

namespace dw::sim {
namespace {

// Starts `allowed` threads, then fails as the system does (std::thread's std::system_error), or
// with `failure` when one is given.
WorkerPool::ThreadStart refusing_after(unsigned allowed, std::exception_ptr failure = nullptr) {
  auto started = std::make_shared<unsigned>(0);
  return [=](std::function<void()> body) {
    if (*started == allowed) {
      if (failure) std::rethrow_exception(failure);
      throw std::system_error(EAGAIN, std::generic_category(), "Resource temporarily unavailable");
    }
    ++*started;
    return std::thread(std::move(body));
  };
}

// Every index of the pool's size runs once, a few times over.
void expect_runs_every_index(WorkerPool& pool) {
  for (int round = 0; round < 3; ++round) {
    std::vector<std::atomic<int>> ran(pool.size());
    pool.run([&](unsigned i) { ++ran[i]; });
    for (unsigned i = 0; i < pool.size(); ++i) EXPECT_EQ(ran[i].load(), 1) << "index " << i;
  }
}

TEST(WorkerPool, RunsOnTheThreadsTheSystemGaveAndSaysSoOnce) {
  testing::internal::CaptureStderr();
  {
    WorkerPool pool(64, refusing_after(27));
    EXPECT_EQ(pool.size(), 28u);
    expect_runs_every_index(pool);
  }
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_EQ(said,
            "dwatch: warning: the system refused a thread (Resource temporarily unavailable): running on 28 of the 64 "
            "threads asked for (--threads, `threads`; the results are the same)\n");
}

TEST(WorkerPool, RunsOnTheCallersThreadWhenTheSystemGaveNone) {
  testing::internal::CaptureStderr();
  {
    WorkerPool pool(8, refusing_after(0));
    EXPECT_EQ(pool.size(), 1u);
    expect_runs_every_index(pool);
  }
  EXPECT_NE(testing::internal::GetCapturedStderr().find("running on 1 of the 8 threads"), std::string::npos);
}

// Another failure while threads start (memory) is thrown on, after the threads already started
// have ended: the pool's destructor does not run for a constructor that threw.
TEST(WorkerPool, AnotherFailureWhileStartingEndsTheThreadsStartedAndIsThrown) {
  EXPECT_THROW(WorkerPool(8, refusing_after(3, std::make_exception_ptr(std::bad_alloc()))), std::bad_alloc);
}

TEST(WorkerPool, AnExceptionInAThreadIsRethrownByRun) {
  WorkerPool pool(4);
  EXPECT_EQ(pool.size(), 4u);
  EXPECT_THROW(pool.run([](unsigned i) {
    if (i == 2) throw std::runtime_error("x");
  }),
               std::runtime_error);
  expect_runs_every_index(pool);
}

}  // namespace
}  // namespace dw::sim
