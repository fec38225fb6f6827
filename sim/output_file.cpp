#include "sim/output_file.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <streambuf>
#include <thread>
#include <vector>

namespace dw::sim {

// A stream buffer over a file descriptor that remembers the first write error (errno), so that
// the message can say why ("No space left on device"), which std::ofstream cannot.
// A descriptor opened without blocking (a FIFO, a device) waits for room at most `wait` without
// progress, then fails with ETIMEDOUT: a reader that stopped reading blocked write() for ever.
class OutputFile::FdBuffer final : public std::streambuf {
 public:
  FdBuffer(int fd, bool owns, std::chrono::milliseconds wait, std::stop_token stop)
      : fd_(fd), owns_(owns), wait_(wait), stop_(std::move(stop)), buffer_(size_t{1} << 16) {
    setp(buffer_.data(), buffer_.data() + buffer_.size());
  }
  ~FdBuffer() override { close(); }

  // Writes out what is buffered; the first error seen, or 0.
  int flush() {
    drain();
    return error_;
  }
  int fd() const { return fd_; }
  // Flushes and closes; the first error seen, or 0.
  int close() {
    drain();
    if (owns_ && fd_ >= 0 && ::close(fd_) != 0 && error_ == 0) error_ = errno;
    fd_ = -1;
    return error_;
  }

 protected:
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  bool drain() {
    const char* p = pbase();
    size_t left = static_cast<size_t>(pptr() - pbase());
    while (left > 0 && error_ == 0 && fd_ >= 0) {
      const ssize_t n = ::write(fd_, p, left);
      if (n < 0) {
        if (errno == EINTR) continue;
        if (errno == EAGAIN && wait_for_room()) continue;
        error_ = errno;
      } else {
        p += n;
        left -= static_cast<size_t>(n);
      }
    }
    setp(buffer_.data(), buffer_.data() + buffer_.size());
    return error_ == 0;
  }
  // Whether the descriptor took room to write within the wait; errno ETIMEDOUT when not, and
  // ECANCELED when a stop was requested meanwhile (looked at every 50 ms).
  bool wait_for_room() {
    const auto until = std::chrono::steady_clock::now() + wait_;
    for (;;) {
      if (stop_.stop_requested()) {
        errno = ECANCELED;
        return false;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now());
      if (left.count() <= 0) {
        errno = ETIMEDOUT;
        return false;
      }
      pollfd p{fd_, POLLOUT, 0};
      const int ready = ::poll(&p, 1, static_cast<int>(std::min<int64_t>(left.count(), 50)));
      if (ready > 0) return true;  // room, or an error the next write reports
      if (ready < 0 && errno != EINTR) return false;
    }
  }

  int fd_;
  bool owns_;
  std::chrono::milliseconds wait_;
  std::stop_token stop_;
  int error_ = 0;
  std::vector<char> buffer_;
};

OutputFile::OutputFile(std::string path, std::string temporary, int fd, bool owns_fd, std::chrono::milliseconds wait,
                       std::stop_token stop)
    : path_(std::move(path)),
      temporary_(std::move(temporary)),
      wait_(wait),
      buffer_(std::make_unique<FdBuffer>(fd, owns_fd, wait, std::move(stop))),
      stream_(buffer_.get()) {}

OutputFile::~OutputFile() {
  buffer_->close();
  if (!committed_ && !temporary_.empty()) ::unlink(temporary_.c_str());
}

std::string resolved_path(const std::string& path) {
  std::error_code ec;
  std::filesystem::path p = std::filesystem::absolute(path, ec);
  for (int hops = 0; hops < 40; ++hops) {  // as the kernel's limit on links followed
    const std::filesystem::path real = std::filesystem::weakly_canonical(p, ec);
    if (ec) return p.lexically_normal().string();
    if (!std::filesystem::is_symlink(real, ec)) return real.string();
    // A dangling link: weakly_canonical stops at it; follow it by hand.
    p = real.parent_path() / std::filesystem::read_symlink(real, ec);
    if (ec) return real.string();
  }
  return p.lexically_normal().string();
}

std::string OutputFile::reason(int code) const {
  if (code == ETIMEDOUT)
    return "nothing read what was written for " + std::to_string(wait_.count()) +
           " ms (a FIFO or a pipe whose reader stopped)";
  if (code == ECANCELED) return "cancelled while it waited for room to write";
  return std::strerror(code);
}

namespace {

// A FIFO with no reader blocked open() for ever, and no signal ended it: opened without blocking,
// its reader is waited for at most `wait`, a look every 20 ms, or until a stop is requested
// (errno ECANCELED).
int open_in_place(const std::string& path, std::chrono::milliseconds wait, const std::stop_token& stop) {
  const auto until = std::chrono::steady_clock::now() + wait;
  for (;;) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd >= 0 || (errno != ENXIO && errno != EINTR) || std::chrono::steady_clock::now() >= until) return fd;
    if (stop.stop_requested()) {
      errno = ECANCELED;
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

}  // namespace

std::unique_ptr<OutputFile> OutputFile::open(const std::string& path, std::string* error,
                                             std::chrono::milliseconds wait, std::stop_token stop) {
  const auto fail = [&](int code) {
    if (error) *error = "cannot write " + path + ": " + std::strerror(code);
    return nullptr;
  };
  if (path == "-") return std::unique_ptr<OutputFile>(new OutputFile(path, "", STDOUT_FILENO, false, wait, stop));
  if (path.empty()) return fail(ENOENT);
  struct stat st {};
  const std::string target = resolved_path(path);  // a symlink's file is replaced, not the link
  mode_t mode = 0;
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) return fail(EISDIR);
    if (!S_ISREG(st.st_mode)) {
      // A device, a FIFO or a socket: written in place, and never created, truncated or removed.
      const int fd = open_in_place(path, wait, stop);
      if (fd < 0 && (errno == ENXIO || errno == ECANCELED)) {
        if (error)
          *error = "cannot write " + path +
                   (errno == ECANCELED
                        ? std::string(": cancelled while it waited for a process to read this FIFO")
                        : ": no process opened this FIFO to read it within " + std::to_string(wait.count()) + " ms");
        return nullptr;
      }
      if (fd < 0) return fail(errno);
      return std::unique_ptr<OutputFile>(new OutputFile(path, "", fd, true, wait, stop));
    }
    if (::access(path.c_str(), W_OK) != 0) return fail(errno);
    mode = st.st_mode & 07777;
  } else if (errno != ENOENT) {
    return fail(errno);
  } else {
    // A new file: its directory must exist as the kernel walks the path, not as the path reads
    // once normalized (in "nosuch/../x" the kernel stops at "nosuch", while the target resolves
    // to ./x, which may be an input).
    const std::filesystem::path given(path);
    const std::string parent = given.has_parent_path() ? given.parent_path().string() : ".";
    struct stat dir {};
    if (::stat(parent.c_str(), &dir) != 0) return fail(errno);
    if (!S_ISDIR(dir.st_mode)) return fail(ENOTDIR);
    const mode_t mask = ::umask(0);
    ::umask(mask);
    mode = 0666 & ~mask;
  }
  const std::filesystem::path at(target);
  const std::filesystem::path dir = at.has_parent_path() ? at.parent_path() : std::filesystem::path(".");
  // An unnamed temporary when the file system has them and /proc can name it at commit.
  if (::access("/proc/self/fd", X_OK) == 0) {
    const int fd = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, mode);
    if (fd >= 0) {
      ::fchmod(fd, mode);
      auto out = std::unique_ptr<OutputFile>(new OutputFile(path, "", fd, true, wait, stop));
      out->unnamed_ = true;
      out->target_ = target;
      return out;
    }
    // EOPNOTSUPP (no O_TMPFILE here), EISDIR (a kernel without it): a named temporary below;
    // anything else (no permission, no such directory) is the answer.
    if (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL) return fail(errno);
  }
  std::string temporary = (dir / ("." + at.filename().string() + ".dwatch-XXXXXX")).string();
  const int fd = ::mkstemp(temporary.data());
  if (fd < 0) return fail(errno);
  ::fchmod(fd, mode);
  ::fcntl(fd, F_SETFD, FD_CLOEXEC);
  auto out = std::unique_ptr<OutputFile>(new OutputFile(path, temporary, fd, true, wait, stop));
  out->target_ = target;
  return out;
}

// Gives the unnamed temporary a name beside the target (linkat through /proc, which needs no
// privilege, unlike AT_EMPTY_PATH): the caller renames it over the target. Empty, or the errno.
std::string OutputFile::link_unnamed(const std::string& directory) {
  const std::string from = "/proc/self/fd/" + std::to_string(buffer_->fd());
  const std::string base =
      (std::filesystem::path(directory) /
       ("." + std::filesystem::path(target_).filename().string() + ".dwatch-" + std::to_string(::getpid()) + "-"))
          .string();
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string name = base + std::to_string(attempt);
    if (::linkat(AT_FDCWD, from.c_str(), AT_FDCWD, name.c_str(), AT_SYMLINK_FOLLOW) == 0) {
      temporary_ = std::move(name);
      return {};
    }
    if (errno != EEXIST) break;
  }
  return std::strerror(errno);
}

std::string OutputFile::commit() {
  if (committed_) return {};
  stream_.flush();
  if (unnamed_) {
    if (const int code = buffer_->flush(); code != 0) return "writing " + path_ + " failed: " + reason(code);
    const std::filesystem::path at(target_);
    if (std::string error = link_unnamed(at.has_parent_path() ? at.parent_path().string() : "."); !error.empty())
      return "writing " + path_ + " failed: " + error;
    unnamed_ = false;
  }
  const int code = buffer_->close();
  if (code != 0) return "writing " + path_ + " failed: " + reason(code);
  if (!temporary_.empty() && ::rename(temporary_.c_str(), target_.c_str()) != 0)
    return "writing " + path_ + " failed: " + std::strerror(errno);
  committed_ = true;
  return {};
}

std::string write_file(const std::string& path, std::span<const uint8_t> bytes) {
  std::string error;
  auto out = OutputFile::open(path, &error);
  if (!out) return error;
  out->stream().write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return out->commit();
}

}  // namespace dw::sim
