// Reading an input whole, with the reason when it cannot be read ("Is a directory" included: on
// Linux a folder opens as a file and reads as empty, which would be reported as a parse error).
//
// Every input has a size limit, checked against a file's size before reading it, and kept while
// reading a pipe or a device (which has no size): `dwatch run /dev/zero` is an error, not a
// process growing without end. Text inputs hold no NUL byte: a binary file is refused at its
// first one, without being read whole. A text input's UTF-8 byte-order mark, which some editors
// write first, is dropped.
#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace dw::sim {

// A scenario, a session script, a watchpoint file, a Lua script (docs/errors.md).
inline constexpr size_t kMaxTextInput = size_t(8) << 20;
// How long an input that is a FIFO may take to be written whole (from its opening to its end).
inline constexpr std::chrono::milliseconds kFifoWriterWait{10'000};

// The file's bytes, or nothing with `error` set to "cannot read PATH: REASON".
// A FIFO is read for at most `fifo_wait`.
std::optional<std::string> read_file(const std::string& path, std::string* error, size_t max_bytes = kMaxTextInput,
                                     bool text = true, std::chrono::milliseconds fifo_wait = kFifoWriterWait);
// The same for an open stream (standard input), named `name` in the reason.
std::optional<std::string> read_stream(int fd, const std::string& name, std::string* error,
                                       size_t max_bytes = kMaxTextInput, bool text = true);
// The same bytes as read, in blocks of at most 64 MiB, for a caller that joins them into a buffer
// of its own (a trace's padded text): a large input is then held once, not twice.
struct ReadBlocks {
  std::vector<std::string> blocks;
  size_t size = 0;
};
// A FIFO is read for at most `fifo_wait`.
std::optional<ReadBlocks> read_file_blocks(const std::string& path, std::string* error, size_t max_bytes,
                                           bool text = true, std::chrono::milliseconds fifo_wait = kFifoWriterWait);
// Empty when `path` names a readable file that is not a directory, else "cannot read PATH: REASON".
std::string check_readable(const std::string& path);

// "8 MiB", "3.0 GiB": a size for messages.
std::string size_text(size_t bytes);
// What the machine's memory can still hold (MemAvailable), or 0 when unknown.
size_t available_memory();

}  // namespace dw::sim
