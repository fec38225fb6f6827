#include "sim/output_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <streambuf>
#include <vector>

namespace dw::sim {

// A stream buffer over a file descriptor that remembers the first write error (errno), so that
// the message can say why ("No space left on device"), which std::ofstream cannot.
class OutputFile::FdBuffer final : public std::streambuf {
 public:
  FdBuffer(int fd, bool owns) : fd_(fd), owns_(owns), buffer_(size_t{1} << 16) {
    setp(buffer_.data(), buffer_.data() + buffer_.size());
  }
  ~FdBuffer() override { close(); }

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
        error_ = errno;
      } else {
        p += n;
        left -= static_cast<size_t>(n);
      }
    }
    setp(buffer_.data(), buffer_.data() + buffer_.size());
    return error_ == 0;
  }

  int fd_;
  bool owns_;
  int error_ = 0;
  std::vector<char> buffer_;
};

OutputFile::OutputFile(std::string path, std::string temporary, int fd, bool owns_fd)
    : path_(std::move(path)),
      temporary_(std::move(temporary)),
      buffer_(std::make_unique<FdBuffer>(fd, owns_fd)),
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

std::unique_ptr<OutputFile> OutputFile::open(const std::string& path, std::string* error) {
  const auto fail = [&](int code) {
    if (error) *error = "cannot write " + path + ": " + std::strerror(code);
    return nullptr;
  };
  if (path == "-") return std::unique_ptr<OutputFile>(new OutputFile(path, "", STDOUT_FILENO, false));
  if (path.empty()) return fail(ENOENT);
  struct stat st {};
  const std::string target = resolved_path(path);  // a symlink's file is replaced, not the link
  mode_t mode = 0;
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) return fail(EISDIR);
    if (!S_ISREG(st.st_mode)) {
      // A device, a FIFO or a socket: written in place, and never created, truncated or removed.
      const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
      if (fd < 0) return fail(errno);
      return std::unique_ptr<OutputFile>(new OutputFile(path, "", fd, true));
    }
    if (::access(path.c_str(), W_OK) != 0) return fail(errno);
    mode = st.st_mode & 07777;
  } else if (errno != ENOENT) {
    return fail(errno);
  } else {
    const mode_t mask = ::umask(0);
    ::umask(mask);
    mode = 0666 & ~mask;
  }
  const std::filesystem::path at(target);
  const std::filesystem::path dir = at.has_parent_path() ? at.parent_path() : std::filesystem::path(".");
  std::string temporary = (dir / ("." + at.filename().string() + ".dwatch-XXXXXX")).string();
  const int fd = ::mkstemp(temporary.data());
  if (fd < 0) return fail(errno);
  ::fchmod(fd, mode);
  ::fcntl(fd, F_SETFD, FD_CLOEXEC);
  auto out = std::unique_ptr<OutputFile>(new OutputFile(path, temporary, fd, true));
  out->target_ = target;
  return out;
}

std::string OutputFile::commit() {
  if (committed_) return {};
  stream_.flush();
  const int code = buffer_->close();
  if (code != 0) return "writing " + path_ + " failed: " + std::strerror(code);
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
