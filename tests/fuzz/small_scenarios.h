// The shipped scenarios the session's fuzz targets run on (session_fuzz, protocol_fuzz), each
// on a few modules and with a short end, so that one input stays in the milliseconds.
#pragma once

#include <string_view>

namespace dw::fuzz {

// The session cases' scenarios (as `# scenario:` names them; the first is the protocol's). Their paths are taken as in
// scenarios/, so that the Lua scripts are found (and `reload` reads them again from there; nothing writes them).
struct FuzzScenario {
  std::string_view name;  // as a session case's `# scenario:` names it
  const char* toml;
};
inline constexpr FuzzScenario kScenarios[] = {
    {"token_ring.toml", R"toml(name = "token_ring"
steps = 24
[lattice]
kind = "ring"
size = [8]
[[program]]
name = "token_ring"
duplicate_at = 12
[[watch]]
name = "token_from_nowhere"
text = '''modules(a x b); neighbor(x b) and (x.token = 1) and (((a.last.token = 1) and (b.last.token = 1)) or
  ((a.last.token = 0) and (b.last.token = 0)))'''
algorithm = "centralized"
action = "pause"
)toml"},
    {"token_ring_correct.toml", R"toml(name = "token_ring_correct"
steps = 24
[lattice]
kind = "ring"
size = [8]
[[program]]
name = "token_ring"
[[watch]]
name = "token_from_nowhere"
text = '''modules(a x b); neighbor(x b) and (x.token = 1) and (((a.last.token = 1) and (b.last.token = 1)) or
  ((a.last.token = 0) and (b.last.token = 0)))'''
algorithm = "centralized"
action = "pause"
[[event]]
at = 9
module = 3
set = { _keep = 1 }
[[event]]
at = 20
module = 5
remove = true
)toml"},
    {"leader_election.toml", R"toml(name = "leader_election"
steps = 24
[lattice]
kind = "hex2d"
size = [4, 3]
[[program]]
name = "leader_election"
bug = true
[[watch]]
name = "two_leaders"
text = "modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)"
algorithm = "distributed"
action = "pause"
)toml"},
    {"gradient_ldp.toml", R"toml(name = "gradient_ldp"
steps = 16
[lattice]
kind = "square2d"
size = [3, 3]
[[program]]
script = "lua/ldp_idle.lua"
root = 4
[[watch]]
name = "gradient"
text = "modules(a b); a.dist > b.dist + 1 then set a.dist = b.dist + 1"
algorithm = "centralized"
action = "count"
)toml"},
    {"token_ring_fault.toml", R"toml(name = "token_ring_fault"
steps = 24
[lattice]
kind = "ring"
size = [6]
[[program]]
script = "lua/token_hop.lua"
timeout = 8
[[watch]]
name = "drop"
text = "modules(a); a.pos = 3 and a.token = 1 then set a.token = 0"
algorithm = "centralized"
action = "log"
[[watch]]
name = "lost"
text = '''modules(a x b);
neighbor(x a) and neighbor(x b) and x.last.last.token = 1 and x.token = 0 and a.token = 0 and b.token = 0'''
algorithm = "centralized"
action = "pause"
)toml"},
    {"lua/token_ring.toml", R"toml(name = "token_ring_lua"
steps = 24
[lattice]
kind = "ring"
size = [6]
[[program]]
script = "lua/token_ring.lua"
duplicate_at = 12
[[watch]]
name = "token_from_nowhere"
text = '''modules(a x b); neighbor(x b) and (x.token = 1) and (((a.last.token = 1) and (b.last.token = 1)) or
  ((a.last.token = 0) and (b.last.token = 0)))'''
algorithm = "centralized"
action = "pause"
)toml"},
};

}  // namespace dw::fuzz
