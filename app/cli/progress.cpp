#include "app/cli/progress.h"

#include <unistd.h>
#include <cstdio>

namespace dw::app {

ProgressBar::ProgressBar(std::string label, int64_t total, bool enabled)
    : label_(std::move(label)),
      total_(total),
      enabled_(enabled && isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {
  // Written with stdio, beside the filtered streams (app/cli/terminal_filter.h): the label, a
  // scenario's name, is shown without its control characters here.
  for (char& c : label_)
    if ((static_cast<unsigned char>(c) < 0x20) || c == 0x7F) c = '?';
}

void ProgressBar::update(int64_t done) {
  if (!enabled_ || total_ <= 0) return;
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (elapsed < 1.0 || now - last_ < std::chrono::milliseconds(100)) return;
  last_ = now;
  shown_ = true;
  constexpr int kWidth = 30;
  const double share = double(done) / double(total_);
  const int filled = static_cast<int>(share * kWidth);
  std::string bar(static_cast<size_t>(filled), '=');
  if (filled < kWidth) bar += '>';
  bar.resize(kWidth, ' ');
  const double left = share > 0 ? elapsed / share - elapsed : 0;
  std::fprintf(stderr, "\r%s [%s] %lld/%lld steps  %.1f s, %.0f s left ", label_.c_str(), bar.c_str(),
               static_cast<long long>(done), static_cast<long long>(total_), elapsed, left);
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (!shown_) return;
  shown_ = false;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
}

}  // namespace dw::app
