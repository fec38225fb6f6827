// Benchmark rows run in a child process, so that each row's peak memory is its own.
#pragma once

#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <iostream>
#include <type_traits>

namespace dw::bench {

// Called in a child just forked from `parent`: it gets `signal` when its parent ends (a bench
// stopped by a signal leaves no row running on).
inline void end_with_parent(pid_t parent, int signal = SIGKILL) {
  for (const int s : {SIGINT, SIGTERM, SIGHUP}) std::signal(s, SIG_DFL);  // the parent says what stopped
  ::prctl(PR_SET_PDEATHSIG, signal);
  if (::getppid() != parent) _exit(1);  // the parent ended before the child asked
}

// Runs `fn` (returning a trivially copyable Result) in a child process; the child's peak resident
// memory goes to `peak_kib`. False when the child failed.
template <class Result, class Fn>
bool in_child(Fn&& fn, Result& result, long& peak_kib) {
  static_assert(std::is_trivially_copyable_v<Result>);
  int pipe_fds[2];
  if (pipe(pipe_fds) != 0) return false;
  std::cout.flush();
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) return false;
  if (pid == 0) {
    end_with_parent(parent);
    close(pipe_fds[0]);
    Result r = fn();
    const ssize_t wrote = write(pipe_fds[1], &r, sizeof r);
    _exit(wrote == static_cast<ssize_t>(sizeof r) ? 0 : 1);
  }
  close(pipe_fds[1]);
  const ssize_t got = read(pipe_fds[0], &result, sizeof result);
  close(pipe_fds[0]);
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  peak_kib = usage.ru_maxrss;
  return got == static_cast<ssize_t>(sizeof result) && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

}  // namespace dw::bench
