// libFuzzer target for the scenario loader: any TOML text, [physics], props and watchpoints
// included, must give a Model and a World or diagnostics, never a crash, a hang or a sanitizer
// report. Lattices are capped at 4,096 modules, a stated budget, so that an input of a few bytes
// asking for a million modules does not measure the allocator.
#include <cstddef>
#include <cstdint>
#include <string>
#include <variant>

#include "scenarios/scenario.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dw::scenarios::ScenarioOverrides overrides;
  overrides.max_modules = 4096;
  auto loaded =
      dw::scenarios::load_scenario_text("fuzz.toml", std::string(reinterpret_cast<const char*>(data), size), overrides);
  if (auto* errors = std::get_if<std::string>(&loaded)) {
    // Every diagnostic names the file and a line and column.
    if (errors->empty() || errors->rfind("fuzz.toml:", 0) != 0) __builtin_trap();
  } else if (std::get<dw::scenarios::Scenario>(loaded).model == nullptr) {
    __builtin_trap();
  }
  return 0;
}
