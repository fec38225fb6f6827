#include "app/cli/terminal_filter.h"

#include <unistd.h>

#include <iostream>

namespace dw::app {

bool TerminalFilter::put(char c) {
  const auto u = static_cast<unsigned char>(c);
  if (after_c2_) {
    after_c2_ = false;
    // A C1 control: both its bytes shown as '?' (the 0xC2 was held back for this).
    if (u >= 0x80 && u < 0xA0) return out_->sputc('?') != traits_type::eof() && out_->sputc('?') != traits_type::eof();
    if (out_->sputc(char(0xC2)) == traits_type::eof()) return false;
  }
  if (u == 0xC2) {
    after_c2_ = true;
    return true;
  }
  const bool control = (u < 0x20 && c != '\t' && c != '\n' && c != '\r') || u == 0x7F;
  return out_->sputc(control ? '?' : c) != traits_type::eof();
}

TerminalFilter::int_type TerminalFilter::overflow(int_type c) {
  if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
  return put(traits_type::to_char_type(c)) ? c : traits_type::eof();
}

std::streamsize TerminalFilter::xsputn(const char* s, std::streamsize n) {
  for (std::streamsize i = 0; i < n; ++i)
    if (!put(s[i])) return i;
  return n;
}

int TerminalFilter::sync() {
  // A 0xC2 held back at a flush is written: what follows cannot make it a control any more
  // than a message ending there would.
  if (after_c2_) {
    after_c2_ = false;
    if (out_->sputc(char(0xC2)) == traits_type::eof()) return -1;
  }
  return out_->pubsync();
}

TerminalOutput::TerminalOutput() : out_(std::cout.rdbuf()), err_(std::cerr.rdbuf()) {
  if (isatty(STDOUT_FILENO)) old_out_ = std::cout.rdbuf(&out_);
  if (isatty(STDERR_FILENO)) old_err_ = std::cerr.rdbuf(&err_);
}

TerminalOutput::~TerminalOutput() {
  if (old_out_) {
    std::cout.flush();
    std::cout.rdbuf(old_out_);
  }
  if (old_err_) {
    std::cerr.flush();
    std::cerr.rdbuf(old_err_);
  }
}

}  // namespace dw::app
