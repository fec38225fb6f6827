// `dwatch session SCENARIO --protocol`: the session as a machine interface for other programs
// (docs/design.md §7a, docs/session.md "The protocol"), as a debugger's MI is for an IDE. One
// request a line on standard input, each answered by one JSON line on standard output, flushed:
//
//   request  := COMMAND_LINE | {"id": ID, "cmd": COMMAND_LINE}
//   answer   := {"id": ID, ...the command's answer...}
//             | {"id": ID, "error": {"line": N, "col": C, "message": M, "text": CARET_TEXT}}
//             | {"id": ID, "progress": {"done": D, "total": T}}     (long commands, 10 a second at most)
//
// Requests run one at a time, in order; `cancel` (or {"cmd": "cancel"}) is read at once and stops
// the oldest request not yet answered: the one under way, between steps (its answer then says
// "cancelled": true), or one still waiting, which is then answered "cancelled before it ran"
// without running. A mistake or a failure is an
// answer, never the end of the session; the end of the input ends it (exit 0), as does a signal
// (exit 128 + its number, once the command under way has stopped and answered).
#pragma once

#include <ostream>

#include "shell/interrupts.h"
#include "shell/shell.h"

namespace dw::shell {

// A request line longer than this is answered with an error and skipped.
inline constexpr size_t kMaxRequestBytes = size_t{1} << 20;

int run_protocol(Shell& shell, int in_fd, std::ostream& out, Interrupts* interrupts);

}  // namespace dw::shell
