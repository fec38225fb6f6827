// libFuzzer target for the trace reader: any text must give a Trace or errors naming a line, never
// a crash, a hang or a sanitizer report; a Trace's frames are then made for every step.
#include <cstddef>
#include <cstdint>
#include <string>
#include <variant>

#include "sim/trace.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto read = dw::sim::read_trace_text("fuzz.jsonl", std::string(reinterpret_cast<const char*>(data), size));
  if (auto* errors = std::get_if<std::vector<dw::sim::TraceError>>(&read)) {
    if (errors->empty()) __builtin_trap();
    for (const auto& e : *errors)
      if (e.format().rfind("fuzz.jsonl", 0) != 0) __builtin_trap();
    return 0;
  }
  const dw::sim::Trace& trace = std::get<dw::sim::Trace>(read);
  auto made = dw::sim::FrameReader::make(trace, std::nullopt, 64.0 * (1 << 20));
  if (auto* frames = std::get_if<dw::sim::FrameReader>(&made)) {
    uint64_t present = 0;
    // Steps run to the largest t; a few thousand are enough to exercise the frames.
    for (int64_t t = 0; t < trace.step_count() && t < 4096; ++t)
      for (uint8_t p : frames->frame(t).present) present += p;
    if (trace.step_count() <= 4096 && present != trace.line_count()) __builtin_trap();  // a frame per line
  }
  return 0;
}
