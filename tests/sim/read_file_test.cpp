// Reading inputs (sim/read_file.cpp): whatever a path names, a limit, and no binary text.
#include "sim/read_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <future>
#include <thread>

namespace dw::sim {
namespace {

namespace fs = std::filesystem;

class ReadFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dwatch_read_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(ReadFile, ReadsATextFileWhole) {
  std::ofstream(dir_ / "a.txt") << "one\ntwo\n";
  std::string error;
  EXPECT_EQ(read_file((dir_ / "a.txt").string(), &error), "one\ntwo\n");
  EXPECT_FALSE(read_file(dir_.string(), &error));
  EXPECT_NE(error.find("Is a directory"), std::string::npos) << error;
}

// A byte-order mark some editors write first is no character of any dwatch language: a text
// input drops it (a session script said "unknown command 'step'" with the mark invisible in
// it), from a file or a pipe; bytes read as bytes keep it, and one further in stays.
TEST_F(ReadFile, ATextInputDropsTheByteOrderMarkItStartsWith) {
  const std::string mark = "\xEF\xBB\xBF";
  std::ofstream(dir_ / "bom.txt") << mark << "step 2\n" << mark;
  std::string error;
  EXPECT_EQ(read_file((dir_ / "bom.txt").string(), &error), "step 2\n" + mark);
  EXPECT_EQ(read_file((dir_ / "bom.txt").string(), &error, kMaxTextInput, false), mark + "step 2\n" + mark);
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  ASSERT_EQ(::write(fds[1], (mark + "x").data(), 4), 4);
  ::close(fds[1]);
  EXPECT_EQ(read_stream(fds[0], "standard input", &error), "x");
  ::close(fds[0]);
  std::ofstream(dir_ / "only.txt") << mark;
  EXPECT_EQ(read_file((dir_ / "only.txt").string(), &error), "");
}

TEST_F(ReadFile, AFileOverTheLimitIsRefusedByItsSizeWithoutReadingIt) {
  const fs::path big = dir_ / "big";
  { std::ofstream(big) << "x"; }
  fs::resize_file(big, size_t(3) << 30);  // 3 GiB of NUL bytes, sparse: nothing to read in time
  std::string error;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(read_file(big.string(), &error));
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  EXPECT_NE(error.find("it holds 3.0 GiB, more than the 8 MiB an input of this kind may hold"), std::string::npos)
      << error;
  // Within a larger limit (a trace's), it is refused at its first NUL byte, not read whole.
  EXPECT_FALSE(read_file(big.string(), &error, size_t(4) << 30));
  EXPECT_NE(error.find("a NUL byte at line 1, column 2: it is not a text file"), std::string::npos) << error;
}

TEST_F(ReadFile, ADeviceOrAPipeIsReadWithTheLimit) {
  std::string error;
  EXPECT_FALSE(read_file("/dev/zero", &error));
  EXPECT_NE(error.find("a NUL byte at line 1, column 1"), std::string::npos) << error;
  // An endless pipe of text: read up to the limit, then refused.
  const fs::path fifo = dir_ / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&] {
    std::signal(SIGPIPE, SIG_IGN);
    std::ofstream out(fifo);
    const std::string line(4096, 'a');
    for (int i = 0; i < 10000 && out; ++i) out << line;  // 40 MiB, unless the reader stops first
  });
  EXPECT_FALSE(read_file(fifo.string(), &error, size_t(1) << 20));
  EXPECT_NE(error.find("more than the 1 MiB an input of this kind may hold"), std::string::npos) << error;
  writer.join();
}

TEST_F(ReadFile, AFifoWithoutAWriterIsRefusedAfterAWait) {
  // open() of a FIFO nobody writes to blocked for ever.
  const fs::path fifo = dir_ / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string error;
  EXPECT_FALSE(read_file_blocks(fifo.string(), &error, size_t(1) << 20, true, std::chrono::milliseconds(200)));
  EXPECT_EQ(error, "cannot read " + fifo.string() + ": it is a FIFO that was not written to its end within 200 ms");
  // A writer that comes within the wait is read from.
  std::thread writer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    std::ofstream(fifo) << "late";
  });
  const auto read = read_file_blocks(fifo.string(), &error, size_t(1) << 20, true, std::chrono::milliseconds(5000));
  writer.join();
  ASSERT_TRUE(read) << error;
  EXPECT_EQ(read->blocks.at(0), "late");
}

// A writer that sends a little and then nothing more (or a byte now and then) holds the reader
// no longer than a writer that never came: the wait covers the FIFO's whole reading.
TEST_F(ReadFile, AFifoWhoseWriterStallsIsRefusedAtTheSameWait) {
  const fs::path fifo = dir_ / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::promise<void> done;
  std::thread writer([&, finished = done.get_future()] {
    std::ofstream out(fifo);
    out << "modules(a);" << std::flush;
    finished.wait();  // holds the FIFO open, writing nothing
  });
  std::string error;
  const auto started = std::chrono::steady_clock::now();
  EXPECT_FALSE(read_file_blocks(fifo.string(), &error, size_t(1) << 20, true, std::chrono::milliseconds(300)));
  const auto took = std::chrono::steady_clock::now() - started;
  done.set_value();
  writer.join();
  EXPECT_EQ(error, "cannot read " + fifo.string() + ": it is a FIFO that was not written to its end within 300 ms");
  EXPECT_LT(took, std::chrono::seconds(5));
}

TEST_F(ReadFile, ANulByteIsPlacedAtItsLineAndColumn) {
  std::ofstream(dir_ / "nul.toml", std::ios::binary) << std::string("a = 1\nbc\0d", 10);
  std::string error;
  EXPECT_FALSE(read_file((dir_ / "nul.toml").string(), &error));
  EXPECT_NE(error.find("a NUL byte at line 2, column 3"), std::string::npos) << error;
  // Binary is fine where it is asked for.
  EXPECT_TRUE(read_file((dir_ / "nul.toml").string(), &error, kMaxTextInput, false));
}

}  // namespace
}  // namespace dw::sim
