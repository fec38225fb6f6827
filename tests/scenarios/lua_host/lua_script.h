// A scenario of modules in a line running a script a test writes next to it (the LuaScript
// fixture), for the tests of host programs in Lua (tests/scenarios/lua_host/).
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <variant>

#include "scenarios/scenario.h"
#include "sim/session.h"

namespace dw::scenarios::test {

// A scenario of `n` modules in a line running `script` (written next to it), with `params`.
class LuaScript : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("dwatch_lua_" + std::to_string(::getpid()) + "_" +
                                                     ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::variant<Scenario, std::string> load(const std::string& script, const std::string& params = "", int n = 4) {
    std::ofstream(dir_ / "x.lua") << script;
    const std::string text =
        "[lattice]\nkind = \"line\"\nsize = [" + std::to_string(n) + "]\n[[program]]\nscript = \"x.lua\"\n" + params;
    return load_scenario_text((dir_ / "s.toml").string(), text);
  }
  // The error that stops a run of `steps` steps, or "" when it runs through.
  std::string run_error(const std::string& script, int64_t steps = 5) {
    auto loaded = load(script);
    if (auto* e = std::get_if<std::string>(&loaded)) return "load: " + *e;
    Scenario& s = std::get<Scenario>(loaded);
    sim::Session run(*s.model, *s.world, {.threads = 1});
    try {
      run.run_until(steps);
    } catch (const sim::ProgramError& e) {
      return e.what();
    }
    return "";
  }
  std::string script_path() const { return "x.lua"; }  // as the scenario names it

  std::filesystem::path dir_;
};

// The declaration most tests' scripts start with: one variable, one parameter.
inline const std::string kHeader = "program = { vars = { \"v\" }, params = { k = 3 } }\n";

}  // namespace dw::scenarios::test
