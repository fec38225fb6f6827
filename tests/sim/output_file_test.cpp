// Output files never destroy anything: a failed write leaves the old file and no temporary behind,
// a device is written in place and never removed, and a complete write lands whole.
#include "sim/output_file.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace dw::sim {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class OutputFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dwatch_output_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  size_t entries() const {
    return static_cast<size_t>(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }
  // Whether this file system has unnamed temporaries (O_TMPFILE): then a write under way shows
  // no file at all.
  bool unnamed_temporaries() const {
    const int fd = ::open(dir_.c_str(), O_TMPFILE | O_WRONLY, 0600);
    if (fd < 0) return false;
    ::close(fd);
    return true;
  }
  fs::path dir_;
};

TEST_F(OutputFileTest, NothingReachesTheTargetBeforeCommit) {
  const fs::path p = dir_ / "out.txt";
  std::ofstream(p) << "old";
  std::string error;
  auto out = OutputFile::open(p.string(), &error);
  ASSERT_TRUE(out) << error;
  out->stream() << "new contents";
  EXPECT_EQ(slurp(p), "old") << "the old file stays until the new one is complete";
  EXPECT_EQ(entries(), unnamed_temporaries() ? 1u : 2u) << "a named temporary sits beside it, an unnamed one nowhere";
  EXPECT_EQ(out->commit(), "");
  EXPECT_EQ(slurp(p), "new contents");
  EXPECT_EQ(entries(), 1u) << "no temporary left behind";
}

TEST_F(OutputFileTest, AnAbandonedWriteLeavesTheOldFileAndNoTemporary) {
  const fs::path p = dir_ / "out.txt";
  std::ofstream(p) << "old";
  {
    auto out = OutputFile::open(p.string(), nullptr);
    ASSERT_TRUE(out);
    out->stream() << "half";
  }
  EXPECT_EQ(slurp(p), "old");
  EXPECT_EQ(entries(), 1u);
}

TEST_F(OutputFileTest, AFailedWriteLeavesTheOldFileAndSaysWhy) {
  // A file-size limit makes write() fail with EFBIG part way, as a full disk would.
  const fs::path p = dir_ / "out.txt";
  std::ofstream(p) << "old";
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    std::string error = "not opened";
    if (auto out = OutputFile::open(p.string(), nullptr)) {
      out->stream() << std::string(1 << 20, 'x');
      error = out->commit();
    }  // its temporary is removed here, before _exit
    ::_exit(error.find("File too large") != std::string::npos && error.find(p.string()) != std::string::npos ? 0 : 11);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "the error did not name the path and the reason";
  EXPECT_EQ(slurp(p), "old");
  EXPECT_EQ(entries(), 1u) << "no temporary left behind";
}

TEST_F(OutputFileTest, AWriterKilledMidWriteLeavesTheOldFileAndNothingElse) {
  if (!unnamed_temporaries()) GTEST_SKIP() << "no O_TMPFILE on this file system: a named temporary would stay";
  const fs::path p = dir_ / "out.txt";
  std::ofstream(p) << "old";
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    auto out = OutputFile::open(p.string(), nullptr);
    if (out) out->stream() << std::string(1 << 20, 'x') << std::flush;
    ::raise(SIGKILL);  // no destructor, no handler: only the kernel cleans up
    ::_exit(1);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(slurp(p), "old");
  EXPECT_EQ(entries(), 1u) << "a killed writer left its temporary behind";
}

TEST_F(OutputFileTest, ADeviceIsWrittenInPlaceAndNeverRemoved) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  std::string error;
  auto out = OutputFile::open("/dev/full", &error);
  ASSERT_TRUE(out) << error;
  out->stream() << std::string(1 << 17, 'x');
  const std::string failed = out->commit();
  EXPECT_NE(failed.find("No space left on device"), std::string::npos) << failed;
  out.reset();
  EXPECT_TRUE(fs::is_character_file("/dev/full")) << "the device node is still there";
  auto null = OutputFile::open("/dev/null", &error);
  ASSERT_TRUE(null) << error;
  null->stream() << "gone";
  EXPECT_EQ(null->commit(), "");
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
}

TEST_F(OutputFileTest, KeepsTheModeOfTheFileItReplacesAndWritesThroughASymlink) {
  const fs::path real = dir_ / "real.txt", link = dir_ / "link.txt";
  std::ofstream(real) << "old";
  fs::permissions(real, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  fs::create_symlink(real, link);
  ASSERT_EQ(write_file(link.string(), std::vector<uint8_t>{'n', 'e', 'w'}), "");
  EXPECT_TRUE(fs::is_symlink(link)) << "the link stays a link";
  EXPECT_EQ(slurp(real), "new");
  EXPECT_EQ(fs::status(real).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
}

TEST_F(OutputFileTest, BadPathsAreRefusedWithTheReason) {
  std::string error;
  EXPECT_FALSE(OutputFile::open((dir_ / "no" / "such" / "dir.txt").string(), &error));
  EXPECT_NE(error.find("No such file or directory"), std::string::npos) << error;
  EXPECT_FALSE(OutputFile::open(dir_.string(), &error));
  EXPECT_NE(error.find("Is a directory"), std::string::npos) << error;
  EXPECT_EQ(entries(), 0u);
}

// A path through a directory that does not exist is refused as the kernel refuses it, even where
// it reads, once normalized, as a file that exists: "nosuch/../kept.txt" must not replace
// kept.txt (an input, perhaps).
TEST_F(OutputFileTest, APathThroughAMissingDirectoryIsRefusedNotNormalizedAway) {
  std::ofstream(dir_ / "kept.txt") << "input";
  std::ofstream(dir_ / "plain") << "a file";
  std::string error;
  for (const fs::path& through :
       {dir_ / "nosuch" / ".." / "kept.txt", dir_ / "plain" / ".." / "kept.txt", dir_ / "nosuch" / ".." / "new.txt"}) {
    error.clear();
    EXPECT_FALSE(OutputFile::open(through.string(), &error)) << through;
    EXPECT_FALSE(error.empty()) << through;
  }
  EXPECT_EQ(slurp(dir_ / "kept.txt"), "input");
  EXPECT_EQ(entries(), 2u);
  // Through a directory that exists, ".." is the kernel's own: the file is written.
  fs::create_directory(dir_ / "there");
  auto out = OutputFile::open((dir_ / "there" / ".." / "new.txt").string(), &error);
  ASSERT_TRUE(out) << error;
  out->stream() << "new";
  EXPECT_EQ(out->commit(), "");
  EXPECT_EQ(slurp(dir_ / "new.txt"), "new");
}

// A FIFO no process reads (`record f`, f a FIFO) blocked open() for ever, and a signal did not end
// it: its reader is waited for a bounded time, then the write is refused saying why. A reader that
// stops reading stalls a write no longer than that either.
TEST_F(OutputFileTest, AFifoWithoutAReaderIsRefusedWithinTheWait) {
  const fs::path fifo = dir_ / "f";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string error;
  const auto started = std::chrono::steady_clock::now();
  EXPECT_EQ(OutputFile::open(fifo.string(), &error, std::chrono::milliseconds(200)), nullptr);
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(5));
  EXPECT_NE(error.find("no process opened this FIFO to read it within 200 ms"), std::string::npos) << error;

  const int reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);  // opens it, never reads
  ASSERT_GE(reader, 0);
  auto out = OutputFile::open(fifo.string(), &error, std::chrono::milliseconds(200));
  ASSERT_NE(out, nullptr) << error;
  out->stream() << std::string(size_t{4} << 20, 'x');  // far more than a pipe holds
  const std::string failed = out->commit();
  EXPECT_NE(failed.find("nothing read what was written for 200 ms"), std::string::npos) << failed;
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(10));
  ::close(reader);
  EXPECT_TRUE(fs::exists(fifo)) << "a FIFO is never removed";
}

}  // namespace
}  // namespace dw::sim
