// Ctrl-C, SIGTERM and SIGHUP as a user sends them to a running dwatch (shell/interrupts.cpp): the
// run stops, says where, exits 128 + signal, and leaves every file as it was -- no temporary, no
// half-written output, the earlier outputs untouched.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <set>
#include <thread>
#include <vector>

#include "tests/app/cli.h"

extern char** environ;

namespace {

using namespace dw::cli_test;

const fs::path kScenarios = DWATCH_SCENARIOS_DIR;

class Interrupted : public Cli {
 protected:
  // Starts dwatch with `args`, its stdout and stderr in files of the test's directory.
  pid_t start(const std::vector<std::string>& args) {
    std::vector<std::string> all{DWATCH_EXE};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, (dir_ / "stdout").c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    posix_spawn_file_actions_addopen(&files, STDERR_FILENO, (dir_ / "stderr").c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    pid_t pid = -1;
    const int spawned = posix_spawn(&pid, all[0].c_str(), &files, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&files);
    EXPECT_EQ(spawned, 0);
    return pid;
  }
  // Waits until the process has written `bytes` to stdout: it is past its set-up and stepping.
  void wait_for_output(size_t bytes) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (std::chrono::steady_clock::now() < deadline) {
      std::error_code ec;
      if (fs::file_size(dir_ / "stdout", ec) >= bytes && !ec) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    FAIL() << "no output after 120 s";
  }
  static int exit_code(pid_t pid) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  }
  std::set<std::string> files() const {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.insert(e.path().filename().string());
    return names;
  }
};

TEST_F(Interrupted, ARunStopsBetweenStepsSaysWhereAndLeavesEveryFileAsItWas) {
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    SCOPED_TRACE(signal);
    write("matches.jsonl", "the matches of an earlier run\n");
    // The trace goes to stdout, where the test sees the run stepping; the other outputs go to
    // files, one of which exists from before.
    const pid_t pid =
        start({"run", (kScenarios / "table1.toml").string(), "--steps", "1000000", "--no-progress", "--record", "-",
               "--matches", (dir_ / "matches.jsonl").string(), "--stats", (dir_ / "stats.json").string()});
    wait_for_output(1 << 20);
    ::kill(pid, signal);
    EXPECT_EQ(exit_code(pid), 128 + signal);
    const std::string err = slurp(dir_ / "stderr");
    EXPECT_NE(err.find("interrupted (" +
                       std::string(signal == SIGINT    ? "SIGINT"
                                   : signal == SIGTERM ? "SIGTERM"
                                                       : "SIGHUP") +
                       ") after "),
              std::string::npos)
        << err;
    EXPECT_NE(err.find(" of 1000000 steps: nothing written"), std::string::npos) << err;
    EXPECT_EQ(slurp(dir_ / "matches.jsonl"), "the matches of an earlier run\n");
    EXPECT_EQ(files(), (std::set<std::string>{"matches.jsonl", "stderr", "stdout"}))
        << "a temporary or an output stayed";
  }
}

TEST_F(Interrupted, AVideoStopsBetweenFramesAndLeavesTheOldFile) {
  write("old.mp4", "an earlier video\n");
  const pid_t pid = start({"render", (kScenarios / "token_ring.toml").string(), "--video", (dir_ / "old.mp4").string(),
                           "--to", "999999", "--width", "64", "--height", "48"});
  // The video is open once the process holds a file in the test's directory (its unnamed
  // temporary); then it draws frames.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  bool open = false;
  while (!open && std::chrono::steady_clock::now() < deadline) {
    std::error_code ec;
    for (const auto& fd : fs::directory_iterator("/proc/" + std::to_string(pid) + "/fd", ec)) {
      const std::string target = fs::read_symlink(fd.path(), ec).string();
      open = open || (target.rfind(dir_.string() + "/#", 0) == 0 || target.find("(deleted)") != std::string::npos);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(open) << "the video was never opened";
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ::kill(pid, SIGINT);
  EXPECT_EQ(exit_code(pid), 130);
  const std::string err = slurp(dir_ / "stderr");
  EXPECT_NE(err.find("interrupted (SIGINT) after "), std::string::npos) << err;
  EXPECT_NE(
      err.find(" of 1000000 frames: nothing written (--video " + (dir_ / "old.mp4").string() + ": as it was before)"),
      std::string::npos)
      << err;
  EXPECT_EQ(slurp(dir_ / "old.mp4"), "an earlier video\n");
  EXPECT_EQ(files(), (std::set<std::string>{"old.mp4", "stderr", "stdout"})) << "a temporary stayed";
}

TEST_F(Interrupted, ASessionScriptStopsAtTheCommandUnderWay) {
  const fs::path script = write("long.session", "step 1\nrecord " + (dir_ / "early.jsonl").string() +
                                                    "\nrun 1000000\nrecord " + (dir_ / "late.jsonl").string() + "\n");
  const pid_t pid =
      start({"session", (kScenarios / "table1.toml").string(), "--script", script.string(), "--history-mb", "16"});
  // The answers to `step` and `record` come before the long `run`.
  wait_for_output(std::string("{\"cmd\":\"step 1\"").size());
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ::kill(pid, SIGINT);
  EXPECT_EQ(exit_code(pid), 130);
  const std::string err = slurp(dir_ / "stderr");
  EXPECT_NE(err.find(script.string() + ":3: interrupted (SIGINT)"), std::string::npos) << err;
  EXPECT_TRUE(fs::exists(dir_ / "early.jsonl")) << "what was done before stays done";
  EXPECT_FALSE(fs::exists(dir_ / "late.jsonl")) << "the script went on after the signal";
}

// `record f`, f a FIFO no process reads, blocked in open() for ever and the first SIGTERM was
// swallowed (issue 62, 4): the wait for a reader ends at the first signal, which stops the
// script there as it stops any command.
TEST_F(Interrupted, ASignalEndsTheWaitForAFifosReaderAtOnce) {
  const fs::path fifo = dir_ / "f";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const fs::path script = write("fifo.session", "step 1\nrecord " + fifo.string() + "\nstep 1\n");
  const pid_t pid = start({"session", (kScenarios / "token_ring.toml").string(), "--script", script.string()});
  wait_for_output(std::string("{\"cmd\":\"step 1\"").size());
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const auto signalled = std::chrono::steady_clock::now();
  ::kill(pid, SIGTERM);
  EXPECT_EQ(exit_code(pid), 143);
  EXPECT_LT(std::chrono::steady_clock::now() - signalled, std::chrono::seconds(3)) << "the wait went on";
  const std::string err = slurp(dir_ / "stderr");
  EXPECT_NE(err.find(script.string() + ":2: interrupted (SIGTERM)"), std::string::npos) << err;
}

}  // namespace
