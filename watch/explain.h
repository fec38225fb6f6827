// What a watchpoint means to the detectors (`dwatch check`, and beside the window's editor):
// its normal form, slots, E+, each variable's offsets and span, what each slot reads, how
// neighbor() culls, and the PatternMatcher's size.
#pragma once

#include <ostream>

#include "watch/watchpoint.h"

namespace dw::watch {

void explain_watchpoint(const watch::Watchpoint& w, std::ostream& out);

}  // namespace dw::watch
