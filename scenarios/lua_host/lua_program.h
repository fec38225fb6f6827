// Host programs written by users in Lua 5.4 (docs/design.md §11): `[[program]] script = "x.lua"` plus the
// script's parameters. The script declares `program = { vars = {...}, params = {...} }` and
// defines `step(m)` (and optionally `init(m)`); `m` is the module's side of the host-program API
// (sim/host_program.h): m.id, m.step, m:get, m:set, m:neighbors, m:inbox, m:send, m:broadcast,
// m:random, m:param.
//
// Sandboxed (scenarios/lua_host/lua_sandbox.h): libraries bounded in time, an instruction budget per call,
// a memory cap per Lua state and a deadline, none of which a script can catch. A module's state
// lives only in its variables: once loaded, a script
// may not write a global, a table reached from one, or a local declared outside the function
// running. One Lua state per thread that steps modules, never per module, and a fresh one for each
// call run again counted (see LuaState::run).
#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "scenarios/lua_host/lua_sandbox.h"
#include "scenarios/table_reader.h"
#include "sim/host_program.h"

namespace dw::scenarios {

// Parameter values a scenario gives a script, by name.
using ParamValues = std::vector<std::pair<std::string, int64_t>>;

// Builds the program of the script `display` (as messages name it) with the source `text` and the
// parameters of its [[program]] table, each of which the script must declare. nullptr when it does
// not compile or declare itself properly, or a parameter is wrong: the reason is in `why`
// (`display:LINE: message` for the script's own mistakes), or reported at the parameter's key.
// The values the table gave go to `given`, to load the script again with them.
std::unique_ptr<const sim::HostProgram> make_lua_program(const std::string& display, const std::string& text,
                                                         TableReader& params, std::string& why,
                                                         const LuaLimits& limits = {}, ParamValues* given = nullptr);
// The same with the values given before (a script loaded again after a change): each must still
// be declared.
std::unique_ptr<const sim::HostProgram> make_lua_program(const std::string& display, const std::string& text,
                                                         const ParamValues& given, std::string& why,
                                                         const LuaLimits& limits = {});

}  // namespace dw::scenarios
