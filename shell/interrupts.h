// Ctrl-C (SIGINT), SIGTERM and SIGHUP (docs/design.md §6). The three signals are blocked in every
// thread and taken by one thread of this object's, with sigwait, so that nothing runs inside a
// signal handler and the rest of dwatch never sees an interrupted system call.
//
//   - While a command has a Stoppable open, the first signal asks it to stop (its token, polled
//     between steps): the command unwinds, outputs stay uncommitted (their temporaries go with
//     them, sim/output_file.h) and it says what it stopped and where, exiting with 128 + signal.
//   - Otherwise, or at a second signal, the process says so on stderr and exits at once with
//     128 + signal. An output being written then leaves nothing behind either: its temporary has
//     no name until it is committed.
#pragma once

#include <csignal>
#include <mutex>
#include <optional>
#include <stop_token>
#include <string>
#include <thread>

namespace dw::shell {

class Interrupts {
 public:
  // Blocks the signals in the calling thread, which every thread it starts afterwards inherits:
  // make it first in main, before any thread exists.
  Interrupts();
  ~Interrupts();
  Interrupts(const Interrupts&) = delete;
  Interrupts& operator=(const Interrupts&) = delete;

  // A stretch of a command that stops cleanly when asked; the first signal during it requests
  // stop on its token. One at a time. The command asks signal() once the stretch is over; a
  // signal it never heard of (one that came after it last asked) ends the process when the
  // stretch closes, so that none is lost between the asking and the closing.
  class Stoppable {
   public:
    explicit Stoppable(Interrupts& interrupts);
    ~Stoppable();
    Stoppable(const Stoppable&) = delete;
    Stoppable& operator=(const Stoppable&) = delete;
    std::stop_token token() const { return source_.get_token(); }
    // The signal that stopped it, or nothing.
    std::optional<int> signal() const;

   private:
    friend class Interrupts;
    Interrupts& interrupts_;
    std::stop_source source_;
    mutable bool answered_ = false;  // signal() has reported the signal
  };

  // "SIGINT", "SIGTERM", "SIGHUP".
  static const char* name(int signal);
  // The exit code of a process ended by `signal`, as a shell reports it: 128 + signal.
  static int exit_code(int signal) { return 128 + signal; }

 private:
  void watch();

  std::mutex mutex_;
  Stoppable* open_ = nullptr;  // the stoppable stretch under way, if any
  int first_ = 0;              // the signal that stopped it, 0 before any
  bool closing_ = false;
  std::thread thread_;
};

}  // namespace dw::shell
