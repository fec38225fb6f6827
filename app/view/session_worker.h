// Long work off the window's frame loop: running, seeking, evaluating a watchpoint over the whole
// history and recording run on one worker thread, one job at a time in the order asked, so the
// window keeps drawing and can cancel (sim::Control). The window reads the session only between
// jobs (try_read), never while one runs: the session itself is not shared between threads.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <stop_token>
#include <thread>

#include "sim/session.h"

namespace dw::view {

class SessionWorker {
 public:
  using Job = std::function<void(sim::Session&, const sim::Control&)>;

  explicit SessionWorker(sim::Session& session);
  ~SessionWorker();  // cancels what runs and waits for it
  SessionWorker(const SessionWorker&) = delete;
  SessionWorker& operator=(const SessionWorker&) = delete;

  // Queues a job; it runs after those queued before it. A background job (the inspector's history)
  // gives way: a job submitted after it stops it (and runs it cancelled if it has not started).
  void submit(Job job, bool background = false);
  // Nothing queued and nothing running.
  bool idle() const;
  // Blocks until idle.
  void wait_idle();
  // Stops the running job at its next step and drops the queued ones.
  void cancel();
  // How far the running job has got (done of total), zeros when none reports.
  std::pair<int64_t, int64_t> progress() const;
  // Jobs finished so far: the window re-reads the session when it changes.
  uint64_t finished() const;

  // Calls `read(session)` on this thread when no job is running; false (not called) otherwise.
  template <class Read>
  bool try_read(Read&& read) {
    std::unique_lock lock(session_mutex_, std::try_to_lock);
    if (!lock.owns_lock()) return false;
    read(session_);
    return true;
  }
  // The same, waiting for the running job: for a script, which goes one command at a time.
  template <class Read>
  void read(Read&& read) {
    std::lock_guard lock(session_mutex_);
    read(session_);
  }

 private:
  void loop(std::stop_token stop);

  sim::Session& session_;
  std::mutex session_mutex_;  // held while a job runs and while the window reads
  mutable std::mutex queue_mutex_;
  std::condition_variable_any queue_changed_;
  std::condition_variable idle_changed_;
  struct Queued {
    Job job;
    bool background = false;
    bool given_way = false;  // a background job a later job stopped before it started
  };
  std::deque<Queued> queue_;
  bool running_ = false, running_background_ = false;
  std::stop_source job_stop_;
  int64_t done_ = 0, total_ = 0;
  uint64_t finished_ = 0;
  std::jthread thread_;  // last: it starts once everything above exists
};

}  // namespace dw::view
