// The dwatch executable run as a user runs it, for the command-line tests: exit code, stdout
// and stderr, in a fresh directory per test.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>

namespace dw::cli_test {

namespace fs = std::filesystem;

struct Result {
  int code;
  std::string out, err;
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dwatch_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Runs dwatch with `args` (already shell-quoted as needed).
  Result run(const std::string& args) { return run_with_env("", args); }
  // The same with environment variables set for it: "NAME=value ...".
  Result run_with_env(const std::string& env, const std::string& args) {
    const fs::path out = dir_ / "stdout", err = dir_ / "stderr";
    const std::string cmd =
        env + " " + std::string(DWATCH_EXE) + " " + args + " >" + out.string() + " 2>" + err.string();
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
  }

  // That dwatch refuses `args` as bad input (exit 2) with exactly `message` on stderr.
  void expect_refused(const std::string& args, const std::string& message) {
    const Result r = run(args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_EQ(r.err, message) << args;
  }

  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }

  fs::path dir_;
  const fs::path cases_ = DWATCH_CONFORMANCE_DIR;
};

// The command line on group shapes and state modes (docs/design.md §4a), in the files of the
// commands it runs.
class ShapesCli : public Cli {};

// A PNG's size, from its IHDR chunk.
inline std::pair<uint32_t, uint32_t> png_size(const fs::path& p) {
  const std::string s = slurp(p);
  if (s.size() < 24 || s.compare(1, 3, "PNG") != 0) return {0, 0};
  auto be32 = [&](size_t at) {
    return uint32_t(uint8_t(s[at])) << 24 | uint32_t(uint8_t(s[at + 1])) << 16 | uint32_t(uint8_t(s[at + 2])) << 8 |
           uint32_t(uint8_t(s[at + 3]));
  };
  return {be32(16), be32(20)};
}

}  // namespace dw::cli_test
