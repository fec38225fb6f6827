// What dwatch writes to a terminal shows every byte a user's input put there as text, never as a
// control sequence: a scenario's watchpoint named "\u001b[2J", a Lua error(), a trace's header
// or a command-line word can hold control characters, and echoed raw they would clear the
// screen, move the cursor or retitle the window. Every message passes through std::cout and
// std::cerr; on a terminal their buffers are replaced by one that shows C0 controls (but tab,
// newline and carriage return), DEL and the C1 controls U+0080..U+009F (UTF-8 C2 80..C2 9F, which
// terminals also act on) as '?', one per byte. Output to a pipe or a file is left as written.
#pragma once

#include <streambuf>

namespace dw::app {

class TerminalFilter final : public std::streambuf {
 public:
  explicit TerminalFilter(std::streambuf* out) : out_(out) {}

 protected:
  int_type overflow(int_type c) override;
  std::streamsize xsputn(const char* s, std::streamsize n) override;
  int sync() override;

 private:
  bool put(char c);
  std::streambuf* out_;
  bool after_c2_ = false;  // the last byte was 0xC2: a C1 control may follow
};

// Filters std::cout and std::cerr where they are terminals, for as long as it lives.
class TerminalOutput {
 public:
  TerminalOutput();
  ~TerminalOutput();
  TerminalOutput(const TerminalOutput&) = delete;
  TerminalOutput& operator=(const TerminalOutput&) = delete;

 private:
  TerminalFilter out_, err_;
  std::streambuf* old_out_ = nullptr;
  std::streambuf* old_err_ = nullptr;
};

}  // namespace dw::app
