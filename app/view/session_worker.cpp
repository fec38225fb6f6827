#include "app/view/session_worker.h"

namespace dw::view {

SessionWorker::SessionWorker(sim::Session& session)
    : session_(session), thread_([this](std::stop_token stop) { loop(stop); }) {}

SessionWorker::~SessionWorker() {
  cancel();
  thread_.request_stop();
  queue_changed_.notify_all();
}

void SessionWorker::submit(Job job, bool background) {
  {
    std::lock_guard lock(queue_mutex_);
    if (!background) {
      // Queued background jobs give way: each still runs, at once cancelled, so that it can say it
      // did not finish (its asker would otherwise wait for it for ever).
      for (Queued& q : queue_) q.given_way = q.given_way || q.background;
      if (running_ && running_background_) job_stop_.request_stop();
    }
    queue_.push_back({std::move(job), background});
  }
  queue_changed_.notify_all();
}

bool SessionWorker::idle() const {
  std::lock_guard lock(queue_mutex_);
  return queue_.empty() && !running_;
}

void SessionWorker::wait_idle() {
  std::unique_lock lock(queue_mutex_);
  idle_changed_.wait(lock, [&] { return queue_.empty() && !running_; });
}

void SessionWorker::cancel() {
  std::lock_guard lock(queue_mutex_);
  queue_.clear();
  job_stop_.request_stop();
  if (!running_) idle_changed_.notify_all();
}

std::pair<int64_t, int64_t> SessionWorker::progress() const {
  std::lock_guard lock(queue_mutex_);
  return {done_, total_};
}

uint64_t SessionWorker::finished() const {
  std::lock_guard lock(queue_mutex_);
  return finished_;
}

void SessionWorker::loop(std::stop_token stop) {
  for (;;) {
    Job job;
    sim::Control control;
    {
      std::unique_lock lock(queue_mutex_);
      if (!queue_changed_.wait(lock, stop, [&] { return !queue_.empty(); })) return;
      job = std::move(queue_.front().job);
      running_background_ = queue_.front().background;
      job_stop_ = std::stop_source();
      if (queue_.front().given_way) job_stop_.request_stop();
      queue_.pop_front();
      running_ = true;
      done_ = total_ = 0;
      control.stop = job_stop_.get_token();
    }
    control.progress = [this](int64_t done, int64_t total) {
      std::lock_guard lock(queue_mutex_);
      done_ = done;
      total_ = total;
    };
    {
      std::lock_guard lock(session_mutex_);
      job(session_, control);
    }
    {
      std::lock_guard lock(queue_mutex_);
      running_ = false;
      ++finished_;
    }
    idle_changed_.notify_all();
  }
}

}  // namespace dw::view
