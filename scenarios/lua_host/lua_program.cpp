#include "scenarios/lua_host/lua_program.h"

#include "scenarios/lua_host/lua_state.h"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>

namespace dw::scenarios {
namespace {

class LuaProgram final : public sim::HostProgram {
 public:
  LuaProgram(std::string display, std::string text, Declared declared, LuaLimits limits)
      : display_(std::move(display)), text_(std::move(text)), declared_(std::move(declared)), limits_(limits) {}

  std::string_view name() const override { return display_; }
  std::vector<sim::VariableSpec> variables() const override {
    std::vector<sim::VariableSpec> out;
    for (const std::string& v : declared_.vars) out.push_back({v, 0});
    return out;
  }
  void step(sim::ModuleContext& m) const override {
    auto& s = static_cast<LuaState&>(*m.scratch());
    if (!s.error().empty()) {
      m.fail("at step " + std::to_string(m.step()) + ": " + s.error());
      return;
    }
    if (m.step() == 0 && declared_.has_init) s.run(m, true);
    s.run(m, false, m.step() == 0 && declared_.has_init);
  }
  // A stepping thread's own Lua state, declared from what the script declared at load.
  std::unique_ptr<sim::ProgramScratch> make_scratch() const override {
    auto s = std::make_unique<LuaState>(display_, text_, limits_);
    if (s->error().empty()) s->prepare(declared_);
    return s;
  }

 private:
  std::string display_, text_;
  Declared declared_;
  LuaLimits limits_;
};

}  // namespace

namespace {

// What the script declares, checked by loading it once; nothing, with the reason in `why`.
std::optional<Declared> declared_by(const std::string& display, const std::string& text, std::string& why,
                                    const LuaLimits& limits) {
  LuaState probe(display, text, limits);
  Declared declared;
  if (!probe.error().empty() || !probe.declare(declared) || !probe.prepare(declared)) {
    why = probe.error();
    return std::nullopt;
  }
  return declared;
}

}  // namespace

std::unique_ptr<const sim::HostProgram> make_lua_program(const std::string& display, const std::string& text,
                                                         TableReader& params, std::string& why, const LuaLimits& limits,
                                                         ParamValues* given) {
  std::optional<Declared> declared = declared_by(display, text, why, limits);
  if (!declared) return nullptr;
  bool ok = true;
  for (auto& [name, value] : declared->params)
    if (params.has(name)) {
      const auto v = params.integer(name, INT64_MIN, INT64_MAX);
      if (v) value = *v;
      else ok = false;
      if (v && given) given->emplace_back(name, *v);
    }
  if (!ok) return nullptr;
  return std::make_unique<LuaProgram>(display, text, std::move(*declared), limits);
}

std::unique_ptr<const sim::HostProgram> make_lua_program(const std::string& display, const std::string& text,
                                                         const ParamValues& given, std::string& why,
                                                         const LuaLimits& limits) {
  std::optional<Declared> declared = declared_by(display, text, why, limits);
  if (!declared) return nullptr;
  for (const auto& param : given) {
    auto it = std::find_if(declared->params.begin(), declared->params.end(),
                           [&](const auto& p) { return p.first == param.first; });
    if (it == declared->params.end()) {
      why =
          display + ": the scenario sets '" + param.first + "', which the script no longer declares in program.params";
      return nullptr;
    }
    it->second = param.second;
  }
  return std::make_unique<LuaProgram>(display, text, std::move(*declared), limits);
}

}  // namespace dw::scenarios
