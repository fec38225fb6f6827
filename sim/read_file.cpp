#include "sim/read_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace dw::sim {
namespace {

std::string reason(const std::string& path, int code) { return "cannot read " + path + ": " + std::strerror(code); }

}  // namespace

std::string check_readable(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return reason(path, errno);
  if (S_ISDIR(st.st_mode)) return reason(path, EISDIR);
  if (::access(path.c_str(), R_OK) != 0) return reason(path, errno);
  return {};
}

std::optional<std::string> read_file(const std::string& path, std::string* error) {
  const auto fail = [&](int code) {
    if (error) *error = reason(path, code);
    return std::nullopt;
  };
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return fail(errno);
  struct stat st {};
  if (::fstat(fd, &st) != 0 || S_ISDIR(st.st_mode)) {
    const int code = S_ISDIR(st.st_mode) ? EISDIR : errno;
    ::close(fd);
    return fail(code);
  }
  std::string text;
  if (S_ISREG(st.st_mode)) text.reserve(static_cast<size_t>(st.st_size));
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR) continue;
      const int code = errno;
      ::close(fd);
      return fail(code);
    }
    text.append(buffer, static_cast<size_t>(n));
  }
  ::close(fd);
  return text;
}

}  // namespace dw::sim
