#include "sim/read_file.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string_view>
#include <vector>

namespace dw::sim {
namespace {

std::string reason(const std::string& path, int code) { return "cannot read " + path + ": " + std::strerror(code); }

std::string wait_text(std::chrono::milliseconds wait) {
  return wait.count() % 1000 == 0 ? std::to_string(wait.count() / 1000) + " s" : std::to_string(wait.count()) + " ms";
}

// What some editors (Notepad) write at the start of a UTF-8 file: no character of any of dwatch's
// languages, and invisible in the editor, so a text input drops it rather than reporting it.
constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";

// Reads `fd` to its end; nothing with `error` set when it fails, holds more than `max_bytes` or
// (for text) a NUL byte.
//
// The bytes go into blocks of 64 MiB, joined at the end into a string of the exact size, each
// block let go once copied: a string grown by doubling holds up to twice what it read and, while it
// grows, its old and new buffers together (a trace from a pipe took 10.5 GB before its 7.3 GiB
// limit refused it). Reading takes the limit and one block; joining, the total and one block.
// A FIFO (`fifo`: opened without blocking) is read only until the deadline: a writer that sends a
// byte now and then, or stops, never holds dwatch for longer.
std::optional<ReadBlocks> read_all(int fd, const std::string& name, std::string* error, size_t max_bytes, bool text,
                                   size_t expected, bool fifo = false,
                                   std::chrono::milliseconds fifo_wait = kFifoWriterWait) {
  const auto deadline = std::chrono::steady_clock::now() + fifo_wait;
  const auto fail = [&](const std::string& why) {
    if (error) *error = "cannot read " + name + ": " + why;
    return std::nullopt;
  };
  constexpr size_t kBlock = size_t(64) << 20;
  std::vector<std::string> blocks;
  size_t total = 0;
  for (;;) {
    if (blocks.empty() || blocks.back().size() == kBlock) {
      blocks.emplace_back();
      // A first block as large as the file (a large file refused at its first bytes, a NUL,
      // costs nothing more).
      blocks.back().reserve(
          std::min({blocks.size() == 1 ? std::max<size_t>(expected, 1 << 16) : kBlock, kBlock, max_bytes - total + 1}));
    }
    std::string& block = blocks.back();
    const size_t room = std::min(kBlock - block.size(), size_t(1) << 16);
    if (fifo) {
      // Linux reports neither data nor a hang-up on a FIFO no writer has opened yet: poll waits.
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      pollfd waiting{fd, POLLIN, 0};
      const int ready = ::poll(&waiting, 1, int(std::max<int64_t>(0, left.count())));
      if (ready < 0 && errno != EINTR) return fail(std::strerror(errno));
      if (ready == 0) return fail("it is a FIFO that was not written to its end within " + wait_text(fifo_wait));
    }
    const size_t old_size = block.size();
    block.resize(old_size + room);
    const ssize_t n = ::read(fd, block.data() + old_size, room);
    block.resize(old_size + size_t(std::max<ssize_t>(n, 0)));
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN) continue;
      return fail(std::strerror(errno));
    }
    if (text)
      if (const void* at = std::memchr(block.data() + old_size, 0, size_t(n))) {
        // Lines are counted only to place a NUL byte, once one is found.
        const size_t nul = total + size_t(static_cast<const char*>(at) - (block.data() + old_size));
        size_t lines = 1, line_start = 0, seen = 0;
        for (const std::string& b : blocks)
          for (size_t i = 0; i < b.size() && seen < nul; ++i, ++seen)
            if (b[i] == '\n') ++lines, line_start = seen + 1;
        return fail("a NUL byte at line " + std::to_string(lines) + ", column " + std::to_string(nul - line_start + 1) +
                    ": it is not a text file");
      }
    total += size_t(n);
    if (total > max_bytes) return fail("more than the " + size_text(max_bytes) + " an input of this kind may hold");
  }
  if (text && blocks[0].starts_with(kByteOrderMark)) {
    blocks[0].erase(0, kByteOrderMark.size());
    total -= kByteOrderMark.size();
  }
  return ReadBlocks{std::move(blocks), total};
}

std::optional<std::string> joined(std::optional<ReadBlocks> read) {
  if (!read) return std::nullopt;
  if (read->blocks.size() == 1) return std::move(read->blocks[0]);
  std::string bytes;
  bytes.reserve(read->size);
  for (std::string& b : read->blocks) {
    bytes += b;
    std::string().swap(b);
  }
  return bytes;
}

}  // namespace

std::string size_text(size_t bytes) {
  char text[32];
  if (bytes >= (size_t(1) << 30)) std::snprintf(text, sizeof text, "%.1f GiB", double(bytes) / double(1u << 30));
  else if (bytes >= (size_t(1) << 20) && bytes % (size_t(1) << 20) == 0)
    std::snprintf(text, sizeof text, "%zu MiB", bytes >> 20);
  else if (bytes >= (size_t(1) << 20)) std::snprintf(text, sizeof text, "%.1f MiB", double(bytes) / double(1u << 20));
  else std::snprintf(text, sizeof text, "%zu bytes", bytes);
  return text;
}

size_t available_memory() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  size_t kib = 0;
  std::string unit;
  while (in >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib << 10;
  return 0;
}

std::string check_readable(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return reason(path, errno);
  if (S_ISDIR(st.st_mode)) return reason(path, EISDIR);
  if (::access(path.c_str(), R_OK) != 0) return reason(path, errno);
  return {};
}

std::optional<std::string> read_stream(int fd, const std::string& name, std::string* error, size_t max_bytes,
                                       bool text) {
  return joined(read_all(fd, name, error, max_bytes, text, 0));
}

std::optional<std::string> read_file(const std::string& path, std::string* error, size_t max_bytes, bool text,
                                     std::chrono::milliseconds fifo_wait) {
  return joined(read_file_blocks(path, error, max_bytes, text, fifo_wait));
}

std::optional<ReadBlocks> read_file_blocks(const std::string& path, std::string* error, size_t max_bytes, bool text,
                                           std::chrono::milliseconds fifo_wait) {
  const auto fail = [&](int code) {
    if (error) *error = reason(path, code);
    return std::nullopt;
  };
  // Opened without waiting: a FIFO no program has opened for writing would block open() for ever
  // (a scenario from someone else may name one); it is given `fifo_wait` to get something to read.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return fail(errno);
  struct stat st {};
  if (::fstat(fd, &st) != 0 || S_ISDIR(st.st_mode)) {
    const int code = S_ISDIR(st.st_mode) ? EISDIR : errno;
    ::close(fd);
    return fail(code);
  }
  const bool fifo = S_ISFIFO(st.st_mode);
  if (!fifo) ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);  // reads wait for a pipe's writer
  // A file's size is known before reading it; a pipe's or a device's is not, and the limit
  // stops the reading.
  if (S_ISREG(st.st_mode) && size_t(st.st_size) > max_bytes) {
    ::close(fd);
    if (error)
      *error = "cannot read " + path + ": it holds " + size_text(size_t(st.st_size)) + ", more than the " +
               size_text(max_bytes) + " an input of this kind may hold";
    return std::nullopt;
  }
  auto bytes =
      read_all(fd, path, error, max_bytes, text, S_ISREG(st.st_mode) ? size_t(st.st_size) : 0, fifo, fifo_wait);
  ::close(fd);
  return bytes;
}

}  // namespace dw::sim
