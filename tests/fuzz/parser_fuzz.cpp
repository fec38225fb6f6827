// libFuzzer target for the watchpoint parser: any input must give a tree or diagnostics, never a
// crash, a hang or a sanitizer report. Build with -DDWATCH_FUZZ=ON and clang (see README).
#include <cstddef>
#include <cstdint>
#include <string>

#include "watch/ast.h"
#include "watch/parser.h"
#include "watch/watchpoint.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  auto r = dw::watch::compile_watchpoint("fuzz", dw::watch::SourceText("fuzz", text));
  if (auto* w = std::get_if<dw::watch::Watchpoint>(&r)) {
    // The normal form of a valid watchpoint is itself valid and stable.
    const std::string normal = dw::watch::to_string(w->ast);
    auto again = dw::watch::parse(dw::watch::SourceText("normal", normal));
    if (!again.ok() || dw::watch::to_string(again.ast) != normal) __builtin_trap();
  } else {
    (void)std::get<dw::watch::CompileError>(r).format();
  }
  return 0;
}
