#include "shell/interrupts.h"

#include <pthread.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>

namespace dw::shell {
namespace {

sigset_t interrupt_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);
  return set;
}

// Straight to the file descriptor: the main thread may hold std::cerr's buffer.
void say(const std::string& text) {
  const char* p = text.data();
  size_t left = text.size();
  while (left > 0) {
    const ssize_t n = ::write(STDERR_FILENO, p, left);
    if (n <= 0) return;
    p += n;
    left -= size_t(n);
  }
}

// What an exit at once leaves. An output is committed whole or not at all (sim/output_file.h),
// and the process may end before, during or after the commits: each output is either complete
// or absent, never cut short.
constexpr const char* kStoppingAtOnce =
    "stopping at once; an output not yet complete is not written (a file it would replace is left as it "
    "was), outputs already complete are kept\n";

}  // namespace

Interrupts::Interrupts() {
  const sigset_t set = interrupt_signals();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  thread_ = std::thread([this] { watch(); });
}

Interrupts::~Interrupts() {
  {
    std::lock_guard lock(mutex_);
    closing_ = true;
  }
  // Wakes the watcher: a signal sent to one thread is pending for that thread alone.
  pthread_kill(thread_.native_handle(), SIGTERM);
  thread_.join();
}

const char* Interrupts::name(int signal) {
  switch (signal) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return "a signal";
  }
}

void Interrupts::watch() {
  const sigset_t set = interrupt_signals();
  for (;;) {
    int signal = 0;
    if (sigwait(&set, &signal) != 0) continue;
    std::lock_guard lock(mutex_);
    if (closing_) return;
    if (open_ != nullptr && first_ == 0) {
      first_ = signal;
      open_->source_.request_stop();
      continue;
    }
    say(std::string("dwatch: ") + (first_ != 0 ? "interrupted again" : "interrupted") + " (" + name(signal) +
        "): " + kStoppingAtOnce);
    std::_Exit(exit_code(first_ != 0 ? first_ : signal));
  }
}

Interrupts::Stoppable::Stoppable(Interrupts& interrupts) : interrupts_(interrupts) {
  std::lock_guard lock(interrupts_.mutex_);
  interrupts_.open_ = this;
}

Interrupts::Stoppable::~Stoppable() {
  std::lock_guard lock(interrupts_.mutex_);
  if (interrupts_.first_ != 0 && !answered_) {
    say(std::string("dwatch: interrupted (") + name(interrupts_.first_) + "): " + kStoppingAtOnce);
    std::_Exit(exit_code(interrupts_.first_));
  }
  interrupts_.open_ = nullptr;
  // A signal that stopped this stretch has been answered; the next stretch starts afresh, and
  // a signal between the two ends the process.
  interrupts_.first_ = 0;
}

std::optional<int> Interrupts::Stoppable::signal() const {
  std::lock_guard lock(interrupts_.mutex_);
  if (interrupts_.open_ == this && interrupts_.first_ != 0) {
    answered_ = true;
    return interrupts_.first_;
  }
  return std::nullopt;
}

}  // namespace dw::shell
