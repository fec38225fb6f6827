// `why` over a trace recorded with its messages (docs/design.md §7b, docs/files.md): the same
// window of history a session records (sim/causal_history.h), read from the trace's lines, so a
// log of real robots with their messages gets the same answers as the run that made it.
#pragma once

#include <cstdint>
#include <string>
#include <variant>

#include "sim/causal_history.h"
#include "sim/trace.h"
#include "sim/why.h"

namespace dw::sim {

// The origin of the value of variable `var` (the trace's index) of dense module m at step t: the
// latest step w <= t at which it differs from step w - 1 (or m had no line then, or w = 0).
int64_t trace_origin(const Trace& trace, uint32_t m, uint32_t var, int64_t t);

// Steps [first, last] of the trace as a window of history: every module's variables (0 where a
// line lacks one, and before step 0), presence, neighbours and the messages read. Nothing is
// written from outside in a trace. Why not, when a frame would not fit.
std::variant<CausalHistory, std::string> trace_window(const Trace& trace, int64_t first, int64_t last);

// The cone of §7b of variable `variable` of the module with id `module` at step t, to `depth`
// (narrow or not), from a trace recorded with its messages; or why not (no messages, no such
// module, variable or step, or no line of the module then).
std::variant<Cone, std::string> why_in_trace(const Trace& trace, uint64_t module, const std::string& variable,
                                             int64_t t, int depth, bool narrow);

}  // namespace dw::sim
