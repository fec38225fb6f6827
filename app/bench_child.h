// Benchmark rows run in a child process, so that each row's peak memory is its own.
#pragma once

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <iostream>
#include <type_traits>

namespace dw::app {

// Runs `fn` (returning a trivially copyable Result) in a child process; the child's peak resident
// memory goes to `peak_kib`. False when the child failed.
template <class Result, class Fn>
bool in_child(Fn&& fn, Result& result, long& peak_kib) {
  static_assert(std::is_trivially_copyable_v<Result>);
  int pipe_fds[2];
  if (pipe(pipe_fds) != 0) return false;
  std::cout.flush();
  const pid_t pid = fork();
  if (pid < 0) return false;
  if (pid == 0) {
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

}  // namespace dw::app
