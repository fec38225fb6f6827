// Output files that never destroy anything. A regular file (or a new one) is written to a
// temporary file beside it and renamed into place only when complete, so a failed write leaves
// the old file as it was and no temporary behind. The temporary has no name until then (Linux's
// O_TMPFILE, linked in at commit), so that a process killed mid-write -- a signal, the OOM
// killer -- leaves nothing either; on a file system without O_TMPFILE it is a named
// `.NAME.dwatch-XXXXXX`, removed by the destructor. Anything else -- a device, a FIFO,
// /dev/stdout, "-" for standard output -- is written in place and never removed or truncated
// away on failure, and opened without blocking: a FIFO's reader, and room to write, are waited
// for at most a bound (kOutputWait). Errors name the path and the operating system's reason.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <ostream>
#include <span>
#include <stop_token>
#include <string>

namespace dw::sim {

// How long an output written in place may keep a write waiting: for a FIFO's reader to open it,
// or for a reader to take what was written.
inline constexpr std::chrono::milliseconds kOutputWait{10'000};

class OutputFile {
 public:
  // Opens `path` for writing ("-": standard output). Nothing, with `error` set to
  // "cannot write PATH: REASON", when it cannot be written (a FIFO no process opens to read
  // within `wait`). A stop requested on `stop` (a signal) ends the wait for a reader, or for room
  // to write, at once.
  static std::unique_ptr<OutputFile> open(const std::string& path, std::string* error,
                                          std::chrono::milliseconds wait = kOutputWait, std::stop_token stop = {});
  ~OutputFile();  // without a successful commit(), the temporary is removed; the target is untouched
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  std::ostream& stream() { return stream_; }
  const std::string& path() const { return path_; }
  // Flushes what was written and puts it in place. Empty, or "writing PATH failed: REASON".
  std::string commit();

 private:
  class FdBuffer;
  OutputFile(std::string path, std::string temporary, int fd, bool owns_fd, std::chrono::milliseconds wait,
             std::stop_token stop);
  std::string link_unnamed(const std::string& directory);
  std::string reason(int code) const;  // why a write failed, from its errno

  std::string path_;       // as the user named it
  std::string temporary_;  // a named temporary, renamed over target_ at commit; empty: unnamed or in place
  std::chrono::milliseconds wait_;
  bool unnamed_ = false;  // an O_TMPFILE temporary, given a name at commit
  std::string target_;    // where the temporary goes (a symlink's target, resolved)
  std::unique_ptr<FdBuffer> buffer_;
  std::ostream stream_;
  bool committed_ = false;
};

// `path` with every symbolic link followed, even one whose target does not exist yet (which is
// where a write through the link lands), made absolute and normal.
std::string resolved_path(const std::string& path);

// Writes `bytes` to `path` through an OutputFile. Empty, or the error.
std::string write_file(const std::string& path, std::span<const uint8_t> bytes);

}  // namespace dw::sim
