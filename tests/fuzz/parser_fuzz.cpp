// libFuzzer target for the watchpoint parser: any input must give a tree or diagnostics, never a
// crash, a hang or a sanitizer report. A valid watchpoint is also evaluated, by both detectors,
// over three steps of a small ensemble whose values reach int64's ends (docs/design.md §4b: never a wrap,
// never a trap). Build with -DDWATCH_FUZZ=ON and clang (see CONTRIBUTING.md).
#include <cstddef>
#include <cstdint>
#include <string>

#include <vector>

#include "watch/ast.h"
#include "watch/make_detector.h"
#include "watch/parser.h"
#include "watch/watchpoint.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  auto r = dw::watch::compile_watchpoint("fuzz", dw::watch::SourceText("fuzz", text));
  if (auto* w = std::get_if<dw::watch::Watchpoint>(&r)) {
    // The normal form of a valid watchpoint is itself valid and stable.
    const std::string normal = dw::watch::to_string(w->ast);
    auto again = dw::watch::parse(dw::watch::SourceText("normal", normal));
    // Known limit: the parentheses the normal form puts around each comparison can take an input
    // within a level or two of the nesting limit (256) past it; such a normal form is refused
    // for its depth alone, and nothing else may fail.
    const bool too_deep = !again.ok() && again.diagnostics.size() == 1 &&
                          again.diagnostics[0].message.find("nested too deeply") != std::string::npos;
    if ((!again.ok() && !too_deep) || (again.ok() && dw::watch::to_string(again.ast) != normal)) __builtin_trap();
    // Four modules on a path 0-1-2-3 (module 3 absent at step 1), every variable given a value
    // from the input's bytes or one of int64's ends.
    namespace watch = dw::watch;
    if (w->program.slot_count() > 4) return 0;
    // A window that reads neighbours or two slots is written out over its k + 1 shifts, so its cost
    // is linear in k by design (docs/language.md, Cost): evaluated only while that stays small,
    // as a long one would measure the definition's cost, not find a fault.
    if (w->ast.nodes.size() > 4000) return 0;
    watch::Universe u{{0, 1, 2, 3}, w->program.variables};
    const uint32_t vc = static_cast<uint32_t>(u.variables.size());
    const int64_t ends[] = {INT64_MIN, INT64_MAX, -1, 0, 1, 2, INT64_MIN + 1, 3};
    std::vector<int64_t> values(4 * vc);
    for (size_t i = 0; i < values.size(); ++i) values[i] = ends[(i < size ? data[i] : i) % 8];
    std::vector<uint8_t> has(values.size(), 1);
    const std::vector<uint32_t> begin = {0, 1, 3, 5, 6}, nbrs = {1, 0, 2, 1, 3, 2};
    for (auto a : {watch::Algorithm::Centralized, watch::Algorithm::Distributed}) {
      watch::DetectorOptions o;
      o.live_budget = 100000;
      auto d = watch::make_detector(a, *w, u, o, [](int64_t, auto, auto) {});
      for (int64_t t = 0; t < 3; ++t) {
        const std::vector<uint8_t> present = {1, 1, 1, static_cast<uint8_t>(t != 1)};
        watch::Frame f;
        f.step = t;
        f.present = present;
        f.values = values;
        f.has_value = has;
        f.nbr_begin = begin;
        f.nbrs = nbrs;
        f.variable_count = vc;
        d->observe(f);
      }
      d->finish();
    }
  } else {
    (void)std::get<dw::watch::CompileError>(r).format();
  }
  return 0;
}
