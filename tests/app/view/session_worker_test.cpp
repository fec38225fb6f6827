// The worker that keeps the session's long work off the window's frame loop: jobs in order, the
// session readable only between them, and a cancel that stops the running job and drops the rest.
#include "app/view/session_worker.h"

#include <gtest/gtest.h>

#include <atomic>
#include <latch>

#include "scenarios/scenario.h"

namespace dw::view {
namespace {

struct Worker : ::testing::Test {
  void SetUp() override {
    auto loaded = scenarios::load_scenario(std::string(DWATCH_SCENARIOS_DIR) + "/token_ring_correct.toml");
    ASSERT_TRUE(std::holds_alternative<scenarios::Scenario>(loaded));
    scenario = std::make_unique<scenarios::Scenario>(std::move(std::get<scenarios::Scenario>(loaded)));
    session = std::make_unique<sim::Session>(*scenario->model, *scenario->world,
                                             sim::SessionOptions{1, 0, 64 << 20, scenario->events});
  }
  std::unique_ptr<scenarios::Scenario> scenario;
  std::unique_ptr<sim::Session> session;
};

TEST_F(Worker, RunsJobsInOrderAndCountsThem) {
  SessionWorker worker(*session);
  std::vector<int64_t> seen;
  for (int64_t t : {10, 4, 25})
    worker.submit([&, t](sim::Session& s, const sim::Control& c) {
      if (t > s.latest()) s.run_until(t + 1, {}, c);
      else s.seek(t, c);
      seen.push_back(s.current());
    });
  worker.wait_idle();
  EXPECT_TRUE(worker.idle());
  EXPECT_EQ(worker.finished(), 3u);
  EXPECT_EQ(seen, (std::vector<int64_t>{10, 4, 25}));
}

TEST_F(Worker, TheSessionIsReadOnlyBetweenJobs) {
  SessionWorker worker(*session);
  std::latch started(1), release(1);
  worker.submit([&](sim::Session& s, const sim::Control&) {
    started.count_down();
    release.wait();
    s.run_until(5);
  });
  started.wait();
  bool called = false;
  EXPECT_FALSE(worker.try_read([&](sim::Session&) { called = true; }));
  EXPECT_FALSE(called);
  EXPECT_FALSE(worker.idle());
  release.count_down();
  worker.wait_idle();
  int64_t current = -2;
  EXPECT_TRUE(worker.try_read([&](sim::Session& s) { current = s.current(); }));
  EXPECT_EQ(current, 4);
}

TEST_F(Worker, CancelStopsTheRunningJobAndDropsTheQueuedOnes) {
  SessionWorker worker(*session);
  std::latch stepping(1);
  std::atomic<bool> later_ran = false;
  worker.submit([&](sim::Session& s, const sim::Control& c) {
    sim::Control reporting = c;
    std::atomic<bool> told = false;
    reporting.progress = [&](int64_t done, int64_t total) {
      c.progress(done, total);
      if (!told.exchange(true)) stepping.count_down();
    };
    s.run_until(
        1'000'000,
        [&](const sim::State&, const sim::StepOutput&) {
          if (!told.exchange(true)) stepping.count_down();
        },
        reporting);
  });
  worker.submit([&](sim::Session&, const sim::Control&) { later_ran = true; });
  stepping.wait();
  worker.cancel();
  worker.wait_idle();
  EXPECT_FALSE(later_ran);
  int64_t current = -2;
  worker.try_read([&](sim::Session& s) { current = s.current(); });
  EXPECT_GE(current, 0);
  EXPECT_LT(current, 999'999) << "the run stopped where it had got to";
}

TEST_F(Worker, ABackgroundJobGivesWayToTheNextCommand) {
  SessionWorker worker(*session);
  std::latch started(1);
  std::atomic<bool> background_stopped = false, queued_background_ran = false, queued_background_cancelled = false;
  worker.submit(
      [&](sim::Session&, const sim::Control& c) {
        started.count_down();
        while (!c.stopped()) std::this_thread::yield();
        background_stopped = true;
      },
      true);
  started.wait();
  worker.submit(
      [&](sim::Session&, const sim::Control& c) {
        queued_background_cancelled = c.stopped();
        queued_background_ran = true;
      },
      true);
  int64_t seen = -2;
  worker.submit([&](sim::Session& s, const sim::Control&) {
    s.run_until(3);
    seen = s.current();
  });
  worker.wait_idle();
  EXPECT_TRUE(background_stopped);
  // A background job waiting behind a command runs cancelled: its asker learns it did not finish
  // (the Module panel's and Group tab's readers would otherwise wait for it for ever).
  EXPECT_TRUE(queued_background_ran);
  EXPECT_TRUE(queued_background_cancelled);
  EXPECT_EQ(seen, 2);
}

}  // namespace
}  // namespace dw::view
