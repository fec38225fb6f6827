-- 2-hop leader election (the paper's Fig. 2 setting), the Lua twin of
-- scenarios/leader_election.cpp: the same variables, messages and random draw, so the same state
-- hashes and matches. Leaders end up at least three hops apart.
--
-- Each module draws a unique priority at step 0. Every step it broadcasts its status, its
-- priority, the best priority among the undecided modules it knows within one hop (itself
-- included), and whether a leader is within one hop; from its neighbours' messages it sees its
-- 2-hop neighbourhood one step late. An undecided module that hears of a leader within two hops
-- becomes a follower; one whose priority beats every undecided module within two hops (from step
-- 2 on) becomes a leader.
--
-- bug = 1 compares only 1-hop neighbours and only listens to 1-hop leaders: the classic mistake
-- that makes the paper's Fig. 2 violation, two leaders two hops apart.
program = {
  vars = { "isLeader", "_status", "_priority" },
  params = { bug = 0 },
}

local UNDECIDED, LEADER, FOLLOWER = 0, 1, 2

function step(m)
  local priority = m:get("_priority")
  if m.step == 0 then
    -- Unique: random high bits (m:random(0) draws 64 bits), the module id in the low 24.
    priority = ((m:random(0) >> 25) << 24) | (m.id & 0xFFFFFF)
    m:set("_priority", priority)
  end
  local status = m:get("_status")

  -- The neighbourhood as the inbox tells it (the neighbours' state at t - 1).
  local leader_1hop, leader_2hop = false, false
  local best_neighbor, best_2hop = -1, -1
  for _, msg in ipairs(m:inbox()) do
    local status_of, priority_of, best_of, leader_of = msg.data[1], msg.data[2], msg.data[3], msg.data[4]
    if status_of == LEADER then leader_1hop = true end
    if status_of == UNDECIDED then best_neighbor = math.max(best_neighbor, priority_of) end
    if leader_of ~= 0 then leader_2hop = true end
    best_2hop = math.max(best_2hop, best_of)
  end

  local bug = m:param("bug") ~= 0
  if status == UNDECIDED then
    local covered = leader_1hop or (not bug and leader_2hop)
    local rival = bug and best_neighbor or math.max(best_neighbor, best_2hop)
    local ready = bug and 1 or 2  -- the step from which the compared priorities have arrived
    if covered then
      status = FOLLOWER
    elseif m.step >= ready and priority >= rival then  -- rival may be us, relayed back
      status = LEADER
    end
  end
  m:set("_status", status)
  m:set("isLeader", status == LEADER and 1 or 0)
  -- What the neighbours learn: the new status, the best undecided priority within one hop, and
  -- whether a leader is within one hop.
  local best_1hop = math.max(status == UNDECIDED and priority or -1, best_neighbor)
  m:broadcast({ status, priority, best_1hop, (leader_1hop or status == LEADER) and 1 or 0 })
end
